// `sitlnet capture --medium [SCENARIO]`: the medium's live pcap stream on
// stdout, for `sitlnet capture --medium | tshark -i -` (docs/capture.md).
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <string>

#include "cli/commands.h"
#include "nns/nns.h"
#include "sitlnet/medium.pb.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kCaptureHelp =
    "usage: sitlnet capture --medium [SCENARIO_NAME]\n"
    "\n"
    "Writes the medium's view (every 802.11 frame on the air: data, ACKs, retries,\n"
    "collided frames, with radiotap signal/noise dBm, rate, channel) as a pcap\n"
    "stream to stdout until the daemon stops or the reader goes away:\n"
    "\n"
    "  sitlnet capture --medium | tshark -i -\n"
    "  sitlnet capture --medium two > air.pcap\n"
    "\n"
    "SCENARIO_NAME may be left out when exactly one scenario is up. Needs\n"
    "`sitlnet medium SCENARIO` running. A robot's own view: sitlnet exec ROBOT --\n"
    "tcpdump -i wlan0.\n"
    "\n"
    "exit codes: 0 stream ended, 1 no daemon or no such scenario, 2 usage.\n";

}  // namespace

int RunCaptureCommand(int argc, char** argv) {
  if (WantsHelp(argc, argv)) {
    std::fputs(kCaptureHelp, stdout);
    return kExitOk;
  }
  bool medium = false;
  std::string name;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--medium") {
      medium = true;
    } else if (name.empty() && !arg.starts_with("-")) {
      name = arg;
    } else {
      std::fprintf(stderr, "sitlnet capture: unexpected argument \"%s\"\n%s", arg.c_str(),
                   kCaptureHelp);
      return kExitUsage;
    }
  }
  if (!medium) {
    std::fputs(kCaptureHelp, stderr);
    return kExitUsage;
  }
  return ReportErrors("capture", kExitFailure, [&] {
    if (name.empty()) {
      const std::vector<std::string> up = nns::ListScenarios();
      if (up.size() != 1) {
        throw Error(up.empty() ? "no scenario is up"
                               : "several scenarios are up: name one (sitlnet status)");
      }
      name = up.front();
    }
    tapbridge::ControlClient client(tapbridge::ControlSocketPath(name));
    proto::MediumRequest request;
    request.mutable_subscribe_pcap();
    proto::MediumResponse response;
    response.ParseFromString(client.Call(request.SerializeAsString()));
    if (response.has_error()) throw Error("medium daemon: " + response.error());
    // A reader that exits (tshark -c N) ends the capture quietly.
    signal(SIGPIPE, SIG_IGN);
    char buffer[1 << 16];
    for (;;) {
      const ssize_t n = read(client.fd(), buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return kExitOk;
      for (ssize_t done = 0; done < n;) {
        const ssize_t w = write(STDOUT_FILENO, buffer + done, n - done);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return kExitOk;
        done += w;
      }
    }
  });
}

}  // namespace sitlnet::cli
