// HEARTBEATs of an ArduCopter in each of its modes, encoded by node-mavlink, one per line as
// "<frame hex> <mode name>": the custom_mode and its name both from node-mavlink's CopterMode
// enum (ArduPilot's ardupilotmega.xml, COPTER_MODE). A ground station's HEARTBEAT follows,
// named "-": it reports no autopilot mode. Used by view/test/air_modes_test.cc.
'use strict';
const { MavLinkProtocolV2, minimal, ardupilotmega } = require('node-mavlink');

const copter = new MavLinkProtocolV2(1, 1);  // system 1, autopilot component
let seq = 0;
for (const [name, value] of Object.entries(ardupilotmega.CopterMode)) {
  if (typeof value !== 'number') continue;  // TypeScript enums map both ways
  const heartbeat = new minimal.Heartbeat();
  heartbeat.type = minimal.MavType.QUADROTOR;
  heartbeat.autopilot = minimal.MavAutopilot.ARDUPILOTMEGA;
  heartbeat.baseMode = minimal.MavModeFlag.CUSTOM_MODE_ENABLED;
  heartbeat.customMode = value;
  heartbeat.systemStatus = minimal.MavState.ACTIVE;
  heartbeat.mavlinkVersion = 3;
  process.stdout.write(`${copter.serialize(heartbeat, seq++ & 0xff).toString('hex')} ${name}\n`);
}
const gcs = new minimal.Heartbeat();
gcs.type = minimal.MavType.GCS;
gcs.autopilot = minimal.MavAutopilot.INVALID;
gcs.customMode = 4;
process.stdout.write(`${new MavLinkProtocolV2(255, 190).serialize(gcs, 0).toString('hex')} -\n`);
