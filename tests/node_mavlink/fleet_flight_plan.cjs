// The flights of a fleet of PX4 and ArduCopter vehicles, apart from how MAVLink travels: one plan
// per vehicle, told apart by MAVLink system id (the vehicle's --sysid), each its own autopilot's
// plan (px4_flight_plan.cjs, guided_flight_plan.cjs) over the same route from its own home, so
// the fleet keeps its formation. A fleet's arguments, as its ground stations take them:
//   ALT_M HOLD_S ROUTE VEHICLE...
// ROUTE: waypoints NORTH,EAST (m from home) joined by '/', e.g. 4,0/4,4/0,4/0,0.
// VEHICLE: px4:SYSID or arducopter:SYSID.
// Each plan's lines are printed prefixed with "sys=SYSID ".
// Used by fleet_lockstep.cjs (a station robot of the lock-step) and fleet_gcs.cjs (a GCS on the
// host, through `sitlnet run --gcs`).
'use strict';
const { guidedFlight } = require('./guided_flight_plan.cjs');
const { px4Flight } = require('./px4_flight_plan.cjs');

// The fleet of `args` (ALT_M HOLD_S ROUTE VEHICLE...); on bad arguments prints why and `usage`
// to stderr, prefixed with `script`, and exits 2. send(bytes, address, port) sends a datagram.
// onAllDone() is called once every vehicle disarmed after landing.
// Returns take(datagram, from) for each datagram from a vehicle, heartbeatPx4s() to send each
// PX4 a GCS HEARTBEAT, and status() for a timeout's message.
function fleetFlight({ script, usage, args, send, onAllDone = () => {} }) {
  function fail(why) {
    process.stderr.write(`${script}: ${why}\n${usage}`);
    process.exit(2);
  }
  const [altArg, holdArg, routeArg, ...vehicleArgs] = args;
  const altM = Number(altArg), holdS = Number(holdArg);
  if (Number.isNaN(altM) || Number.isNaN(holdS) || !routeArg || vehicleArgs.length === 0) fail('missing arguments');
  const waypoints = routeArg.split('/').map((point) => {
    const [northM, eastM] = point.split(',').map(Number);
    if (Number.isNaN(northM) || Number.isNaN(eastM)) fail(`bad waypoint '${point}'`);
    return { northM, eastM };
  });

  const vehicles = new Map();  // system id -> { flight, address, port, px4, done }
  const allDone = () => [...vehicles.values()].every((vehicle) => vehicle.done);
  for (const arg of vehicleArgs) {
    const [kind, idText] = arg.split(':');
    const sysid = Number(idText);
    if (!Number.isInteger(sysid) || sysid < 1 || sysid > 254 || vehicles.has(sysid)) fail(`bad system id in '${arg}'`);
    const vehicle = { flight: null, address: null, port: 0, px4: kind === 'px4', done: false };
    const common = {
      waypoints,
      write: (bytes) => { if (vehicle.address !== null) send(bytes, vehicle.address, vehicle.port); },
      say: (line) => process.stdout.write(`sys=${sysid} ${line}\n`),
      onDone: () => {
        vehicle.done = true;
        if (allDone()) onAllDone();
      },
    };
    if (kind === 'px4') {
      vehicle.flight = px4Flight({ altitudeM: altM, ...common });
    } else if (kind === 'arducopter') {
      vehicle.flight = guidedFlight({ altM, holdS, sysid, ...common });
    } else {
      fail(`unknown autopilot '${kind}' in '${arg}'`);
    }
    vehicles.set(sysid, vehicle);
  }

  // The sender's system id in a datagram's first MAVLink frame (v2 at byte 5, v1 at byte 3).
  function systemId(datagram) {
    if (datagram.length > 5 && datagram[0] === 0xfd) return datagram[5];
    if (datagram.length > 3 && datagram[0] === 0xfe) return datagram[3];
    return -1;
  }

  return {
    // A datagram goes to the plan of the system id in its first MAVLink header, and that plan's
    // commands go to the address its first datagram came from.
    take: (datagram, from) => {
      const vehicle = vehicles.get(systemId(datagram));
      if (vehicle === undefined) return;
      if (vehicle.address === null) [vehicle.address, vehicle.port] = [from.address, from.port];
      vehicle.flight.splitter.write(datagram);
    },
    heartbeatPx4s: () => {
      for (const vehicle of vehicles.values()) if (vehicle.px4) vehicle.flight.heartbeat();
    },
    status: () => [...vehicles].map(([sysid, vehicle]) => `sys=${sysid} done=${vehicle.done}`).join(' '),
  };
}

module.exports = { fleetFlight };
