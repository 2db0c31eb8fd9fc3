// Appends to a pcap file (nanosecond pcap, radiotap link type, as sitlnet's medium.pcap) one
// 802.11 DATA frame from robot ROBOT carrying, in a UDP datagram to port 14550, an ArduCopter
// HEARTBEAT in mode MODE (a name of node-mavlink's CopterMode enum), encoded by node-mavlink.
// The frame starts at TIME_NS of simulated time (radiotap TSFT). Written here, apart from
// sitlnet's pcap writer, for view_browser_test.cc: the page must show the mode from that time.
//   node append_heartbeat.cjs PCAP ROBOT TIME_NS MODE
'use strict';
const fs = require('node:fs');
const { MavLinkProtocolV2, minimal, ardupilotmega } = require('node-mavlink');

const [file, robotText, timeText, modeName] = process.argv.slice(2);
const robot = Number(robotText);
const timeNs = BigInt(timeText);
if (!(modeName in ardupilotmega.CopterMode)) {
  process.stderr.write(`no CopterMode ${modeName}\n`);
  process.exit(2);
}
const heartbeat = new minimal.Heartbeat();
heartbeat.type = minimal.MavType.QUADROTOR;
heartbeat.autopilot = minimal.MavAutopilot.ARDUPILOTMEGA;
heartbeat.baseMode = minimal.MavModeFlag.CUSTOM_MODE_ENABLED;
heartbeat.customMode = ardupilotmega.CopterMode[modeName];
heartbeat.systemStatus = minimal.MavState.ACTIVE;
heartbeat.mavlinkVersion = 3;
const mavlink = new MavLinkProtocolV2(robot + 1, 1).serialize(heartbeat, 0);

const robotMac = Buffer.from([0x02, 0, 0, 0, (robot >> 8) & 0xff, robot & 0xff]);
const udp = Buffer.alloc(8);
udp.writeUInt16BE(14550, 0);
udp.writeUInt16BE(14550, 2);
udp.writeUInt16BE(8 + mavlink.length, 4);
const ip = Buffer.alloc(20);
ip.writeUInt8(0x45, 0);                       // IPv4, 20-byte header
ip.writeUInt16BE(20 + udp.length + mavlink.length, 2);
ip.writeUInt16BE(0x4000, 6);                  // Don't Fragment
ip.writeUInt8(64, 8);                         // TTL
ip.writeUInt8(17, 9);                         // UDP
Buffer.from([10, 0, 0, robot + 1, 10, 0, 0, 255]).copy(ip, 12);
const snap = Buffer.from([0xaa, 0xaa, 0x03, 0, 0, 0, 0x08, 0x00]);  // RFC 1042, IPv4
const wlan = Buffer.concat([
  Buffer.from([0x08, 0x00, 0, 0]),              // DATA, no flags; duration
  Buffer.from([0xff, 0xff, 0xff, 0xff, 0xff, 0xff]), robotMac,
  Buffer.from([0x02, 0, 0, 0, 0, 0]), Buffer.from([0, 0]),  // BSSID, sequence
]);
const radiotap = Buffer.alloc(16);
radiotap.writeUInt16LE(16, 2);                // it_len
radiotap.writeUInt32LE(1, 4);                 // present: TSFT
radiotap.writeBigUInt64LE(timeNs / 1000n, 8); // TSFT, microseconds
const fcs = Buffer.alloc(4);                  // Not checked by the view.
const data = Buffer.concat([radiotap, wlan, snap, ip, udp, mavlink, fcs]);
const header = Buffer.alloc(16);
header.writeUInt32LE(Number(timeNs / 1000000000n), 0);
header.writeUInt32LE(Number(timeNs % 1000000000n), 4);
header.writeUInt32LE(data.length, 8);
header.writeUInt32LE(data.length, 12);
fs.appendFileSync(file, Buffer.concat([header, data]));
