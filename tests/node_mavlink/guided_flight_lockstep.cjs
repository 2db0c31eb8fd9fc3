// A ground station that flies one ArduCopter over the simulated radio, reproducibly in a
// lockstep run: a robot of the scenario in the lock-step (lockstep_station.cjs), flying
// guided_flight_plan.cjs's flight.
//   node guided_flight_lockstep.cjs ALT_M HOLD_S NORTH_M EAST_M
// Listens on UDP 14550 (the autopilot's `--serial0 udpclient:<this robot's wlan0
// address>:14550`) and answers the sender of the latest MAVLink datagram.
// Prints "GCS ready" once bound, then the flight's lines.
// Used by tests/integration/autopilot_reproducibility_test.cc.
'use strict';
const { guidedFlight } = require('./guided_flight_plan.cjs');
const { lockstepStation } = require('./lockstep_station.cjs');

const args = process.argv.slice(2).map(Number);
if (args.length !== 4 || args.some(Number.isNaN)) {
  process.stderr.write('usage: node guided_flight_lockstep.cjs ALT_M HOLD_S NORTH_M EAST_M\n');
  process.exit(2);
}
const [altM, holdS, northM, eastM] = args;
let autopilot = null;  // { address, port } of the latest MAVLink datagram
let socket = null;
const flight = guidedFlight({
  altM, holdS, northM, eastM,
  write: (bytes) => { if (autopilot) socket.send(bytes, autopilot.port, autopilot.address); },
  say: (line) => process.stdout.write(line + '\n'),
  onDone: () => {},  // keeps answering the lock-step until the run ends
});
socket = lockstepStation({
  port: 14550,
  onDatagram: (datagram, from) => {
    autopilot = { address: from.address, port: from.port };
    flight.splitter.write(datagram);
  },
  onState: () => {},
});
