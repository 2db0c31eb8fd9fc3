#include "runner/remote_network.h"

#include <cstdio>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"

namespace sitlnet::runner {

std::unique_ptr<coordinator::Connector> AcceptRemoteNetwork(const Scenario& scenario,
                                                            const RunOptions& options,
                                                            int interrupt_fd) {
  const coordinator::Endpoint endpoint = coordinator::ParseEndpoint(options.listen);
  if (options.secret_file.empty() && !coordinator::IsLocalOnly(endpoint)) {
    throw Error("--listen " + options.listen +
                " can be reached from other hosts: give --secret-file PATH, the same file as "
                "`sitlnet medium --connect`'s (docs/coordinator.md, \"Authentication\")");
  }
  const std::string secret = options.secret_file.empty()
                                 ? std::string()
                                 : coordinator::LoadSecretFile(options.secret_file);
  coordinator::Listener listener(endpoint);
  std::fprintf(stderr,
               "sitlnet run: %s: waiting %lld s for the network connector on %s "
               "(sitlnet medium FILE --connect HOST:PORT)\n",
               scenario.name.c_str(), static_cast<long long>(options.remote_wait_ns / kNsPerS),
               listener.endpoint().ToString().c_str());
  coordinator::HandshakeExpectation expect;
  expect.scenario_hash = network_side::MediumScenarioHash(scenario);
  expect.iteration_ns = scenario.iteration_ns;
  expect.secret = secret;
  coordinator::WaitLimits limits;
  limits.timeout_ns = options.remote_wait_ns;
  limits.deadline_ns = MonotonicNowNs() + options.remote_wait_ns;
  limits.interrupt_fd = interrupt_fd;
  auto connector =
      coordinator::AcceptConnectorOfRole(listener, coordinator::Role::kNetwork, expect, limits);
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
