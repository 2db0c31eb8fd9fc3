// Decodes MAVLink frames read from stdin with node-mavlink (CRC and CRC_EXTRA checked by its
// splitter) and prints one line per message: "MSG <id> <name> seq=.. sysid=.. compid=..
// <field>=<value> ...", then "COUNTS valid=.. invalid=.. unknown=..". Used by
// physics_mujoco/test/mavlink_node_test.cc.
'use strict';
const { Readable } = require('stream');
const { MavLinkPacketSplitter, MavLinkPacketParser, minimal, common } = require('node-mavlink');

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };

function format(value) {
  if (Array.isArray(value)) return value.map(format).join(',');
  return String(value);  // numbers: shortest round-trip text; bigint: exact
}

const chunks = [];
process.stdin.on('data', (chunk) => chunks.push(chunk));
process.stdin.on('end', () => {
  const splitter = new MavLinkPacketSplitter();
  const lines = [];
  Readable.from([Buffer.concat(chunks)])
    .pipe(splitter)
    .pipe(new MavLinkPacketParser())
    .on('data', (packet) => {
      const clazz = REGISTRY[packet.header.msgid];
      if (!clazz) {
        lines.push(`UNKNOWN ${packet.header.msgid}`);
        return;
      }
      const data = packet.protocol.data(packet.payload, clazz);
      const fields = clazz.FIELDS.map((f) => `${f.source}=${format(data[f.name])}`);
      const h = packet.header;
      lines.push(`MSG ${h.msgid} ${clazz.MSG_NAME} seq=${h.seq} sysid=${h.sysid} ` +
                 `compid=${h.compid} ${fields.join(' ')}`);
    })
    .on('end', () => {
      lines.push(`COUNTS valid=${splitter.validPackages} invalid=${splitter.invalidPackages} ` +
                 `unknown=${splitter.unknownPackagesCount}`);
      process.stdout.write(lines.join('\n') + '\n');
    });
});
