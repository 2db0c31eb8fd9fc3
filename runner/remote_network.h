// `sitlnet run --listen ... --remote network`: accepting the medium's connector from another host.
#ifndef SITLNET_RUNNER_REMOTE_NETWORK_H_
#define SITLNET_RUNNER_REMOTE_NETWORK_H_

#include <memory>

#include "coordinator/connector.h"
#include "network_side/network_side.h"
#include "runner/runner.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

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
