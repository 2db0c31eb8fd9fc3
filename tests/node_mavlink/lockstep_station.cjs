// A ground station that takes part in a lockstep run as a robot of the scenario, through
// sitlnet's native protocol (docs/protocols.md): its motors stay off, sitlnet sends it a
// RobotState each step, and it answers with a MotorCommand only after it has handled every
// datagram that came before that state and sent what they called for.
// Why that is reproducible: the medium writes the frames due before a state into this robot's
// TAP before physics sends the state, and one socket takes both, so they queue in that order;
// node handles each datagram, and the sends it makes, before the next one; what this robot sends
// before its MotorCommand enters the medium in the same iteration.
// Used by guided_flight_lockstep.cjs and fly_px4_lockstep.cjs.
'use strict';
const dgram = require('dgram');

// The protobuf wire format of robot.proto, as far as a station needs it.
function varint(value) {
  const bytes = [];
  for (; value >= 0x80; value = Math.floor(value / 0x80)) bytes.push((value % 0x80) | 0x80);
  bytes.push(value);
  return bytes;
}
// RobotState's step (field 2) and sim_time_ns (field 3), 0 when absent; null if malformed.
function readState(buffer) {
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
  const state = { step: 0, simTimeNs: 0 };
  try {
    while (at < buffer.length) {
      const key = readVarint();
      const [field, type] = [Math.floor(key / 8), key % 8];
      if (type === 0) {
        const value = readVarint();
        if (field === 2) state.step = value;
        if (field === 3) state.simTimeNs = value;
      } else if (type === 1) {
        at += 8;
      } else if (type === 2) {
        const length = readVarint();  // read before `at` is: `at += readVarint()` would not skip it
        at += length;
      } else if (type === 5) {
        at += 4;
      } else {
        return null;
      }
    }
  } catch (error) {
    return null;
  }
  return at === buffer.length ? state : null;
}
// MotorCommand { step, throttle: [0, 0, 0, 0] }: motors off, this step answered.
function motorsOff(step) {
  return Buffer.from([0x10, ...varint(step), 0x22, 32, ...new Array(32).fill(0)]);
}

// Binds UDP `port` on all addresses; calls onDatagram(datagram, from) for every datagram not from
// physics and onState(simTimeNs) for every state, before answering it. Prints "GCS ready" once
// bound (the image's ready_log_line). Returns the socket, for sends.
function lockstepStation({ port, onDatagram, onState }) {
  const [physicsHost, physicsPort] = (process.env.SITLNET_PHYSICS_ADDR || '').split(':');
  if (!physicsPort) {
    process.stderr.write('SITLNET_PHYSICS_ADDR=HOST:PORT is not set (sitlnet sets it in a robot)\n');
    process.exit(2);
  }
  const socket = dgram.createSocket('udp4');
  const subscribe = () => socket.send(motorsOff(0), Number(physicsPort), physicsHost);
  let subscribing = null;  // until the first state: a subscription sent too early is lost
  socket.on('message', (datagram, from) => {
    if (from.address !== physicsHost || from.port !== Number(physicsPort)) {
      onDatagram(datagram, from);
      return;
    }
    const state = readState(datagram);
    if (state === null) return;
    clearInterval(subscribing);
    onState(state.simTimeNs);
    socket.send(motorsOff(state.step), from.port, from.address);
  });
  socket.bind(port, () => {
    process.stdout.write('GCS ready\n');
    subscribe();
    subscribing = setInterval(subscribe, 100);
  });
  return socket;
}

module.exports = { lockstepStation };
