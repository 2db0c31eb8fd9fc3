// The flight of guided_flight.cjs and guided_flight_lockstep.cjs, apart from how MAVLink travels:
// GUIDED, arm (retried until armed), take off to ALT m, hold HOLD_S s, fly to NORTH,EAST m
// (local NED from home; or to each point of `waypoints` in turn, holding HOLD_S s at each),
// LAND, wait for the disarm. Time is the autopilot's (time_boot_ms):
// the plan never reads a clock of its own, so it works at any speed of the simulation.
// Prints one line per event, with the autopilot's time in seconds:
//   STATUSTEXT t=.. <text> | ARMED t=.. | TAKEOFF_REACHED t=.. | WAYPOINT_REACHED t=.. |
//   (with `waypoints`: WAYPOINT_REACHED t=.. index=.. for each) |
//   LAND t=.. (LAND mode asked) | DISARMED t=.. | POS t=.. rel_alt=.. north=.. east=.. (GLOBAL_POSITION_INT, every report)
'use strict';
const {
  MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common, ardupilotmega,
} = require('node-mavlink');
const { requestDataStream } = require('./request_stream.cjs');

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY, ...ardupilotmega.REGISTRY };
const COPTER_GUIDED = 4;
const COPTER_LAND = 9;
const ARMED_FLAG = 128;  // MAV_MODE_FLAG_SAFETY_ARMED

// Flies one ArduCopter: write(bytes) sends a serialized MAVLink frame to it, say(line) prints,
// onDone() is called once it disarmed after landing. Feed it the autopilot's bytes with
// splitter().write(chunk). `sysid`: the autopilot's MAVLink system id (its --sysid), 1 by
// default; `waypoints`: [{ northM, eastM }, ...], else the one point northM, eastM.
function guidedFlight({ altM, holdS, northM, eastM, waypoints, sysid = 1, write, say, onDone }) {
  const route = waypoints || [{ northM, eastM }];
  let leg = 0;  // the index in `route` of the waypoint flown to
  const protocol = new MavLinkProtocolV2(255, 190);  // A GCS's usual system and component ids.
  let seq = 0;
  function send(message) { write(protocol.serialize(message, seq++ & 255)); }
  function command(id, params) {
    const message = new common.CommandLong();
    message.targetSystem = sysid;
    message.targetComponent = 1;
    message.command = id;
    message.confirmation = 0;
    params.forEach((value, i) => { message[`_param${i + 1}`] = value; });
    send(message);
  }

  // States of the flight; each advances on what the autopilot reports.
  let phase = 'boot';
  let timeS = 0;            // The autopilot's time of its latest report.
  let lastTryS = -10;       // When the current command was last sent.
  let phaseStartS = 0;
  let armed = false;
  let position = null;      // { relAlt, north, east } from GLOBAL_POSITION_INT and LOCAL_POSITION_NED

  function enter(next) { phase = next; phaseStartS = timeS; lastTryS = -10; }
  function due(periodS) {
    if (timeS - lastTryS < periodS) return false;
    lastTryS = timeS;
    return true;
  }

  function step() {
    switch (phase) {
      case 'boot':
        if (due(1)) {
          requestDataStream(send, sysid, 0, 10);  // MAV_DATA_STREAM_ALL
          command(176, [1, COPTER_GUIDED, 0, 0, 0, 0, 0]);  // MAV_CMD_DO_SET_MODE
          command(400, [1, 0, 0, 0, 0, 0, 0]);              // MAV_CMD_COMPONENT_ARM_DISARM
        }
        if (armed) { say(`ARMED t=${timeS.toFixed(3)}`); enter('takeoff'); }
        break;
      case 'takeoff':
        if (due(1) && position && position.relAlt < 0.5) command(22, [0, 0, 0, 0, 0, 0, altM]);
        if (position && position.relAlt >= altM - 0.1) {
          say(`TAKEOFF_REACHED t=${timeS.toFixed(3)}`);
          enter('hold');
        }
        break;
      case 'hold':
        if (timeS - phaseStartS >= holdS) enter('waypoint');
        break;
      case 'waypoint': {
        if (due(1)) {
          const target = new common.SetPositionTargetLocalNed();
          target.timeBootMs = Math.round(timeS * 1000);
          target.targetSystem = sysid;
          target.targetComponent = 1;
          target.coordinateFrame = 1;  // MAV_FRAME_LOCAL_NED
          target.typeMask = 0x0DF8;    // position only
          target.x = route[leg].northM;
          target.y = route[leg].eastM;
          target.z = -altM;
          send(target);
        }
        const off = Math.hypot(position.north - route[leg].northM, position.east - route[leg].eastM);
        if (off < 1) {
          say(`WAYPOINT_REACHED t=${timeS.toFixed(3)}` + (waypoints ? ` index=${leg}` : ''));
          enter('settle');
        }
        break;
      }
      case 'settle':
        if (timeS - phaseStartS < holdS) break;
        if (++leg < route.length) {
          enter('waypoint');
        } else {
          say(`LAND t=${timeS.toFixed(3)}`);
          enter('land');
        }
        break;
      case 'land':
        if (due(1)) command(176, [1, COPTER_LAND, 0, 0, 0, 0, 0]);
        if (!armed) { say(`DISARMED t=${timeS.toFixed(3)}`); enter('done'); onDone(); }
        break;
      default:
        break;
    }
  }

  function take(packet) {
    if (packet.header.sysid !== sysid || packet.header.compid !== 1) return;
    const clazz = REGISTRY[packet.header.msgid];
    if (!clazz) return;
    const data = packet.protocol.data(packet.payload, clazz);
    switch (clazz.MSG_NAME) {
      case 'HEARTBEAT':
        armed = (data.baseMode & ARMED_FLAG) !== 0;
        break;
      case 'SYSTEM_TIME':
        timeS = Math.max(timeS, data.timeBootMs / 1000);
        break;
      case 'STATUSTEXT':
        say(`STATUSTEXT t=${timeS.toFixed(3)} ${data.text.replace(/\0.*$/s, '')}`);
        break;
      case 'GLOBAL_POSITION_INT':
        timeS = Math.max(timeS, data.timeBootMs / 1000);
        position = { ...(position || { north: 0, east: 0 }), relAlt: data.relativeAlt / 1000 };
        say(`POS t=${(data.timeBootMs / 1000).toFixed(3)} rel_alt=${position.relAlt.toFixed(3)} ` +
            `north=${position.north.toFixed(3)} east=${position.east.toFixed(3)}`);
        break;
      case 'LOCAL_POSITION_NED':
        timeS = Math.max(timeS, data.timeBootMs / 1000);
        position = { ...(position || { relAlt: 0 }), north: data.x, east: data.y };
        break;
      default:
        return;
    }
    step();
  }

  const splitter = new MavLinkPacketSplitter();
  splitter.pipe(new MavLinkPacketParser()).on('data', take);
  return { splitter, done: () => phase === 'done' };
}

module.exports = { guidedFlight };
