// The filter on the root side of the robots' ctl0 links (issue 17, findings 3 and 11;
// docs/security.md): an nftables table, `inet sitlnet-<scenario>`, in the scenario's ctl
// namespace, that lets a robot reach only the root side of its own ctl0, and there only the
// ports the physics server listens on for it (the physics protocol's UDP port, its ArduPilot JSON
// UDP port, its PX4 TCP port), ping, and answers to what the root side sent it first. Without it,
// a robot that can write its neighbour table (CAP_NET_ADMIN, or `sandbox: NONE`) reaches every
// address of the ctl namespace through ctl0 (Linux accepts a packet for any local address on any
// interface): the other robots' root sides and their physics ports. (When the root sides were in
// the host's namespace, that was every address of the host.) Written with libnftables, in nft's
// own language, as one transaction.
#include <nftables/libnftables.h>

#include <memory>
#include <string>

#include "nns/nns_internal.h"

namespace sitlnet::nns::internal {
namespace {

struct NftContextFree {
  void operator()(nft_ctx* context) const { nft_ctx_free(context); }
};

// Runs `commands` (nft syntax) as one transaction; the error nft printed, or "" on success.
std::string RunNft(const std::string& commands) {
  std::unique_ptr<nft_ctx, NftContextFree> context(nft_ctx_new(NFT_CTX_DEFAULT));
  if (!context) return "libnftables: no context";
  nft_ctx_buffer_output(context.get());
  nft_ctx_buffer_error(context.get());
  if (nft_run_cmd_from_buffer(context.get(), commands.c_str()) == 0) return "";
  std::string error = nft_ctx_get_error_buffer(context.get());
  // nft's message, then the command and a caret line: the first line says what went wrong.
  error = error.substr(0, error.find('\n'));
  return error.empty() ? "nft failed" : error;
}

std::string TableName(const std::string& scenario) { return "sitlnet-" + scenario; }

}  // namespace

void AddCtlFilter(const Scenario& scenario, const std::vector<int>& robots) {
  const uint32_t physics_port = scenario.spec.addresses().physics_port();
  std::string veths;
  std::string own;
  std::string allowed;
  const auto add = [](std::string* list, const std::string& element) {
    *list += (list->empty() ? "" : ", ") + element;
  };
  for (const int index : robots) {
    const RobotPlan& robot = scenario.robots[index];
    const std::string veth = "\"" + robot.root_veth + "\"";
    const std::string root = veth + " . " + FormatIpv4(robot.ctl_root_address);
    add(&veths, veth);
    add(&own, root);
    add(&allowed, root + " . udp . " + std::to_string(physics_port));
    if (const uint32_t json = robot.spec.ardupilot_json_port(); json != 0) {
      add(&allowed, root + " . udp . " + std::to_string(json));
    }
    if (const uint32_t px4 = robot.spec.px4_sim_port(); px4 != 0) {
      add(&allowed, root + " . tcp . " + std::to_string(px4));
    }
  }
  const std::string table = "inet " + TableName(scenario.name);
  // Sets hold the exact names: another scenario's veths never match ("a-c0" of scenario "a"
  // and "a-c-c0" of scenario "a-c" share a prefix). Before the host's own filters (priority
  // filter - 10); what is not dropped here goes on to them.
  const std::string lines[] = {
      "add table " + table,
      "add set " + table + " robots { type ifname; elements = { " + veths + " }; }",
      "add set " + table + " own { type ifname . ipv4_addr; elements = { " + own + " }; }",
      "add set " + table +
          " allowed { type ifname . ipv4_addr . inet_proto . inet_service; elements = { " +
          allowed + " }; }",
      "add chain " + table + " from_robots",
      // Answers to what the root side sent first (the physics server's states, a ping or a
      // probe from the host): conntrack's own flows, which a robot cannot start.
      "add rule " + table + " from_robots ct state established,related accept",
      "add rule " + table + " from_robots iifname . ip daddr . meta l4proto . th dport @allowed " +
          "accept",
      "add rule " + table + " from_robots iifname . ip daddr @own icmp type echo-request accept",
      "add rule " + table + " from_robots counter drop",
      // The physics traffic itself (each robot's commands in, states out, hundreds per
      // second) skips conntrack, which would otherwise track every one of these flows.
      "add chain " + table + " untracked_in { type filter hook prerouting priority raw; }",
      "add rule " + table + " untracked_in iifname . ip daddr . meta l4proto . th dport " +
          "@allowed notrack",
      // Nor are a robot's pings to its own root address (one conntrack entry per ICMP id
      // would let a robot fill the host's conntrack table).
      "add rule " + table + " untracked_in iifname . ip daddr @own icmp type echo-request notrack",
      "add chain " + table + " untracked_out { type filter hook output priority raw; }",
      "add rule " + table + " untracked_out oifname . ip saddr . meta l4proto . th sport " +
          "@allowed notrack",
      "add rule " + table + " untracked_out oifname . ip saddr @own icmp type echo-reply notrack",
      "add chain " + table +
          " input { type filter hook input priority filter - 10; policy accept; }",
      "add rule " + table + " input iifname @robots jump from_robots",
      "add chain " + table +
          " forward { type filter hook forward priority filter - 10; policy accept; }",
      "add rule " + table + " forward iifname @robots counter drop",
  };
  std::string rules;
  for (const std::string& line : lines) rules += line + "\n";
  if (const std::string error = RunNft(rules); !error.empty()) {
    throw Error("scenario \"" + scenario.name + "\": nftables table " + table + ": " + error);
  }
}

}  // namespace sitlnet::nns::internal
