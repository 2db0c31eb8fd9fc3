// A ground station that flies one ArduCopter over the simulated radio, reproducibly in a
// lockstep run: it is a robot of the scenario that takes part in the lock-step through sitlnet's
// native protocol (docs/protocols.md), and the flight is guided_flight_plan.cjs's.
//   node guided_flight_lockstep.cjs ALT_M HOLD_S NORTH_M EAST_M
// Listens on UDP 14550 of all addresses (the autopilot's `--serial0 udpclient:<this robot's
// wlan0 address>:14550`) and answers the sender of the latest MAVLink datagram. Its motors stay
// off: sitlnet sends it a RobotState each step, and it answers with a MotorCommand only after it
// has read every datagram that came before that state, and sent what they called for.
// Why that is reproducible: the medium writes the frames due before a state into this robot's
// TAP before physics sends the state, and one socket takes both, so they queue in that order;
// what this program sends before its MotorCommand enters the medium in the same iteration.
// Prints "GCS ready" once bound, then the flight's lines (guided_flight_plan.cjs).
'use strict';
const dgram = require('dgram');
const { guidedFlight } = require('./guided_flight_plan.cjs');

const args = process.argv.slice(2).map(Number);
const [physicsHost, physicsPort] = (process.env.SITLNET_PHYSICS_ADDR || '').split(':');
if (args.length !== 4 || args.some(Number.isNaN) || !physicsPort) {
  process.stderr.write('usage: SITLNET_PHYSICS_ADDR=HOST:PORT node guided_flight_lockstep.cjs ' +
                       'ALT_M HOLD_S NORTH_M EAST_M\n');
  process.exit(2);
}
const [altM, holdS, northM, eastM] = args;
const GCS_PORT = 14550;

const socket = dgram.createSocket('udp4');
let autopilot = null;  // { address, port } of the latest MAVLink datagram
const flight = guidedFlight({
  altM, holdS, northM, eastM,
  write: (bytes) => { if (autopilot) socket.send(bytes, autopilot.port, autopilot.address); },
  say: (line) => process.stdout.write(line + '\n'),
  onDone: () => {},  // keeps answering the lock-step until the run ends
});

// The protobuf wire format of robot.proto, as far as this program needs it.
function varint(value) {
  const bytes = [];
  for (; value >= 0x80; value = Math.floor(value / 0x80)) bytes.push((value % 0x80) | 0x80);
  bytes.push(value);
  return bytes;
}
// RobotState.step (field 2, varint); null if absent or malformed.
function stateStep(buffer) {
  let at = 0;
  const readVarint = () => {
    let value = 0;
    for (let scale = 1; at < buffer.length; scale *= 0x80) {
      const byte = buffer[at++];
      value += (byte & 0x7f) * scale;
      if (byte < 0x80) return value;
    }
    throw new Error('truncated varint');
  };
  try {
    while (at < buffer.length) {
      const key = readVarint();
      const [field, type] = [Math.floor(key / 8), key % 8];
      if (type === 0) {
        const value = readVarint();
        if (field === 2) return value;
      } else if (type === 1) {
        at += 8;
      } else if (type === 2) {
        at += readVarint();
      } else if (type === 5) {
        at += 4;
      } else {
        return null;
      }
    }
  } catch (error) {
    return null;
  }
  return null;
}
// MotorCommand { step, throttle: [0, 0, 0, 0] }: motors off, this step answered.
function motorsOff(step) {
  return Buffer.from([0x10, ...varint(step), 0x22, 32, ...new Array(32).fill(0)]);
}

socket.on('message', (datagram, from) => {
  if (from.address === physicsHost && from.port === Number(physicsPort)) {
    const step = stateStep(datagram);
    if (step !== null) socket.send(motorsOff(step), from.port, from.address);
    return;
  }
  autopilot = { address: from.address, port: from.port };
  flight.splitter.write(datagram);
});
socket.bind(GCS_PORT, () => {
  process.stdout.write('GCS ready\n');
  socket.send(motorsOff(0), Number(physicsPort), physicsHost);  // subscribes
});
