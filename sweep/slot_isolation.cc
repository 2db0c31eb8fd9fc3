// Runs at once never clash: each job slot has its own scenario name (namespaces, devices and the
// state file are named from it), its own ctl subnet (its root-side addresses) and physics port
// (docs/architecture.md, "Names").
#include "common/common.h"
#include "scenario/scenario.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

// `prefix` moved up by `slot` times its own size; throws past the end of the IPv4 space.
std::string ShiftedSubnet(const std::string& field, const std::string& prefix_text, int slot) {
  const std::optional<Ipv4Prefix> prefix = ParseIpv4Prefix(prefix_text);
  if (!prefix) throw Error(field + " \"" + prefix_text + "\" is not an IPv4 prefix");
  const uint64_t network = prefix->network.host_order + static_cast<uint64_t>(slot) * prefix->Size();
  if (network + prefix->Size() > (uint64_t{1} << 32)) {
    throw Error(field + " \"" + prefix_text + "\": job slot " + std::to_string(slot) +
                " would need a subnet past 255.255.255.255 (fewer --jobs or a lower subnet)");
  }
  return FormatIpv4Prefix({Ipv4{static_cast<uint32_t>(network)}, prefix->length});
}

constexpr int kMaxSlots = 1000;  // "sw" + 4 digits + "_" + 3 digits = kMaxScenarioNameLength.
constexpr uint32_t kMaxPort = 65535;

}  // namespace

void IsolateForSlot(int slot, unsigned sweep_id, proto::Scenario* spec) {
  if (slot < 0 || slot >= kMaxSlots) {
    throw Error("job slot " + std::to_string(slot) + ": at most " + std::to_string(kMaxSlots) +
                " runs at once");
  }
  spec->set_name("sw" + std::to_string(sweep_id % 10000) + "_" + std::to_string(slot));
  SITLNET_DEMAND(static_cast<int>(spec->name().size()) <= kMaxScenarioNameLength);
  proto::AddressPlan& addresses = *spec->mutable_addresses();
  // The wlan subnet stays: it exists only inside the robots' own namespaces (docs/nns.md), so
  // runs at once may share it, and a point's capture is the same bytes in every slot.
  addresses.set_ctl_subnet(ShiftedSubnet("addresses.ctl_subnet", addresses.ctl_subnet(), slot));
  const uint32_t port = addresses.physics_port() + static_cast<uint32_t>(slot);
  if (port > kMaxPort) {
    throw Error("addresses.physics_port " + std::to_string(addresses.physics_port()) +
                ": job slot " + std::to_string(slot) + " would need port " +
                std::to_string(port));
  }
  addresses.set_physics_port(port);
}

}  // namespace sitlnet::sweep
