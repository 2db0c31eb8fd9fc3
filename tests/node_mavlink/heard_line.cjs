// The "HEARD ..." line a GCS script prints for each MAVLink message it decodes, so that
// tests/integration/run_test_util.cc reads host_gcs.cjs's and fleet_gcs.cjs's alike:
//   HEARD sysid=S msgid=M name=NAME wall_ms=W[ compid=C seq=Q][EXTRA][ boot_ms=T]
// W: ms since the GCS bound its port; T: the message's time_boot_ms, the vehicle's clock, for a
// message that has one.
'use strict';
const { minimal, common } = require('node-mavlink');

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };

// `packet` from node-mavlink's MavLinkPacketParser; `extra` is put before boot_ms.
function heardLine(packet, wallMs, { sequence = false, extra = '' } = {}) {
  const h = packet.header;
  const clazz = REGISTRY[h.msgid];
  const timed = clazz && clazz.FIELDS.some((field) => field.source === 'time_boot_ms');
  const boot = timed ? ` boot_ms=${packet.protocol.data(packet.payload, clazz).timeBootMs}` : '';
  const numbers = sequence ? ` compid=${h.compid} seq=${h.seq}` : '';
  return `HEARD sysid=${h.sysid} msgid=${h.msgid} name=${clazz ? clazz.MSG_NAME : 'UNKNOWN'} ` +
         `wall_ms=${wallMs}${numbers}${extra}${boot}\n`;
}

module.exports = { heardLine, REGISTRY };
