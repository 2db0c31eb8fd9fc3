// A ground station that flies one ArduCopter in GUIDED mode over MAVLink, with node-mavlink
// (the flight, and the lines it prints: guided_flight_plan.cjs).
//   node guided_flight.cjs HOST PORT ALT_M HOLD_S NORTH_M EAST_M
// HOST PORT: ArduPilot's TCP server (its --serial0 tcp:0 on the robot's loopback), or, with
// HOST `udpin`, a UDP port of this node where ArduPilot's --serial0 udpclient:THIS_NODE:PORT
// sends (over the simulated radio; PORT 0: any free port): the script prints `LISTENING on UDP
// port N` once bound and answers the address the vehicle's datagrams come from, as a GCS does.
// Exits 0 after DISARMED, 1 if the connection closes first. Its commands reach the autopilot
// when the host schedules this process, so a lockstep run with it is not reproducible
// (guided_flight_lockstep.cjs is).
// Used by tests/integration/arducopter_flight_test.cc (TCP) and autopilot_radio_test.cc (udpin).
'use strict';
const dgram = require('dgram');
const net = require('net');
const { guidedFlight } = require('./guided_flight_plan.cjs');

const [host, port, altM, holdS, northM, eastM] = process.argv.slice(2);
if (eastM === undefined) {
  process.stderr.write('usage: node guided_flight.cjs HOST PORT ALT_M HOLD_S NORTH_M EAST_M\n');
  process.exit(2);
}
function say(line) { process.stdout.write(line + '\n'); }

// The link to the vehicle: write(bytes), end(); what arrives goes to `splitter`.
function tcpLink(splitter, isDone) {
  const socket = net.connect(Number(port), host);
  socket.pipe(splitter);
  socket.on('error', (error) => { say(`ERROR ${error.message}`); process.exit(1); });
  socket.on('close', () => process.exit(isDone() ? 0 : 1));
  return { write: (bytes) => socket.write(bytes), end: () => socket.end() };
}
function udpLink(splitter) {
  const socket = dgram.createSocket('udp4');
  let vehicle = null;  // { address, port } of the vehicle's first datagram
  socket.on('message', (datagram, from) => {
    if (vehicle === null) vehicle = { address: from.address, port: from.port };
    splitter.write(datagram);
  });
  socket.on('error', (error) => { say(`ERROR ${error.message}`); process.exit(1); });
  socket.bind(Number(port), () => say(`LISTENING on UDP port ${socket.address().port}`));
  return {
    write: (bytes) => { if (vehicle) socket.send(bytes, vehicle.port, vehicle.address); },
    end: () => socket.close(() => process.exit(0)),
  };
}

let link = null;
const flight = guidedFlight({
  altM: Number(altM), holdS: Number(holdS), northM: Number(northM), eastM: Number(eastM),
  write: (bytes) => link.write(bytes),
  say,
  onDone: () => link.end(),
});
link = host === 'udpin' ? udpLink(flight.splitter) : tcpLink(flight.splitter, flight.done);
