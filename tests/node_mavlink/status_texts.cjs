// Listens to one ArduCopter as a ground station that never flies it, to hear its own complaints
// (bench/autopilots/real_fleet.sh counts its loop-rate ones: "Main loop slow (..Hz < ..Hz)",
// "Gyro 1 rate ..Hz < loop ratex1.8 ..Hz"). ArduPilot says its failing pre-arm checks only to a
// ground station, when asked: every wall second this sends a HEARTBEAT and
// MAV_CMD_RUN_PREARM_CHECKS (401; ArduPilot's GCS_Common.cpp runs pre_arm_checks(report=true)).
//   node status_texts.cjs HOST PORT SYSID
// HOST PORT: ArduPilot's TCP server (its --serial0, tcp:5760 on the robot's loopback by
// default). Prints "STATUSTEXT t=<its time, s> <text>" per status text; exits when the
// connection closes (the run ended).
'use strict';
const net = require('net');
const {
  MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common,
} = require('node-mavlink');
const { requestDataStream } = require('./request_stream.cjs');

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };
const [host, port, sysidText] = process.argv.slice(2);
if (sysidText === undefined) {
  process.stderr.write('usage: node status_texts.cjs HOST PORT SYSID\n');
  process.exit(2);
}
const sysid = Number(sysidText);
const protocol = new MavLinkProtocolV2(255, 190);  // A GCS's usual system and component ids.
let seq = 0;
let timeS = 0;  // The autopilot's time (SYSTEM_TIME), s.

const socket = net.connect(Number(port), host);
function send(message) { socket.write(protocol.serialize(message, seq++ & 255)); }
function askEverySecond() {
  const heartbeat = new minimal.Heartbeat();
  heartbeat.type = minimal.MavType.GCS;
  heartbeat.autopilot = minimal.MavAutopilot.INVALID;
  send(heartbeat);
  // SYSTEM_TIME (MAV_DATA_STREAM_EXTRA3), for the times printed.
  requestDataStream(send, sysid, 12, 1);
  const checks = new common.CommandLong();
  checks.targetSystem = sysid;
  checks.targetComponent = 1;
  checks.command = 401;  // MAV_CMD_RUN_PREARM_CHECKS
  send(checks);
}
const splitter = new MavLinkPacketSplitter();
socket.pipe(splitter);
splitter.pipe(new MavLinkPacketParser()).on('data', (packet) => {
  if (packet.header.sysid !== sysid) return;
  const clazz = REGISTRY[packet.header.msgid];
  if (!clazz) return;
  const data = packet.protocol.data(packet.payload, clazz);
  if (clazz.MSG_NAME === 'SYSTEM_TIME') timeS = Math.max(timeS, data.timeBootMs / 1000);
  if (clazz.MSG_NAME === 'STATUSTEXT') {
    process.stdout.write(`STATUSTEXT t=${timeS.toFixed(3)} ${data.text.replace(/\0.*$/s, '')}\n`);
  }
});
const timer = setInterval(askEverySecond, 1000);
socket.on('connect', askEverySecond);
socket.on('error', (error) => { process.stderr.write(`status_texts: ${error.message}\n`); });
socket.on('close', () => { clearInterval(timer); process.exit(0); });
