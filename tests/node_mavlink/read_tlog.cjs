// Reads a telemetry log (QGroundControl's and MAVProxy's .tlog: before each MAVLink frame, a
// big-endian uint64 of microseconds) and checks every frame with node-mavlink:
//   node read_tlog.cjs FILE
// The entries are split by the format's definition (the frame's length from its MAVLink 1 or 2
// header, as MAVProxy's mavutil reads a tlog); node-mavlink then parses the frames alone, end to
// end, so a wrong split shows as invalid frames or a count that differs. Prints one line per
// entry, "ENTRY stamp_us=T sysid=S msgid=M name=NAME [time_boot_ms=B]", then
// "COUNTS entries=N valid=.. invalid=.. unknown=.. trailing=BYTES".
// Used by tests/integration/gcs_relay_test.cc.
'use strict';
const fs = require('fs');
const { Readable } = require('stream');
const { MavLinkPacketSplitter, MavLinkPacketParser, minimal, common } = require('node-mavlink');

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };
const log = fs.readFileSync(process.argv[2]);
const stamps = [];
const frames = [];
let at = 0;
while (at + 8 + 3 <= log.length) {
  const frame = at + 8;
  const magic = log[frame];
  const length = log[frame + 1];
  let bytes = 0;
  if (magic === 0xFE) bytes = 6 + length + 2;
  if (magic === 0xFD) bytes = 10 + length + 2 + ((log[frame + 2] & 1) ? 13 : 0);
  if (bytes === 0 || frame + bytes > log.length) break;
  stamps.push(log.readBigUInt64BE(at));
  frames.push(log.subarray(frame, frame + bytes));
  at = frame + bytes;
}
const splitter = new MavLinkPacketSplitter();
const lines = [];
let index = 0;
Readable.from([Buffer.concat(frames)])
  .pipe(splitter)
  .pipe(new MavLinkPacketParser())
  .on('data', (packet) => {
    const h = packet.header;
    const clazz = REGISTRY[h.msgid];
    let line = `ENTRY stamp_us=${stamps[index++]} sysid=${h.sysid} msgid=${h.msgid} ` +
               `name=${clazz ? clazz.MSG_NAME : 'UNKNOWN'}`;
    if (clazz) {
      const data = packet.protocol.data(packet.payload, clazz);
      if (data.timeBootMs !== undefined) line += ` time_boot_ms=${data.timeBootMs}`;
    }
    lines.push(line);
  })
  .on('end', () => {
    lines.push(`COUNTS entries=${frames.length} valid=${splitter.validPackages} ` +
               `invalid=${splitter.invalidPackages} unknown=${splitter.unknownPackagesCount} ` +
               `trailing=${log.length - at}`);
    process.stdout.write(lines.join('\n') + '\n');
  });
