#!/usr/bin/env python3
"""Writes the seeds of the node link fuzzers (issue 35) from valid messages.

node_to_central_fuzz and central_to_node_fuzz read their input through libFuzzer's
FuzzedDataProvider, so a seed is the byte string that makes each of them build valid messages:
Hellos of both nodes, their frames, a bridge turn and their Ends; Starts that carry a broadcast
to both of a node's robots; in lockstep and in realtime pacing. Encoder below:
FuzzedDataProvider takes integers from the end of the input (most significant byte first) and
strings from the front ('\\' doubled, '\\' and any other byte end one). The seeds follow the
order in which the fuzzers read: after changing what a fuzzer reads, run this again
(python3 fuzz/fleet_seeds.py) and commit the seeds.
"""
import pathlib
import struct

CORPUS = pathlib.Path(__file__).resolve().parent / "corpus"


class ProviderInput:
    """The bytes a FuzzedDataProvider turns into the values given, in the order they are read."""

    def __init__(self):
        self.front = bytearray()
        self.back = bytearray()  # In the order they are read: the input holds them reversed.

    def int_in_range(self, low, high, value):
        assert low <= value <= high
        span, offset, taken = high - low, 0, []
        while offset < 64 and (span >> offset) > 0:
            taken.append(offset)
            offset += 8
        self.back += (value - low).to_bytes(len(taken), "big") if taken else b""
        return self

    def boolean(self, value):
        return self.int_in_range(0, 255, int(value))

    def double_in_range(self, low, high, value):
        # low + (high - low) * ConsumeProbability(), the probability an 8-byte integer's share.
        share = min(round((value - low) / (high - low) * 2**64), 2**64 - 1)
        return self.int_in_range(0, 2**64 - 1, share)

    def string(self, data):
        self.front += data.replace(b"\\", b"\\\\") + b"\\;"
        return self

    def bytes(self):
        return bytes(self.front) + bytes(reversed(self.back))


def robot_mac(index):
    return bytes([0x02, 0, 0, 0, (index >> 8) & 0xFF, index & 0xFF])


def broadcast_frame(robot, payload):
    """An Ethernet broadcast of a UDP datagram from robot `robot` (as the flockers send)."""
    udp = struct.pack("!HHHH", 47000, 47000, 8 + len(payload), 0) + payload
    ip = struct.pack("!BBHHHBBH4s4s", 0x45, 0, 20 + len(udp), 0, 0x4000, 64, 17, 0,
                     bytes([10, 0, 0, 1 + robot]), bytes([10, 0, 0, 255]))
    return b"\xff" * 6 + robot_mac(robot) + b"\x08\x00" + ip + udp


def poses(seed, robots, ranges=((-100, 100), (-1, 1), (-20, 20))):
    """fuzz_inputs.h FillPoses: the counts a physics sends, velocities included, finite values."""
    seed.int_in_range(0, 3, 0).boolean(True)  # Counts per robot; with velocities.
    for (low, high), per_robot in zip(ranges, (3, 4, 3)):
        for i in range(per_robot * robots):
            seed.int_in_range(0, 3, 2).double_in_range(low, high, (low + high) / 2 + i % 3 * 0.25)


def node_to_central(realtime):
    """Nodes n0 (robots a, c) and n1 (b) join, send their frames (realtime: read instants, and
    the lateness of the Start's 2 writes), the bridge reads, both End."""
    seed = ProviderInput().int_in_range(0, 7, 7 if realtime else 0)
    for node, robots in ((0, 2), (1, 1)):  # Hello: one of the nodes, its robots, their poses.
        seed.int_in_range(0, 1, node).int_in_range(0, 4, 0)
        seed.int_in_range(0, 2, 0).int_in_range(0, 1, node).boolean(True).int_in_range(0, 1, node)
        seed.int_in_range(0, 3, robots)
        poses(seed, robots)
    writes_sent = 2 if realtime else 0
    for node, batches in ((0, ((0, 2), (2, 1))), (1, ((1, 1),))):  # NodeFrames in bounds.
        seed.int_in_range(0, 1, node).int_in_range(0, 4, 1).int_in_range(0, 3, writes_sent)
        seed.int_in_range(0, 7, 0).int_in_range(0, 4, len(batches))
        for robot, frames in batches:
            seed.boolean(True).int_in_range(-1, 3, robot).int_in_range(0, 15, 0)
            seed.int_in_range(0, 4, frames)
            for k in range(frames):
                seed.int_in_range(0, 7, 0).string(broadcast_frame(robot, b"flock %d" % k))
            seed.int_in_range(0, 7, 0).int_in_range(0, 1, int(realtime))  # Read instants.
            for k in range(frames if realtime else 0):
                seed.boolean(True).int_in_range(-1, 10**9, 2_000_000 * (k + 1))
            seed.int_in_range(0, 3, 2)  # No read error.
        seed.int_in_range(0, 4, writes_sent)  # The writes' lateness.
        for late_ns in (150_000, 2_500_000)[:writes_sent]:
            seed.boolean(True).int_in_range(-1, 10**7, late_ns)
    seed.int_in_range(0, 1, 0).int_in_range(0, 4, 2)  # The bridge reads a turn.
    for node, robots in ((0, 2), (1, 1)):  # End: the node's poses.
        seed.int_in_range(0, 1, node).int_in_range(0, 4, 4).int_in_range(0, 7, 0)
        poses(seed, robots)
    return seed.bytes()


def central_to_node(realtime):
    """Node n0 (robots a, c), two iterations (realtime: of no length): a and c each send a
    frame; b's broadcast comes down to both with the first Start, nothing with the second."""
    seed = ProviderInput().int_in_range(0, 3, 3 if realtime else 0)
    if not realtime:
        seed.boolean(True)  # The physics reports its commands.
    seed.int_in_range(1, 4, 2)  # 2 iterations.
    for k in range(2):
        for robot in (0, 2):
            seed.int_in_range(0, 15, 0).int_in_range(0, 3, 1)
            seed.int_in_range(0, 5, 0).string(broadcast_frame(robot, b"flock %d" % k))
            seed.int_in_range(0, 15, 0).int_in_range(0, 7, 0)  # No read error; writes go.
        if realtime:
            seed.boolean(True)  # Starts at k * 10 ms.
        seed.int_in_range(0, 7, 0)  # A NodeStart.
        frames, writes = ((1, ((0, 0), (2, 0))), (0, ()))[k]
        seed.int_in_range(0, 3, frames)
        for _ in range(frames):
            seed.string(broadcast_frame(1, b"flock from b"))
        seed.int_in_range(0, 6, len(writes))
        for robot, frame in writes:
            seed.boolean(True).int_in_range(-1, 3, robot).boolean(True)
            seed.int_in_range(-1, frames, frame).boolean(True).int_in_range(-1, 10**9, 4_000_000)
    return seed.bytes()


SEEDS = (("node_to_central_fuzz", "two_nodes_join_send_and_end", node_to_central(False)),
         ("node_to_central_fuzz", "realtime_frames_with_read_instants_and_lateness",
          node_to_central(True)),
         ("central_to_node_fuzz", "a_broadcast_down_to_two_robots", central_to_node(False)),
         ("central_to_node_fuzz", "realtime_a_broadcast_due_at_4_ms", central_to_node(True)))
for target, name, data in SEEDS:
    (CORPUS / target).mkdir(parents=True, exist_ok=True)
    (CORPUS / target / name).write_bytes(data)
    print(f"fuzz/corpus/{target}/{name}: {len(data)} bytes")
