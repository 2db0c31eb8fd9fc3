// What the page shows of the GCS relay's vehicles. Mode numbers are the autopilots' own:
// ArduCopter's COPTER_MODE_GUIDED is 4 (ardupilotmega.xml); PX4's AUTO.LOITER is main mode 4,
// sub mode 3 (px4_custom_mode.h), so custom_mode (3 << 24) | (4 << 16) = 50593792.
#include "view/gcs_vehicles.h"

#include <gtest/gtest.h>

namespace sitlnet::view {
namespace {

// summary.json's gcs_relay as runner/summary.cc writes it (fields the view does not read left out).
constexpr char kSummary[] =
    R"({"scenario":"s","gcs_relay":{"endpoints":"udp:127.0.0.1:14550","from_vehicles":200,)"
    R"("vehicles":[)"
    R"({"system_id":2,"address":"10.77.0.2","robot":"copter","messages":90,"sequence_gaps":10,)"
    R"("heartbeat":{"type":2,"autopilot":3,"base_mode":217,"custom_mode":4,"armed":true}},)"
    R"({"system_id":3,"address":"10.77.0.3","robot":"px4","messages":50,"sequence_gaps":0,)"
    R"("heartbeat":{"type":2,"autopilot":12,"base_mode":29,"custom_mode":50593792,"armed":false}},)"
    R"({"system_id":9,"address":"10.9.9.9","robot":null,"messages":3,"sequence_gaps":1,)"
    R"("heartbeat":null}]}})";

TEST(GcsVehiclesTest, SummaryVehiclesByRobotWithModeArmedAndLoss) {
  const std::vector<GcsVehicle> vehicles =
      GcsVehiclesOfSummary(kSummary, {"station", "copter", "px4"});
  EXPECT_EQ(GcsVehiclesArray(vehicles),
            "[{\"robot\":1,\"system_id\":2,\"mode\":\"GUIDED\",\"armed\":true,\"messages\":90,"
            "\"sequence_gaps\":10,\"loss\":0.1},"
            "{\"robot\":2,\"system_id\":3,\"mode\":\"AUTO.LOITER\",\"armed\":false,\"messages\":50,"
            "\"sequence_gaps\":0,\"loss\":0},"
            "{\"robot\":null,\"system_id\":9,\"mode\":null,\"armed\":null,\"messages\":3,"
            "\"sequence_gaps\":1,\"loss\":0.25}]");
}

TEST(GcsVehiclesTest, ARunWithoutARelayOrASummaryThatIsNotJsonHasNone) {
  EXPECT_TRUE(GcsVehiclesOfSummary(R"({"scenario":"s","gcs_relay":null})", {"a"}).empty());
  EXPECT_TRUE(GcsVehiclesOfSummary(R"({"scenario":"s")", {"a"}).empty());
}

TEST(GcsVehiclesTest, ALiveVehicleOfAnotherAutopilotShowsItsCustomMode) {
  run_formats::LiveVehicle live;
  live.robot = 4;
  live.system_id = 5;
  live.messages = 7;
  live.heartbeat_seen = true;
  live.autopilot = 0;  // MAV_AUTOPILOT_GENERIC: sitlnet's test autopilot
  live.custom_mode = 0;
  live.armed = true;
  EXPECT_EQ(GcsVehiclesArray({GcsVehicleOf(live)}),
            "[{\"robot\":4,\"system_id\":5,\"mode\":\"custom mode 0\",\"armed\":true,"
            "\"messages\":7,\"sequence_gaps\":0,\"loss\":0}]");
  EXPECT_EQ(GcsVehiclesArray({GcsVehicleOf(run_formats::LiveVehicle{})}),
            "[{\"robot\":null,\"system_id\":0,\"mode\":null,\"armed\":null,\"messages\":0,"
            "\"sequence_gaps\":0,\"loss\":null}]");
}

}  // namespace
}  // namespace sitlnet::view
