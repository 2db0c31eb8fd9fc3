// A ground station that flies a fleet of PX4 and ArduCopter vehicles over the simulated radio, in
// the lock-step (lockstep_station.cjs); the fleet's flight and the lines it prints:
// fleet_flight_plan.cjs.
//   node fleet_lockstep.cjs ALT_M HOLD_S ROUTE VEHICLE...
// Every vehicle sends to this robot's UDP 14550. Prints "GCS ready" once bound.
// Used by tests/integration/autopilot_fleet_test.cc and bench/autopilot_fleet.sh.
'use strict';
const { fleetFlight } = require('./fleet_flight_plan.cjs');
const { lockstepStation } = require('./lockstep_station.cjs');

const NS_PER_S = 1e9;
let socket = null;
const fleet = fleetFlight({
  script: 'fleet_lockstep.cjs',
  usage: 'usage: node fleet_lockstep.cjs ALT_M HOLD_S NORTH,EAST/... px4|arducopter:SYSID...\n',
  args: process.argv.slice(2),
  send: (bytes, address, port) => socket.send(bytes, port, address),
  // Keeps answering the lock-step until the run ends.
});

let lastSecond = -1;
socket = lockstepStation({
  port: 14550,
  onDatagram: fleet.take,
  onState: (simTimeNs) => {
    // A HEARTBEAT to each PX4 at each whole second of the virtual clock (fly_px4_lockstep.cjs).
    const second = Math.floor(simTimeNs / NS_PER_S);
    if (second !== lastSecond) fleet.heartbeatPx4s();
    lastSecond = second;
  },
});
