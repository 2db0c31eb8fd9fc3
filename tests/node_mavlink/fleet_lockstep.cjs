// A ground station that flies a fleet of PX4 and ArduCopter vehicles over the simulated radio, in
// the lock-step (lockstep_station.cjs): every vehicle flies the same route from its own home, so
// the fleet keeps its formation. Each vehicle flies its own autopilot's plan
// (px4_flight_plan.cjs, guided_flight_plan.cjs) with its waypoints.
//   node fleet_lockstep.cjs ALT_M HOLD_S ROUTE VEHICLE...
// ROUTE: waypoints NORTH,EAST (m from home) joined by '/', e.g. 4,0/4,4/0,4/0,0.
// VEHICLE: px4:SYSID or arducopter:SYSID, the vehicle's MAVLink system id (its --sysid).
// Every vehicle sends to this robot's UDP 14550; a datagram goes to the plan of the system id in
// its first MAVLink header, and that plan's commands go to the address its first datagram came
// from. Prints "GCS ready" once bound, then each plan's lines prefixed with "sys=SYSID ".
// Used by tests/integration/autopilot_fleet_test.cc and bench/autopilot_fleet.sh.
'use strict';
const { guidedFlight } = require('./guided_flight_plan.cjs');
const { px4Flight } = require('./px4_flight_plan.cjs');
const { lockstepStation } = require('./lockstep_station.cjs');

const USAGE = 'usage: node fleet_lockstep.cjs ALT_M HOLD_S NORTH,EAST/... px4|arducopter:SYSID...\n';
function fail(why) {
  process.stderr.write(`fleet_lockstep.cjs: ${why}\n${USAGE}`);
  process.exit(2);
}
const [altArg, holdArg, routeArg, ...vehicleArgs] = process.argv.slice(2);
const altM = Number(altArg), holdS = Number(holdArg);
if (Number.isNaN(altM) || Number.isNaN(holdS) || !routeArg || vehicleArgs.length === 0) fail('missing arguments');
const waypoints = routeArg.split('/').map((point) => {
  const [northM, eastM] = point.split(',').map(Number);
  if (Number.isNaN(northM) || Number.isNaN(eastM)) fail(`bad waypoint '${point}'`);
  return { northM, eastM };
});

const NS_PER_S = 1e9;
let socket = null;
const vehicles = new Map();  // system id -> { flight, address, port, px4 }
for (const arg of vehicleArgs) {
  const [kind, idText] = arg.split(':');
  const sysid = Number(idText);
  if (!Number.isInteger(sysid) || sysid < 1 || sysid > 254 || vehicles.has(sysid)) fail(`bad system id in '${arg}'`);
  const vehicle = { flight: null, address: null, port: 0, px4: kind === 'px4' };
  const common = {
    waypoints,
    write: (bytes) => { if (vehicle.address !== null) socket.send(bytes, vehicle.port, vehicle.address); },
    say: (line) => process.stdout.write(`sys=${sysid} ${line}\n`),
    onDone: () => {},  // keeps answering the lock-step until the run ends
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

let lastSecond = -1;
socket = lockstepStation({
  port: 14550,
  onDatagram: (datagram, from) => {
    const vehicle = vehicles.get(systemId(datagram));
    if (vehicle === undefined) return;
    if (vehicle.address === null) [vehicle.address, vehicle.port] = [from.address, from.port];
    vehicle.flight.splitter.write(datagram);
  },
  onState: (simTimeNs) => {
    // A HEARTBEAT to each PX4 at each whole second of the virtual clock (fly_px4_lockstep.cjs).
    const second = Math.floor(simTimeNs / NS_PER_S);
    if (second !== lastSecond) {
      for (const vehicle of vehicles.values()) if (vehicle.px4) vehicle.flight.heartbeat();
    }
    lastSecond = second;
  },
});
