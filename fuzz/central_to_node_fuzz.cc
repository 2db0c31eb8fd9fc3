// What the central host sends a node host (issue 35) is input too: the central proved the shared
// secret, but a node must refuse a Start it cannot serve in one line (Error), never crash or
// write to a robot that is not its own. Here node n0 (robots a and c of a three-robot fleet)
// runs NodeSimulator, the production code between the link and its robots' TAPs, over in-memory
// TAPs and a stand-in physics, for Starts whose payload is a NodeStart made up from the bytes
// (frames, writes to any robot, frame index and due instant) or the bytes as they come, in
// lockstep or realtime pacing (iterations of no length there: the wait to their end is the
// central's to set). Checked each iteration:
// - a refused Start writes nothing; an accepted one writes exactly its writes, in order, each
//   robot its own frames;
// - the frames the node drains and sends up (lockstep: CommandsCollected.payload; realtime:
//   End.payload, with a read instant per frame and a lateness of 0 or more per write) parse as
//   NodeFrames that the central's own checks (FindBrokenBound, FindBrokenWriteLateness) accept,
//   and are what the robots sent, in order, a bridge turn at most, each cut to
//   kMaxNodeFrameBytes; a failed read ends a robot's batch with its errno and the robot is read
//   no more.
#include <fuzzer/FuzzedDataProvider.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "clock/clock.h"
#include "common/common.h"
#include "fleet/fleet.h"
#include "fleet/node_frames_bounds.h"
#include "fleet/node_ports.h"
#include "fuzz/fuzz_inputs.h"

namespace {

namespace fleet = sitlnet::fleet;
namespace pn = sitlnet::proto::node;
namespace pc = sitlnet::proto::coord;

// Rare cases take the largest value of a range (fuzz_inputs.h).

const std::vector<std::string>& RobotNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const sitlnet::RobotPlan& plan : sitlnet::fuzz::ThreeRobotFleet().robots)
      all.push_back(plan.name);
    return all;
  }();
  return names;
}

// A robot's wlan0 TAP in memory: what its software sent and what was written to it.
struct MemoryTap {
  std::deque<std::string> sent;
  int read_errno = 0;  // Reads fail with it once `sent` is empty.
  bool refuse_writes = false;
  std::vector<std::string> written;
  int ready_fd = -1;  // An eventfd: readable while frames or an error wait, as a TAP polls.

  void UpdateReady() const {
    uint64_t value = 1;
    [[maybe_unused]] const ssize_t n = sent.empty() && read_errno == 0
                                           ? read(ready_fd, &value, sizeof value)
                                           : write(ready_fd, &value, sizeof value);
  }
};

class MemoryPort final : public sitlnet::tapbridge::Port {
 public:
  explicit MemoryPort(MemoryTap* tap) : tap_(*tap) {
    tap_.ready_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  }
  ~MemoryPort() override { close(tap_.ready_fd); }
  int fd() const override { return tap_.ready_fd; }
  ssize_t Read(std::span<uint8_t> buffer) override {
    if (tap_.sent.empty()) {
      tap_.UpdateReady();
      return -tap_.read_errno;
    }
    const std::string frame = std::move(tap_.sent.front());
    tap_.sent.pop_front();
    const size_t length = std::min(frame.size(), buffer.size());  // Cut, as a TAP read does.
    std::copy_n(frame.begin(), length, buffer.begin());
    return static_cast<ssize_t>(length);
  }
  int Write(std::span<const uint8_t> frame) override {
    if (tap_.refuse_writes) return -ENOBUFS;
    tap_.written.emplace_back(frame.begin(), frame.end());
    return 0;
  }
  std::optional<uint64_t> KernelTxDropped() override { return std::nullopt; }

 private:
  MemoryTap& tap_;
};

// The node's physics: poses of its robots; it reports the commands in, or leaves that to
// NodeSimulator (which then reports after the iteration).
class StandInPhysics final : public sitlnet::coordinator::Simulator {
 public:
  explicit StandInPhysics(bool reports) : reports_(reports) {}
  void RunIteration(const pc::Start&, pc::End* end,
                    sitlnet::coordinator::IterationContext& context) override {
    ran_ = true;
    if (reports_) context.CommandsCollected();
    end->mutable_poses()->add_position_m(0);
  }
  bool ran() const { return ran_; }
  void Reset() { ran_ = false; }

 private:
  bool reports_;
  bool ran_ = false;
};

// What the coordinator's side of the node sends up: the CommandsCollected payload.
class PayloadContext final : public sitlnet::coordinator::IterationContext {
 public:
  void CommandsCollected() override { __builtin_trap(); }  // A node always sends its frames.
  void CommandsCollectedWithPayload(std::string payload) override {
    ++reports_;
    payload_ = std::move(payload);
  }
  int reports_ = 0;
  std::string payload_;
};

// Frames a robot's software sent this iteration: a few of any length (some longer than a node
// sends), sometimes more than a bridge turn; sometimes its TAP fails after them.
void RobotSends(FuzzedDataProvider& in, MemoryTap* tap) {
  const bool flood = in.ConsumeIntegralInRange(0, 15) == 15;
  const size_t count = flood ? sitlnet::tapbridge::kMaxFramesPerRobotPerTurn +
                                   in.ConsumeIntegralInRange<size_t>(0, 3)
                             : in.ConsumeIntegralInRange<size_t>(0, 3);
  for (size_t i = 0; i < count; ++i) {
    if (flood) {
      tap->sent.push_back(std::string(1 + i % 5, 'f'));
    } else if (in.ConsumeIntegralInRange(0, 5) == 5) {
      tap->sent.push_back(
          std::string(fleet::kMaxNodeFrameBytes + in.ConsumeIntegralInRange(-1, 600), 'L'));
    } else {
      tap->sent.push_back(in.ConsumeRandomLengthString(100) + "!");  // A TAP read gives a byte.
    }
  }
  if (in.ConsumeIntegralInRange(0, 15) == 15) tap->read_errno = EIO;
  tap->refuse_writes = in.ConsumeIntegralInRange(0, 7) == 7;
  tap->UpdateReady();
}

// A Start's payload: a NodeStart made up from the bytes, or the bytes as they come.
std::string StartPayload(FuzzedDataProvider& in) {
  if (in.ConsumeIntegralInRange(0, 7) == 7) return in.ConsumeRandomLengthString(300);
  pn::NodeStart start;
  pn::NodeWrites* writes = start.mutable_writes();
  const int frames = in.ConsumeIntegralInRange(0, 3);
  for (int i = 0; i < frames; ++i) writes->add_frames(in.ConsumeRandomLengthString(200));
  const int count = in.ConsumeIntegralInRange(0, 6);
  for (int i = 0; i < count; ++i) {
    pn::NodeWrites::Write* write = writes->add_writes();
    write->set_robot(in.ConsumeBool() ? in.ConsumeIntegralInRange(-1, 3)
                                      : in.ConsumeIntegral<int32_t>());
    write->set_frame_index(in.ConsumeBool() ? in.ConsumeIntegralInRange(-1, frames)
                                            : in.ConsumeIntegral<int32_t>());
    // Realtime: the virtual instant it was written on the central; near the run's start, or any.
    write->set_due_ns(in.ConsumeBool() ? in.ConsumeIntegralInRange<int64_t>(-1, 1'000'000'000)
                                       : in.ConsumeIntegral<int64_t>());
  }
  return start.SerializeAsString();
}

// The frames the node must send up for a robot whose TAP held `sent` (with `read_errno` after
// them): a bridge turn at most, each cut to kMaxNodeFrameBytes; the errno if reads got to it.
struct ExpectedBatch {
  std::vector<std::string> frames;
  int read_errno = 0;
};
ExpectedBatch ExpectedDrain(const MemoryTap& tap) {
  ExpectedBatch batch;
  for (const std::string& frame : tap.sent) {
    if (batch.frames.size() == sitlnet::tapbridge::kMaxFramesPerRobotPerTurn) return batch;
    batch.frames.push_back(frame.substr(0, fleet::kMaxNodeFrameBytes));
  }
  if (batch.frames.size() < sitlnet::tapbridge::kMaxFramesPerRobotPerTurn) {
    batch.read_errno = tap.read_errno;
  }
  return batch;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const sitlnet::Scenario& scenario = sitlnet::fuzz::ThreeRobotFleet();
  const fleet::NodeSlice& slice = scenario.nodes[0];
  FuzzedDataProvider in(data, size);
  std::map<int, MemoryTap> taps;
  fleet::NodePorts ports(slice,
                         [&taps](int robot) { return std::make_unique<MemoryPort>(&taps[robot]); });
  // Realtime pacing one input in four: its physics reports no CommandsCollected.
  const bool realtime = in.ConsumeIntegralInRange(0, 3) == 3;
  sitlnet::clock::Timebase timebase;  // Begun by the first Start.
  StandInPhysics physics(!realtime && in.ConsumeBool());
  fleet::NodeSimulator node(&physics, &ports, realtime ? &timebase : nullptr);
  std::map<int, bool> read_failed;  // Robots the node reads no more.

  const int iterations = in.ConsumeIntegralInRange(1, 4);
  for (int k = 0; k < iterations; ++k) {
    std::map<int, ExpectedBatch> expected;
    for (const int robot : slice.robots) {
      RobotSends(in, &taps[robot]);
      if (!read_failed[robot]) expected[robot] = ExpectedDrain(taps[robot]);
    }
    pc::Start start;
    start.set_iteration(k);
    if (realtime) {  // No length: the node reads its ports once and answers.
      start.set_start_ns(in.ConsumeBool() ? k * 10'000'000 : in.ConsumeIntegral<int64_t>());
      start.set_end_ns(start.start_ns());
    }
    start.set_payload(StartPayload(in));
    std::map<int, size_t> written_before;
    for (const int robot : slice.robots) written_before[robot] = taps[robot].written.size();

    PayloadContext context;
    pc::End end;
    physics.Reset();
    try {
      node.RunIteration(start, &end, context);
    } catch (const sitlnet::Error&) {
      // Refused: nothing written, the physics did not run; the node tells the central and ends.
      for (const int robot : slice.robots) {
        if (taps[robot].written.size() != written_before[robot]) __builtin_trap();
      }
      if (physics.ran()) __builtin_trap();
      return 0;
    }

    // Accepted: it was a NodeStart whose every write names one of the node's robots and one of
    // its frames; each robot got its writes, in order (unless its TAP refused them).
    pn::NodeStart sent;
    if (!sent.ParseFromString(start.payload())) __builtin_trap();
    std::map<int, std::vector<std::string>> writes;
    for (const pn::NodeWrites::Write& write : sent.writes().writes()) {
      if (!std::ranges::binary_search(slice.robots, write.robot()) || write.frame_index() < 0 ||
          write.frame_index() >= sent.writes().frames_size()) {
        __builtin_trap();
      }
      if (!taps[write.robot()].refuse_writes) {
        writes[write.robot()].push_back(sent.writes().frames(write.frame_index()));
      }
    }
    for (const int robot : slice.robots) {
      const std::vector<std::string>& written = taps[robot].written;
      if (!std::equal(written.begin() + static_cast<ptrdiff_t>(written_before[robot]),
                      written.end(), writes[robot].begin(), writes[robot].end())) {
        __builtin_trap();
      }
    }

    // Drained once, up with CommandsCollected (realtime: End), within the bounds the central
    // checks.
    if (!physics.ran() || context.reports_ != (realtime ? 0 : 1)) __builtin_trap();
    pn::NodeFrames up;
    if (!up.ParseFromString(realtime ? end.payload() : context.payload_)) __builtin_trap();
    if (fleet::FindBrokenBound(up, slice, RobotNames(), realtime)) __builtin_trap();
    if (fleet::FindBrokenWriteLateness(up, sent.writes().writes_size())) __builtin_trap();
    if (up.write_late_ns_size() != (realtime ? sent.writes().writes_size() : 0)) __builtin_trap();
    for (const int64_t late_ns : up.write_late_ns()) {
      if (late_ns < 0) __builtin_trap();
    }
    for (const pn::FrameBatch& batch : up.batches()) {
      const auto want = expected.find(batch.robot());
      if (want == expected.end()) __builtin_trap();  // Not its robot, or one read no more.
      if (!std::ranges::equal(batch.frames(), want->second.frames) ||
          batch.read_errno() != want->second.read_errno) {
        __builtin_trap();
      }
      if (batch.read_errno() != 0) read_failed[batch.robot()] = true;
      expected.erase(want);
    }
    // A robot left out had nothing to say.
    for (const auto& [robot, batch] : expected) {
      if (!batch.frames.empty() || batch.read_errno != 0) __builtin_trap();
    }
  }
  return 0;
}
