// `sitlnet medium --connect`: the 802.11 model serving a coordinator on another host as its
// network connector (docs/coordinator.md, "A connector on another host").
#include <unistd.h>

#include <cstdio>
#include <string>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::network_side {
namespace {

std::string Seconds(TimeNs ns) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", static_cast<double>(ns) / kNsPerS);
  return text;
}

}  // namespace

std::string ServeRemoteMedium(const Scenario& scenario, const RemoteMediumOptions& options) {
  const coordinator::Endpoint endpoint = coordinator::ParseEndpoint(options.coordinator_endpoint);
  const std::string secret = options.secret_file.empty()
                                 ? std::string()
                                 : coordinator::LoadSecretFile(options.secret_file);
  std::fprintf(stderr, "sitlnet medium: %s: connecting to the coordinator at %s\n",
               scenario.name.c_str(), endpoint.ToString().c_str());
  UniqueFd socket;
  try {
    socket = coordinator::Connect(endpoint, MonotonicNowNs() + options.connect_timeout_ns);
  } catch (const coordinator::TransportError& e) {
    throw Error(std::string("cannot reach the coordinator: ") + e.what() +
                (e.kind() == coordinator::TransportError::Kind::kTimeout
                     ? " (tried for " + Seconds(options.connect_timeout_ns) + " s)"
                     : std::string()));
  }
  StopSignal stop;  // From here on Ctrl-C ends the wait in order.
  coordinator::Channel channel(std::move(socket));
  MediumLinkSimulator simulator(scenario, tapbridge::MakeMacPhySimMedium(scenario));
  char host[256] = "localhost";
  gethostname(host, sizeof host - 1);
  const coordinator::ConnectorIdentity identity{std::string("medium@") + host,
                                                coordinator::Role::kNetwork,
                                                MediumScenarioHash(scenario), secret};
  return coordinator::ServeCoordinator(channel, simulator, identity, 10 * kNsPerS, stop.fd());
}

}  // namespace sitlnet::network_side
