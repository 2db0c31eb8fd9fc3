// Flies PX4 over the simulated radio from a ground station in the lock-step
// (lockstep_station.cjs), the flight of px4_flight_plan.cjs:
//   node fly_px4_lockstep.cjs <altitude_m> <north_m> <east_m>
// PX4 sends to this robot's UDP 14550 (the px4 manifest's `--gcs <this robot's wlan0
// address>`); the station answers the address of PX4's first datagram. A HEARTBEAT at each whole
// second of the virtual clock (the states' sim_time_ns), where fly_px4.cjs uses the wall clock.
// Prints "GCS ready" once bound, then the flight's lines.
// Used by tests/integration/autopilot_reproducibility_test.cc.
'use strict';
const { px4Flight } = require('./px4_flight_plan.cjs');
const { lockstepStation } = require('./lockstep_station.cjs');

const args = process.argv.slice(2).map(Number);
if (args.length !== 3 || args.some(Number.isNaN)) {
  process.stderr.write('usage: node fly_px4_lockstep.cjs <altitude_m> <north_m> <east_m>\n');
  process.exit(2);
}
const [altitudeM, northM, eastM] = args;
const NS_PER_S = 1e9;

let socket = null;
let vehicle = null;  // { address, port } of PX4's first datagram: where its link listens
const flight = px4Flight({
  altitudeM, northM, eastM,
  write: (bytes) => { if (vehicle !== null) socket.send(bytes, vehicle.port, vehicle.address); },
  say: (line) => process.stdout.write(line + '\n'),
  onDone: () => {},  // keeps answering the lock-step until the run ends
});
let lastSecond = -1;
socket = lockstepStation({
  port: 14550,
  onDatagram: (datagram, from) => {
    if (vehicle === null) vehicle = { address: from.address, port: from.port };
    flight.splitter.write(datagram);
  },
  onState: (simTimeNs) => {
    const second = Math.floor(simTimeNs / NS_PER_S);
    if (second !== lastSecond) flight.heartbeat();
    lastSecond = second;
  },
});
