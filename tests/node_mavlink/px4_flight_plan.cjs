// The flight of fly_px4.cjs and fly_px4_lockstep.cjs, apart from how MAVLink travels: waits
// until PX4 says it can arm (SYS_STATUS pre-arm bit), arms, takes off to ALTITUDE_M above home
// (NAV_TAKEOFF; PX4 ends its take-off NAV_MC_ALT_RAD short of the target and holds where it
// ended, so a DO_REPOSITION to the same altitude follows), holds, flies to the point NORTH_M,
// EAST_M from home (DO_REPOSITION; or to each point of `waypoints` in turn), lands (NAV_LAND) and waits for PX4 to disarm. Its time is
// PX4's (time_boot_ms). Prints:
//   EVENT <name> t_ms=..        ARMED, TAKEOFF, HOLD, WAYPOINT, ARRIVED, LAND, DISARMED
//                               (HOLD and ARRIVED: since_ms=.. when the steady state began;
//                               with `waypoints`, WAYPOINT and ARRIVED: index=.. for each)
//   POS t_ms=.. lat=.. lon=.. alt=.. relative_alt=..   every GLOBAL_POSITION_INT (degE7, mm)
//   HOME lat=.. lon=.. alt=..                          where it armed (degE7, mm)
//   ODOM t_us=.. x=.. y=.. z=..     with `estimates` only (a 40 kB/s radio link of PX4's has no
//                                   room for it): every ODOMETRY (asked for at 20 Hz), local
//                                   NED (m) from its origin, stamped with the instant it estimates
//                                   (GLOBAL_POSITION_INT is stamped when ekf2 published it, later
//                                   by ekf2's own lag on a busy host)
//   ORIGIN lat=.. lon=.. alt=..                        the estimator's origin (GPS_GLOBAL_ORIGIN:
//                                                      degE7, mm), asked for once armed
//   TEXT t_ms=.. severity=.. <text>                    every STATUSTEXT
'use strict';
const { MavLinkProtocolV2, MavLinkPacketSplitter, MavLinkPacketParser, minimal, common } =
    require('node-mavlink');

const EARTH_RADIUS_M = 6371000;  // PX4's map projection (lib/geo) uses this sphere
const MAV_CMD = { NAV_LAND: 21, NAV_TAKEOFF: 22, DO_REPOSITION: 192, ARM_DISARM: 400,
                  SET_MESSAGE_INTERVAL: 511, REQUEST_MESSAGE: 512 };
const ODOMETRY_ID = 331, GPS_GLOBAL_ORIGIN_ID = 49;
const ODOMETRY_INTERVAL_US = 50000;  // 20 Hz
const PREARM_CHECK = 0x10000000;  // MAV_SYS_STATUS_PREARM_CHECK
const ARMED = 0x80;  // MAV_MODE_FLAG_SAFETY_ARMED
const AUTO_LOITER = (4 << 16) | (3 << 24);  // PX4 custom mode: main AUTO, sub LOITER

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };

// Flies one PX4: write(bytes) sends a serialized MAVLink frame to it, say(line) prints,
// onDone() is called once it disarmed after landing. Feed it PX4's datagrams with
// splitter.write(datagram); heartbeat() sends a GCS HEARTBEAT. `waypoints`: [{ northM, eastM },
// ...], else the one point northM, eastM.
function px4Flight({ altitudeM, northM, eastM, waypoints, estimates, write, say, onDone }) {
  const route = waypoints || [{ northM, eastM }];
  const legName = (leg) => (waypoints ? ` index=${leg}` : '');
  let leg = 0;  // the index in `route` of the waypoint flown to
  const protocol = new MavLinkProtocolV2(255, 190);  // a GCS: system 255, MAV_COMP_ID_MISSIONPLANNER
  let sequence = 0;
  function send(message) { write(protocol.serialize(message, sequence++ & 0xff)); }

  let target = 1;  // PX4's system id (MAV_SYS_ID), learnt from its HEARTBEAT
  function commandLong(command, params) {
    const m = new common.CommandLong();
    m.targetSystem = target;
    m.targetComponent = 1;
    m.command = command;
    [m._param1, m._param2, m._param3, m._param4, m._param5, m._param6, m._param7] = params;
    send(m);
  }
  // A position command with latitude and longitude in degE7 (COMMAND_LONG's floats would round
  // them to ~0.4 m) and an altitude above mean sea level.
  function commandGlobal(command, latE7, lonE7, altitudeAmslM) {
    const m = new common.CommandInt();
    m.targetSystem = target;
    m.targetComponent = 1;
    m.frame = 0;  // MAV_FRAME_GLOBAL
    m.command = command;
    m.current = 0;
    m.autocontinue = 0;
    m._param1 = -1;  // default speed
    m._param2 = 1;   // MAV_DO_REPOSITION_FLAGS_CHANGE_MODE
    m._param3 = 0;
    m._param4 = NaN;  // keep the heading
    m._param5 = latE7;  // x
    m._param6 = lonE7;  // y
    m._param7 = altitudeAmslM;  // z
    send(m);
  }

  // State from PX4's telemetry.
  let armed = false, customMode = 0, canArm = false;
  let position = null;  // the latest GLOBAL_POSITION_INT
  let home = null;      // the position where it armed
  let phase = 'wait_ready', phaseSinceMs = 0, lastCommandMs = -1e9, steadySinceMs = null;
  let accepted = new Set();  // commands PX4 accepted (COMMAND_ACK) in this phase
  let lastHeartbeatMs = -1e9;  // PX4's time of the latest HEARTBEAT sent on its telemetry
  // ODOMETRY and GPS_GLOBAL_ORIGIN are not in PX4's default GCS streams: asked for each second of
  // PX4's time until they come (the origin once armed: it is set before PX4 can arm).
  let odometrySeen = false, originSeen = false, lastAskMs = -1e9;
  function askForEstimates(tMs) {
    if (!estimates) return;
    if ((odometrySeen && (originSeen || !armed)) || tMs - lastAskMs < 1000) return;
    lastAskMs = tMs;
    if (!odometrySeen) commandLong(MAV_CMD.SET_MESSAGE_INTERVAL, [ODOMETRY_ID, ODOMETRY_INTERVAL_US, 0, 0, 0, 0, 0]);
    if (armed && !originSeen) commandLong(MAV_CMD.REQUEST_MESSAGE, [GPS_GLOBAL_ORIGIN_ID, 0, 0, 0, 0, 0, 0]);
  }

  function enter(next, tMs) {
    phase = next;
    phaseSinceMs = tMs;
    lastCommandMs = -1e9;
    steadySinceMs = null;
    accepted = new Set();
  }
  // True once `condition` has held for `forMs` of PX4's time.
  function steady(condition, tMs, forMs) {
    if (!condition) {
      steadySinceMs = null;
      return false;
    }
    if (steadySinceMs === null) steadySinceMs = tMs;
    return tMs - steadySinceMs >= forMs;
  }
  // A command is sent once per phase, and again each second of PX4's time until PX4 accepts it.
  function due(command, tMs) {
    if (accepted.has(command) || tMs - lastCommandMs < 1000) return false;
    lastCommandMs = tMs;
    return true;
  }
  function targetOf(north, east) {
    const lat = home.lat / 1e7, lon = home.lon / 1e7;
    const dLat = (north / EARTH_RADIUS_M) * 180 / Math.PI;
    const dLon = (east / (EARTH_RADIUS_M * Math.cos(lat * Math.PI / 180))) * 180 / Math.PI;
    return [Math.round((lat + dLat) * 1e7), Math.round((lon + dLon) * 1e7)];
  }
  function horizontalDistanceM(latE7, lonE7) {
    const dNorth = (position.lat - latE7) / 1e7 * Math.PI / 180 * EARTH_RADIUS_M;
    const dEast = (position.lon - lonE7) / 1e7 * Math.PI / 180 * EARTH_RADIUS_M *
        Math.cos(position.lat / 1e7 * Math.PI / 180);
    return Math.hypot(dNorth, dEast);
  }

  function step(tMs) {
    const p = position;
    const relativeM = home ? (p.alt - home.alt) / 1000 : 0;
    const speedM_s = Math.hypot(p.vx, p.vy, p.vz) / 100;
    switch (phase) {
      case 'wait_ready':
        if (canArm && due(MAV_CMD.ARM_DISARM, tMs)) commandLong(MAV_CMD.ARM_DISARM, [1, 0, 0, 0, 0, 0, 0]);
        if (armed) {
          home = { lat: p.lat, lon: p.lon, alt: p.alt };
          say(`HOME lat=${home.lat} lon=${home.lon} alt=${home.alt}`);
          say(`EVENT ARMED t_ms=${tMs}`);
          enter('takeoff', tMs);
          say(`EVENT TAKEOFF t_ms=${tMs}`);
        }
        break;
      case 'takeoff':
        if (due(MAV_CMD.NAV_TAKEOFF, tMs)) {
          commandLong(MAV_CMD.NAV_TAKEOFF, [0, 0, 0, NaN, NaN, NaN, home.alt / 1000 + altitudeM]);
        }
        // PX4's take-off is done: it switched to Hold (AUTO_LOITER) in the air.
        if (customMode === AUTO_LOITER && relativeM > altitudeM / 2) enter('climb', tMs);
        break;
      case 'climb':
        if (due(MAV_CMD.DO_REPOSITION, tMs)) commandGlobal(MAV_CMD.DO_REPOSITION, home.lat, home.lon,
                                    home.alt / 1000 + altitudeM);
        if (steady(Math.abs(relativeM - altitudeM) < 0.1 && speedM_s < 0.1, tMs, 3000)) {
          say(`EVENT HOLD t_ms=${tMs} since_ms=${steadySinceMs}`);
          enter('waypoint', tMs);
          say(`EVENT WAYPOINT t_ms=${tMs}${legName(leg)}`);
        }
        break;
      case 'waypoint': {
        const [lat, lon] = targetOf(route[leg].northM, route[leg].eastM);
        if (due(MAV_CMD.DO_REPOSITION, tMs)) commandGlobal(MAV_CMD.DO_REPOSITION, lat, lon, home.alt / 1000 + altitudeM);
        if (steady(horizontalDistanceM(lat, lon) < 0.2 && speedM_s < 0.1, tMs, 3000)) {
          say(`EVENT ARRIVED t_ms=${tMs} since_ms=${steadySinceMs}${legName(leg)}`);
          if (++leg < route.length) {
            enter('waypoint', tMs);
            say(`EVENT WAYPOINT t_ms=${tMs}${legName(leg)}`);
          } else {
            enter('land', tMs);
            say(`EVENT LAND t_ms=${tMs}`);
          }
        }
        break;
      }
      case 'land':
        if (due(MAV_CMD.NAV_LAND, tMs)) commandLong(MAV_CMD.NAV_LAND, [0, 0, 0, NaN, NaN, NaN, NaN]);
        if (!armed) {
          say(`EVENT DISARMED t_ms=${tMs}`);
          enter('done', tMs);
          onDone();
        }
        break;
    }
  }

  function take(packet) {
    const clazz = REGISTRY[packet.header.msgid];
    if (!clazz) return;
    const m = packet.protocol.data(packet.payload, clazz);
    switch (clazz) {
      case minimal.Heartbeat:
        if (m.autopilot !== 12) return;  // MAV_AUTOPILOT_PX4 only
        target = packet.header.sysid;
        armed = (m.baseMode & ARMED) !== 0;
        customMode = m.customMode;
        break;
      case common.CommandAck:
        say(`ACK t_ms=${position ? position.timeBootMs : 0} command=${m.command} result=${m.result}`);
        if (m.result === 0) accepted.add(m.command);  // MAV_RESULT_ACCEPTED
        break;
      case common.SysStatus:
        canArm = (m.onboardControlSensorsHealth & PREARM_CHECK) !== 0;
        break;
      case common.StatusText:
        say(`TEXT t_ms=${position ? position.timeBootMs : 0} severity=${m.severity} ${m.text}`);
        break;
      case common.Odometry:
        odometrySeen = true;
        say(`ODOM t_us=${m.timeUsec} x=${m.x} y=${m.y} z=${m.z}`);
        break;
      case common.GpsGlobalOrigin:
        originSeen = true;
        say(`ORIGIN lat=${m.latitude} lon=${m.longitude} alt=${m.altitude}`);
        break;
      case common.GlobalPositionInt:
        // PX4 counts the ground station lost after COM_DL_LOSS_T (10 s) of its own clock without
        // a HEARTBEAT: in lockstep that clock runs faster than the wall clock.
        if (m.timeBootMs - lastHeartbeatMs >= 500 || m.timeBootMs < lastHeartbeatMs) {
          heartbeat();
          lastHeartbeatMs = m.timeBootMs;
        }
        position = m;
        askForEstimates(m.timeBootMs);
        say(`POS t_ms=${m.timeBootMs} lat=${m.lat} lon=${m.lon} alt=${m.alt} ` +
            `relative_alt=${m.relativeAlt}`);
        step(m.timeBootMs);
        break;
    }
  }

  function heartbeat() {
    const m = new minimal.Heartbeat();
    m.type = 6;         // MAV_TYPE_GCS
    m.autopilot = 8;    // MAV_AUTOPILOT_INVALID
    m.baseMode = 0;
    m.customMode = 0;
    m.systemStatus = 4;  // MAV_STATE_ACTIVE
    m.mavlinkVersion = 3;
    send(m);
  }

  const splitter = new MavLinkPacketSplitter();
  splitter.pipe(new MavLinkPacketParser()).on('data', take);
  return { splitter, heartbeat, status: () => `phase=${phase} armed=${armed} can_arm=${canArm}` };
}

module.exports = { px4Flight };
