// The medium daemon's control socket (`/run/sitlnet/<scenario>/medium.sock`, docs/tapbridge.md):
// length-prefixed MediumRequests from `sitlnet capture`, `sitlnet status` or anything root runs.
// The real ControlServer, on a real Unix socket, on the daemon's event loop, in front of a real
// bridge core with the 802.11 model (no TAPs attached): the fuzzer's bytes become a stream of
// frames, each a MediumRequest made up from them (positions of any robot, NaN and infinities
// included, counters, a pcap subscription) or raw bytes, behind a length that may lie. Every
// answer must be a well-framed MediumResponse (until a subscription turns the stream into pcap),
// and the server must go on serving the next connection. Every channel effect is on
// (fuzz_inputs.h, kEveryEffectRadio), so positions reach the whole channel model.
#include <fuzzer/FuzzedDataProvider.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "common/common.h"
#include "fuzz/fuzz_inputs.h"
#include "sitlnet/medium.pb.h"
#include "tapbridge/control_server.h"
#include "tapbridge/pcap_fanout.h"
#include "tapbridge/tapbridge.h"

namespace {

namespace tb = sitlnet::tapbridge;

// The daemon lives until the process ends (libFuzzer ends it with exit()), so its destructor
// never runs: its socket file is removed at exit instead.
const std::string* socket_path = nullptr;
void RemoveSocketFile() {
  if (socket_path != nullptr) unlink(socket_path->c_str());
}

struct Daemon {
  Daemon()
      : scenario(
            sitlnet::LoadScenarioText("name: \"fzc\"\n"
                                      "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
                                      "robot { name: \"b\" position_m { x: 20 y: 0 z: 1 } }\n" +
                                          std::string(sitlnet::fuzz::kEveryEffectRadio),
                                      "control_socket_fuzz")),
        core(scenario, tb::MakeMacPhySimMedium(scenario), Quiet()),
        fanout(0),
        path("/tmp/sitlnet-control-fuzz-" + std::to_string(getpid()) + ".sock"),
        server(path, &loop, &core, &fanout) {
    socket_path = &path;
    std::atexit(RemoveSocketFile);
  }
  static tb::BridgeOptions Quiet() {
    tb::BridgeOptions options;
    options.log = [](const std::string&) {};
    return options;
  }
  sitlnet::Scenario scenario;
  tb::EventLoop loop;
  tb::BridgeCore core;
  tb::PcapFanout fanout;
  std::string path;
  tb::ControlServer server;
};

double Coordinate(FuzzedDataProvider& in) { return sitlnet::fuzz::OddOrInRange(in, -100, 100); }

std::string Request(FuzzedDataProvider& in) {
  sitlnet::proto::MediumRequest request;
  switch (in.ConsumeIntegralInRange(0, 4)) {
    case 0: {
      const int positions = in.ConsumeIntegralInRange(0, 3);
      auto* set = request.mutable_set_positions();
      for (int i = 0; i < positions; ++i) {
        auto* p = set->add_position();
        if (in.ConsumeBool()) {
          p->set_robot_index(in.ConsumeIntegralInRange<uint32_t>(0, 3));
        } else {
          p->set_robot(in.ConsumeRandomLengthString(4));
        }
        p->mutable_position_m()->set_x(Coordinate(in));
        p->mutable_position_m()->set_y(Coordinate(in));
        p->mutable_position_m()->set_z(Coordinate(in));
      }
      break;
    }
    case 1:
      request.mutable_get_counters();
      break;
    case 2:
      if (in.ConsumeIntegralInRange(0, 7) == 0) request.mutable_subscribe_pcap();
      break;
    case 3:
      return in.ConsumeRandomLengthString(64);  // Raw bytes, maybe no MediumRequest.
    default:
      break;  // Empty request.
  }
  return request.SerializeAsString();
}

using sitlnet::fuzz::Le32;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Daemon* daemon = new Daemon();  // One daemon for the whole run, as in production.
  FuzzedDataProvider in(data, size);
  std::string stream;
  bool subscribes = false;
  const int requests = in.ConsumeIntegralInRange(0, 6);
  for (int i = 0; i < requests; ++i) {
    const std::string body = Request(in);
    sitlnet::proto::MediumRequest parsed;
    subscribes = subscribes || (parsed.ParseFromString(body) && parsed.has_subscribe_pcap());
    uint32_t length = static_cast<uint32_t>(body.size());
    if (in.ConsumeIntegralInRange(0, 15) == 0) length = in.ConsumeIntegral<uint32_t>();  // A lie.
    for (int b = 0; b < 4; ++b) stream.push_back(static_cast<char>(length >> (8 * b)));
    stream += body;
  }
  const int client = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, daemon->path.c_str(), sizeof address.sun_path - 1);
  if (connect(client, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    __builtin_trap();  // The server stopped serving.
  }
  daemon->loop.RunOnce(0);  // Accept.
  if (!stream.empty() && send(client, stream.data(), stream.size(), MSG_NOSIGNAL) < 0) {
    __builtin_trap();
  }
  std::string answers;
  for (int round = 0; round < 4; ++round) {
    daemon->loop.RunOnce(0);
    char buffer[65536];
    ssize_t n;
    while ((n = recv(client, buffer, sizeof buffer, 0)) > 0) answers.append(buffer, n);
  }
  close(client);
  daemon->loop.RunOnce(0);  // The server sees the close.
  // Answers: length-prefixed MediumResponses, each parseable (a subscription's pcap stream
  // follows its own answer and is not framed).
  size_t at = 0;
  while (!subscribes && at + 4 <= answers.size()) {
    const uint32_t length = Le32(answers, at);
    if (at + 4 + length > answers.size()) __builtin_trap();
    sitlnet::proto::MediumResponse response;
    if (!response.ParseFromString(answers.substr(at + 4, length))) __builtin_trap();
    at += 4 + length;
  }
  if (!subscribes && at != answers.size()) __builtin_trap();
  return 0;
}
