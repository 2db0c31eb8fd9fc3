// A GCS on the host that flies a fleet of PX4 and ArduCopter vehicles through a ground station
// robot, as docs/howto-autopilot-fleet.md flies the shipped scenarios: `sitlnet run --gcs
// udp:127.0.0.1:PORT` relays the station's MAVLink to this UDP port. The fleet's flight and the
// lines it prints: fleet_flight_plan.cjs.
//   node fleet_gcs.cjs PORT ALT_M HOLD_S ROUTE VEHICLE...
// PORT 0: any free port. Prints "LISTENING on UDP port N" once bound. Every vehicle's datagrams
// come from the relay, and the commands go back there: the relay sends a command to the vehicle
// its target system names (to every vehicle when it names none). Sends each PX4 a HEARTBEAT each
// wall second, as fly_px4.cjs does. Until the first HEARTBEAT of each system id, flown or not,
// it prints each of its messages as host_gcs.cjs does: "HEARD sysid=S msgid=M name=NAME
// wall_ms=W" (W: ms since it bound), with " boot_ms=T" for a message with a time_boot_ms. Exits 0 once every vehicle disarmed after landing. Its
// commands reach the vehicles when the host schedules it: a lockstep run with it is not
// reproducible.
// Used by tests/integration/shipped_fleet_scenarios_test.cc.
'use strict';
const dgram = require('dgram');
const { MavLinkPacketSplitter, MavLinkPacketParser } = require('node-mavlink');
const { heardLine } = require('./heard_line.cjs');
const { fleetFlight } = require('./fleet_flight_plan.cjs');

const [port, ...fleetArgs] = process.argv.slice(2);
if (Number.isNaN(Number(port))) {
  process.stderr.write('fleet_gcs.cjs: PORT is not a number\n');
  process.exit(2);
}
const socket = dgram.createSocket('udp4');
let heartbeats = null;
let closed = false;  // once every vehicle is done; a plan may still answer a report after that
const fleet = fleetFlight({
  script: 'fleet_gcs.cjs',
  usage: 'usage: node fleet_gcs.cjs PORT ALT_M HOLD_S NORTH,EAST/... px4|arducopter:SYSID...\n',
  args: fleetArgs,
  send: (bytes, address, toPort) => { if (!closed) socket.send(bytes, toPort, address); },
  onAllDone: () => {
    clearInterval(heartbeats);
    closed = true;
    socket.close();
  },
});
// Each system's messages up to its first HEARTBEAT, parsed by node-mavlink (a datagram holds
// whole frames).
let boundAt = 0;
const heard = new Set();
const splitter = new MavLinkPacketSplitter();
splitter.pipe(new MavLinkPacketParser()).on('data', (packet) => {
  const h = packet.header;
  if (heard.has(h.sysid)) return;
  if (h.msgid === 0) heard.add(h.sysid);
  process.stdout.write(heardLine(packet, Date.now() - boundAt));
});
socket.on('message', (datagram, from) => {
  splitter.write(datagram);
  fleet.take(datagram, from);
});
socket.on('error', (error) => {
  process.stdout.write(`ERROR ${error.message}\n`);
  process.exit(1);
});
socket.bind(Number(port), () => {
  boundAt = Date.now();
  process.stdout.write(`LISTENING on UDP port ${socket.address().port}\n`);
  heartbeats = setInterval(fleet.heartbeatPx4s, 1000);
});
