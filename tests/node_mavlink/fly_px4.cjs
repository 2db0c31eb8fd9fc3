// Flies PX4 as a ground station would, over a GCS MAVLink link of PX4's, with messages encoded
// by node-mavlink (the flight, and the lines it prints: px4_flight_plan.cjs): it listens on UDP
// 14550, where PX4's GCS links send (its own on the robot's localhost, from port 18570; the px4
// manifest's `--gcs ADDR` link over wlan0, from 14556), and answers the address PX4's first
// datagram came from, as a GCS does. Prints `LISTENING` once bound.
//   node fly_px4.cjs <altitude_m> <north_m> <east_m> <timeout_s> [estimates]
// Exits 0 once PX4 disarmed after landing, 1 on timeout (wall clock). It sends a HEARTBEAT each
// wall second, and its commands reach PX4 when the host schedules it: a lockstep run with it is
// not reproducible (fly_px4_lockstep.cjs's is closer, docs/autopilots-evidence.md).
// Used by tests/integration/px4_flight_test.cc and autopilot_radio_test.cc.
'use strict';
const dgram = require('dgram');
const { px4Flight } = require('./px4_flight_plan.cjs');

const args = process.argv.slice(2);
if ((args.length !== 4 && args.length !== 5) || (args.length === 5 && args[4] !== 'estimates')) {
  process.stderr.write('usage: node fly_px4.cjs <altitude_m> <north_m> <east_m> <timeout_s> [estimates]\n');
  process.exit(2);
}
const [altitudeM, northM, eastM, timeoutS] = args.slice(0, 4).map(Number);
const estimates = args[4] === 'estimates';  // ODOMETRY and the origin too (px4_flight_plan.cjs)

const GCS_PORT = 14550;  // where PX4's GCS links send before they have heard from anyone

const socket = dgram.createSocket('udp4');
let vehicle = null;  // { address, port } of PX4's first datagram: where its link listens
let heartbeats = null, deadline = null;
function finish(code) {
  clearInterval(heartbeats);
  clearTimeout(deadline);
  socket.close();
  process.exitCode = code;
}
const flight = px4Flight({
  altitudeM, northM, eastM, estimates,
  write: (bytes) => { if (vehicle !== null) socket.send(bytes, vehicle.port, vehicle.address); },
  say: (line) => process.stdout.write(line + '\n'),
  onDone: () => finish(0),
});
socket.on('message', (datagram, from) => {
  if (vehicle === null) vehicle = { address: from.address, port: from.port };
  flight.splitter.write(datagram);
});
socket.bind(GCS_PORT, () => {
  process.stdout.write('LISTENING\n');
  heartbeats = setInterval(flight.heartbeat, 1000);
  deadline = setTimeout(() => {
    process.stdout.write(`TIMEOUT ${flight.status()}\n`);
    finish(1);
  }, timeoutS * 1000);
});
