// A GCS on the host for sitlnet run's built-in relay (`--gcs udp:127.0.0.1:PORT`), with
// node-mavlink, a MAVLink implementation sitlnet did not write:
//   node host_gcs.cjs PORT SECONDS [JUNK]
// Binds 127.0.0.1:PORT (0: any free port) and prints "LISTENING on UDP port N". With PORT
// "tcp:N" it connects to 127.0.0.1:N instead (`--gcs tcp-listen:N`) and prints "CONNECTED to TCP
// port N"; JUNK is then written once the connection is up. Prints
// "HEARD sysid=S msgid=M name=NAME wall_ms=W compid=C seq=Q" for each message (W: ms since it
// bound; a HEARTBEAT adds " base_mode=B custom_mode=M"; a message with a time_boot_ms adds
// " boot_ms=T", the vehicle's clock), and on the
// first HEARTBEAT of each system id sends that system a COMMAND_LONG (MAV_CMD_REQUEST_MESSAGE of
// AUTOPILOT_VERSION, target_system = S) to whoever sent it, printing "SENT sysid=S". With JUNK,
// each datagram it gets is first answered with JUNK datagrams of bytes that begin no frame.
// After SECONDS (0: never), at SIGTERM, or when the relay closes a TCP connection, it prints
// "COUNTS valid=.. invalid=.. unknown=.." and exits 0.
// Used by tests/integration/gcs_relay_test.cc.
'use strict';
const dgram = require('dgram');
const { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common } =
    require('node-mavlink');

const { heardLine } = require('./heard_line.cjs');
const tcpPrefix = 'tcp:';
const tcp = (process.argv[2] || '').startsWith(tcpPrefix);
const [port, seconds, junk] =
    [tcp ? process.argv[2].slice(tcpPrefix.length) : process.argv[2], ...process.argv.slice(3)]
        .map(Number);
if (Number.isNaN(port) || Number.isNaN(seconds)) {
  process.stderr.write('usage: node host_gcs.cjs PORT SECONDS [JUNK]\n');
  process.exit(2);
}
const protocol = new MavLinkProtocolV2(255, 190);  // A GCS's usual system and component ids.
const net = require('net');
const socket = tcp ? null : dgram.createSocket('udp4');
let stream = null;  // The TCP connection, with tcp:N.
const splitter = new MavLinkPacketSplitter();
const commanded = new Set();
let sender = null;
let boundAt = 0;
let seq = 0;
splitter.pipe(new MavLinkPacketParser()).on('data', (packet) => {
  const h = packet.header;
  let extra = '';
  if (h.msgid === 0) {
    const heartbeat = packet.protocol.data(packet.payload, minimal.Heartbeat);
    extra = ` base_mode=${heartbeat.baseMode} custom_mode=${heartbeat.customMode}`;
  }
  process.stdout.write(heardLine(packet, Date.now() - boundAt, { sequence: true, extra }));
  if (h.msgid !== 0 || commanded.has(h.sysid)) return;
  commanded.add(h.sysid);
  const command = new common.CommandLong();
  command.targetSystem = h.sysid;
  command.targetComponent = 1;
  command.command = 512;  // MAV_CMD_REQUEST_MESSAGE
  command._param1 = 148;  // AUTOPILOT_VERSION
  const bytes = protocol.serialize(command, seq++ & 255);
  if (stream) {
    stream.write(bytes);
  } else {
    socket.send(bytes, sender.port, sender.address);
  }
  process.stdout.write(`SENT sysid=${h.sysid}\n`);
});
function finish() {
  process.stdout.write(`COUNTS valid=${splitter.validPackages} ` +
                       `invalid=${splitter.invalidPackages} ` +
                       `unknown=${splitter.unknownPackagesCount}\n`);
  process.exit(0);
}
process.on('SIGTERM', finish);
function started() {
  boundAt = Date.now();
  if (seconds > 0) setTimeout(finish, seconds * 1000);
}
if (tcp) {
  stream = net.connect(port, '127.0.0.1', () => {
    process.stdout.write(`CONNECTED to TCP port ${port}\n`);
    for (let i = 0; i < (junk || 0); ++i) stream.write(Buffer.from([0x00, 0x01, 0x02, 0x03]));
    started();
  });
  stream.on('data', (bytes) => splitter.write(bytes));
  stream.on('close', finish);  // The run ended: the relay closed the connection.
  stream.on('error', (error) => {
    // A relay that ends its run closes the connection; when the kernel still held bytes for
    // either side, that close is a reset. The run's end, not a fault: the counts follow.
    if (error.code === 'ECONNRESET' || error.code === 'EPIPE') {
      process.stdout.write(`CLOSED ${error.code}\n`);
      finish();
    }
    process.stdout.write(`ERROR ${error.message}\n`);
    process.exit(1);
  });
} else {
  socket.on('message', (datagram, from) => {
    sender = from;
    for (let i = 0; i < (junk || 0); ++i) {
      socket.send(Buffer.from([0x00, 0x01, 0x02, 0x03]), from.port, from.address);
    }
    splitter.write(datagram);
  });
  socket.bind(port, '127.0.0.1', () => {
    process.stdout.write(`LISTENING on UDP port ${socket.address().port}\n`);
    started();
  });
}
