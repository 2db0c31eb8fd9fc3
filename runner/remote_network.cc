#include "runner/remote_network.h"

#include <cstdio>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"

namespace sitlnet::runner {

PeerListener ListenForPeers(const Scenario& scenario, const RunOptions& options,
                            const PeerWait& wait, int interrupt_fd) {
  const coordinator::Endpoint endpoint = coordinator::ParseEndpoint(options.listen);
  if (options.secret_file.empty() && !coordinator::IsLocalOnly(endpoint)) {
    throw Error("--listen " + options.listen +
                " can be reached from other hosts: give --secret-file PATH, the same file as `" +
                wait.peer_command + "`'s (docs/coordinator.md, \"Authentication\")");
  }
  PeerListener peers;
  peers.expect.secret = options.secret_file.empty()
                            ? std::string()
                            : coordinator::LoadSecretFile(options.secret_file);
  peers.listener = std::make_unique<coordinator::Listener>(endpoint);
  std::fprintf(stderr, "sitlnet run: %s: waiting %lld s for %s on %s (%s)\n", scenario.name.c_str(),
               static_cast<long long>(wait.timeout_ns / kNsPerS), wait.what.c_str(),
               peers.listener->endpoint().ToString().c_str(), wait.peer_command.c_str());
  peers.expect.scenario_hash = wait.scenario_hash;
  peers.expect.iteration_ns = scenario.iteration_ns;
  peers.limits.timeout_ns = wait.timeout_ns;
  peers.limits.deadline_ns = MonotonicNowNs() + wait.timeout_ns;
  peers.limits.interrupt_fd = interrupt_fd;
  return peers;
}

std::unique_ptr<coordinator::Connector> AcceptRemoteNetwork(const Scenario& scenario,
                                                            const RunOptions& options,
                                                            int interrupt_fd) {
  const PeerListener peers =
      ListenForPeers(scenario, options,
                     {"the network connector", "sitlnet medium FILE --connect HOST:PORT",
                      network_side::MediumScenarioHash(scenario), options.remote_wait_ns},
                     interrupt_fd);
  auto connector = coordinator::AcceptConnectorOfRole(*peers.listener, coordinator::Role::kNetwork,
                                                      peers.expect, peers.limits);
  if (connector) std::fprintf(stderr, "sitlnet run: %s connected\n", connector->Describe().c_str());
  return connector;  // The listener closes: nothing else can connect.
}

bool AcceptRemoteMedium(const Scenario& scenario, const RunOptions& options, int interrupt_fd,
                        std::unique_ptr<network_side::RemoteMedium>* remote, RunReport* report) {
  if (options.listen.empty()) return true;
  std::unique_ptr<coordinator::Connector> connector;
  try {
    connector = AcceptRemoteNetwork(scenario, options, interrupt_fd);
  } catch (const Error& error) {
    std::fprintf(stderr, "sitlnet run: %s\n", error.what());
    report->exit_code = 1;
    return false;
  }
  if (!connector) {
    report->interrupted = true;
    report->exit_code = 130;
    return false;
  }
  *remote = std::make_unique<network_side::RemoteMedium>(
      scenario, std::move(connector), coordinator::CoordinatorOptions{}.answer_timeout_ns);
  return true;
}

}  // namespace sitlnet::runner
