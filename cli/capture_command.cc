// `sitlnet capture --medium [SCENARIO]`: the medium's live pcap stream on
// stdout, for `sitlnet capture --medium | tshark -i -` (docs/capture.md).
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "nns/nns.h"
#include "sitlnet/medium.pb.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::cli {
namespace {

constexpr const char* kCaptureFooter =
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
    "exit codes: 0 stream ended, 1 no daemon or no such scenario, 2 usage.";

int Capture(std::string name) {
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

}  // namespace

Command AddCaptureCommand(CLI::App& sitlnet) {
  CLI::App* capture = sitlnet.add_subcommand("capture", "stream the medium's 802.11 view as pcap");
  capture->footer(kCaptureFooter);
  auto name = std::make_shared<std::string>();
  capture->add_flag("--medium")
      ->description("the medium daemon's view (the one view there is)")
      ->required();
  capture->add_option("SCENARIO_NAME", *name,
                      "the scenario (default: the one that is up, when there is one)");
  return {capture, [name] { return Capture(*name); }};
}

}  // namespace sitlnet::cli
