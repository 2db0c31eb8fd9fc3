// Encodes what PX4 sends to a simulator with node-mavlink and prints the frames as hex, one
// per line: a HEARTBEAT, a COMMAND_LONG and a HIL_ACTUATOR_CONTROLS with the values given:
//   node encode.cjs <time_usec> <mode> <flags> <control 0> ... <control 15>
// Used by physics_mujoco/test/mavlink_node_test.cc.
'use strict';
const { MavLinkProtocolV2, minimal, common } = require('node-mavlink');

const args = process.argv.slice(2);
if (args.length !== 19) {
  process.stderr.write('usage: node encode.cjs <time_usec> <mode> <flags> <16 controls>\n');
  process.exit(2);
}
const protocol = new MavLinkProtocolV2(1, 1);  // PX4's default MAV_SYS_ID 1, autopilot component

const heartbeat = new minimal.Heartbeat();
heartbeat.type = 2;        // MAV_TYPE_QUADROTOR
heartbeat.autopilot = 12;  // MAV_AUTOPILOT_PX4
heartbeat.baseMode = 0;
heartbeat.customMode = 0;
heartbeat.systemStatus = 3;
heartbeat.mavlinkVersion = 3;

const command = new common.CommandLong();
command.command = 511;  // MAV_CMD_SET_MESSAGE_INTERVAL, as PX4 asks for HIL_STATE_QUATERNION
command._param1 = 115;
command._param2 = 5000;

const controls = new common.HilActuatorControls();
controls.timeUsec = BigInt(args[0]);
controls.mode = Number(args[1]);
controls.flags = BigInt(args[2]);
controls.controls = args.slice(3).map(Number);

[heartbeat, command, controls].forEach((message, seq) => {
  process.stdout.write(protocol.serialize(message, seq).toString('hex') + '\n');
});
