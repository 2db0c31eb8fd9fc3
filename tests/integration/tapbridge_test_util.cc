#include "tests/integration/tapbridge_test_util.h"

#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <fstream>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge::testing {

std::string MissingRoot() {
  if (geteuid() != 0) return "needs root (namespaces, TAP devices): run with sudo";
  if (access("/dev/net/tun", R_OK | W_OK) != 0) return "needs read-write /dev/net/tun";
  return "";
}

MediumScenario::MediumScenario(const std::string& tag, int slot, const std::string& body,
                               const std::string& address_extra) {
  const unsigned pid = static_cast<unsigned>(getpid());
  name_ = "t" + tag.substr(0, 3) + integration_test::Base36(pid) + std::to_string(slot);
  // 10.{240..244} / 10.{250..254}: away from the defaults and other modules' tests.
  const std::string third = std::to_string(pid % 250);
  subnet_prefix_ = "10." + std::to_string(240 + slot) + "." + third + ".";
  dir_ = integration_test::TempDir() + "/" + name_;
  RunCommand({"mkdir", "-p", dir_});
  path_ = dir_ + "/" + name_ + ".textproto";
  std::ofstream(path_) << "name: \"" << name_ << "\"\n"
                       << body << "\naddresses { wlan_subnet: \"" << subnet_prefix_
                       << "0/24\" ctl_subnet: \"10." << 250 + slot << "." << third << ".0/24\" "
                       << address_extra << " }\n";
  const CommandResult up = RunCommand({SitlnetBinary(), "up", path_});
  up_ = true;  // Down also after a partial failure.
  if (up.exit_code != 0) ADD_FAILURE() << "sitlnet up " << path_ << ": " << up.err;
}

MediumScenario::~MediumScenario() {
  if (daemon_) StopDaemon();
  if (up_) {
    const CommandResult down = RunCommand({SitlnetBinary(), "down", name_});
    if (down.exit_code != 0) ADD_FAILURE() << "sitlnet down " << name_ << ": " << down.err;
  }
}

std::string MediumScenario::Address(int index) const {
  return subnet_prefix_ + std::to_string(index + 1);
}

void MediumScenario::StartDaemon(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {SitlnetBinary(), "medium", path_};
  argv.insert(argv.end(), args.begin(), args.end());
  daemon_ = std::make_unique<Child>(argv);
  ASSERT_TRUE(daemon_->WaitForOutput(true, "robots attached", 10 * kNsPerS)) << daemon_->err();
}

std::string MediumScenario::StopDaemon() {
  if (!daemon_) return "";
  kill(daemon_->pid(), SIGTERM);
  const int code = daemon_->Wait(10 * kNsPerS);
  EXPECT_EQ(code, 0) << "medium daemon exit: " << daemon_->err();
  std::string err = daemon_->err();
  daemon_.reset();
  return err;
}

CommandResult MediumScenario::Exec(const std::string& robot, const std::vector<std::string>& argv,
                                   TimeNs timeout_ns) {
  std::vector<std::string> full = {SitlnetBinary(), "exec", Netns(robot), "--"};
  full.insert(full.end(), argv.begin(), argv.end());
  return RunCommand(full, timeout_ns);
}

std::unique_ptr<Child> MediumScenario::Spawn(const std::string& robot,
                                             const std::vector<std::string>& argv) {
  std::vector<std::string> full = {SitlnetBinary(), "exec", Netns(robot), "--"};
  full.insert(full.end(), argv.begin(), argv.end());
  return std::make_unique<Child>(full);
}

proto::MediumStatus MediumScenario::Counters() {
  ControlClient client(ControlSocketPath(name_));
  proto::MediumRequest request;
  request.mutable_get_counters();
  proto::MediumResponse response;
  EXPECT_TRUE(response.ParseFromString(client.Call(request.SerializeAsString())));
  EXPECT_FALSE(response.has_error()) << response.error();
  return response.status();
}

void MediumScenario::SetPosition(const std::string& robot, double x, double y, double z) {
  ControlClient client(ControlSocketPath(name_));
  proto::MediumRequest request;
  proto::RobotPosition* p = request.mutable_set_positions()->add_position();
  p->set_robot(robot);
  p->mutable_position_m()->set_x(x);
  p->mutable_position_m()->set_y(y);
  p->mutable_position_m()->set_z(z);
  proto::MediumResponse response;
  EXPECT_TRUE(response.ParseFromString(client.Call(request.SerializeAsString())));
  EXPECT_FALSE(response.has_error()) << response.error();
}

TimeNs OfdmAirtimeNs(int psdu_bytes, double rate_mbps) {
  const int bits_per_symbol = static_cast<int>(std::lround(4 * rate_mbps));
  const int symbols = (16 + 8 * psdu_bytes + 6 + bits_per_symbol - 1) / bits_per_symbol;
  return (20 + 4 * symbols) * kNsPerUs;
}

double OfdmAckRateMbps(double rate_mbps) {
  double best = 6;
  for (double basic : {6.0, 12.0, 24.0}) {
    if (basic <= rate_mbps) best = basic;
  }
  return best;
}

double OneStationGoodputMbps(int udp_payload_bytes, double rate_mbps) {
  const int ethernet_bytes = udp_payload_bytes + 8 + 20 + 14;  // UDP, IPv4, Ethernet headers
  const double cycle_ns = kOfdmDifsNs + kOfdmCwMin / 2.0 * kOfdmSlotNs +
                          OfdmAirtimeNs(ethernet_bytes + kEthernetToPsduBytes, rate_mbps) +
                          kOfdmSifsNs + OfdmAirtimeNs(kAckBytes, OfdmAckRateMbps(rate_mbps));
  return udp_payload_bytes * 8.0 / cycle_ns * 1e3;
}

}  // namespace sitlnet::tapbridge::testing
