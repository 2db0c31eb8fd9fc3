// `sitlnet run --listen ... --remote network`: accepting the medium's connector from another host.
#ifndef SITLNET_RUNNER_REMOTE_NETWORK_H_
#define SITLNET_RUNNER_REMOTE_NETWORK_H_

#include <cstdint>
#include <memory>
#include <string>

#include "coordinator/connector.h"
#include "network_side/network_side.h"
#include "runner/runner.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

// What a run listens for on --listen: peers (`what`, "the network connector") that run
// `peer_command`, proving `scenario_hash`, within `timeout_ns`.
struct PeerWait {
  std::string what;
  std::string peer_command;
  uint64_t scenario_hash = 0;
  TimeNs timeout_ns = 0;
};

// The listener on options.listen, and the handshake's expectation and limits from now on.
struct PeerListener {
  std::unique_ptr<coordinator::Listener> listener;
  coordinator::HandshakeExpectation expect;
  coordinator::WaitLimits limits;
};

// Listens on options.listen and says on stderr what it waits for. Throws Error if the address is
// reachable from other hosts without options.secret_file, or if the secret file is refused.
PeerListener ListenForPeers(const Scenario& scenario, const RunOptions& options,
                            const PeerWait& wait, int interrupt_fd);

// `--listen ... --remote network`: waits for the medium's network connector
// (another host's `sitlnet medium FILE --connect`) before anything is
// created, so that a timeout or a refusal leaves nothing behind. Returns null
// if interrupted; throws Error naming the missing side or the refusal.
std::unique_ptr<coordinator::Connector> AcceptRemoteNetwork(const Scenario& scenario,
                                                            const RunOptions& options,
                                                            int interrupt_fd);

// With --listen: the remote medium, accepted (AcceptRemoteNetwork) into *remote and wrapped at
// once, so that whatever fails from here on, the remote side gets Stop with a reason rather than
// a closed connection. Returns false if the run ends here: a failure (its line printed, exit code
// 1) or an interrupt (exit code 130) is in *report. Without --listen: true, *remote stays null.
bool AcceptRemoteMedium(const Scenario& scenario, const RunOptions& options, int interrupt_fd,
                        std::unique_ptr<network_side::RemoteMedium>* remote, RunReport* report);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_REMOTE_NETWORK_H_
