// One cell of the ns-3 side-by-side matrix (bench/ns3_reference/) and its
// geometry: which stations exist, where, and which of them send saturated
// traffic to whom. Plain C++17 and the standard library only, because the
// ns-3 half of the benchmark is compiled as C++17 and includes it too.
#ifndef SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CASE_H_
#define SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CASE_H_

#include <cstdint>
#include <string>
#include <vector>

namespace sitlnet::side_by_side {

enum class Standard { kA, kB, kG };
enum class Topology {
  kRing,     // `senders` stations 1 mm apart, i sends to i + 1 (ns-3's Bianchi validation).
  kSink,     // `senders` stations 1 mm apart send to one more, receive-only station.
  kHidden,   // A -> B <- C on a line: A-B `near_m`, B-C `far_m`; A and C out of each other's range.
  kExposed,  // B <- A   C -> D: A-C `far_m` (they hear each other), A-B = C-D = `near_m`.
};

struct Case {
  std::string id;  // Unique, stable: names the CSV row.
  Standard standard = Standard::kA;
  bool short_slot = false;  // 11g only.
  double rate_mbps = 54;
  int senders = 5;
  Topology topology = Topology::kRing;
  int payload_bytes = 1500;          // Ethernet/packet payload; MPDU = payload + 36 bytes.
  uint32_t rts_threshold_bytes = 0;  // 0: no RTS/CTS.
  bool capture = false;              // SimpleFrameCaptureModel, 5 dB margin.
  double near_m = 0, far_m = 0;      // Hidden/exposed geometry.
  double warmup_s = 1, measure_s = 10;
  // Bianchi's assumption for saturation (CW stays at CWmax); otherwise the
  // standard's 7 / 4 attempts.
  bool unlimited_retries = true;
  bool fast = false;  // Part of the subset scripts/test checks against the CSV.
};

struct Point {
  double x = 0, y = 0, z = 0;
};
struct Flow {
  int from = 0, to = 0;
};
struct Layout {
  std::vector<Point> positions;
  std::vector<Flow> flows;
};

inline Layout MakeLayout(const Case& c) {
  Layout layout;
  switch (c.topology) {
    case Topology::kRing:
      for (int i = 0; i < c.senders; ++i) {
        layout.positions.push_back({0.001 * i, 0, 0});
        layout.flows.push_back({i, (i + 1) % c.senders});
      }
      break;
    case Topology::kSink:
      for (int i = 0; i <= c.senders; ++i) layout.positions.push_back({0.001 * i, 0, 0});
      for (int i = 1; i <= c.senders; ++i) layout.flows.push_back({i, 0});
      break;
    case Topology::kHidden:
      layout.positions = {{0, 0, 0}, {c.near_m, 0, 0}, {c.near_m + c.far_m, 0, 0}};
      layout.flows = {{0, 1}, {2, 1}};
      break;
    case Topology::kExposed:
      layout.positions = {{0, 0, 0}, {-c.near_m, 0, 0}, {c.far_m, 0, 0}, {c.far_m + c.near_m, 0, 0}};
      layout.flows = {{0, 1}, {2, 3}};
      break;
  }
  return layout;
}

inline const char* StandardName(Standard s) {
  return s == Standard::kA ? "a" : (s == Standard::kB ? "b" : "g");
}
inline const char* TopologyName(Topology t) {
  switch (t) {
    case Topology::kRing:
      return "ring";
    case Topology::kSink:
      return "sink";
    case Topology::kHidden:
      return "hidden";
    case Topology::kExposed:
      return "exposed";
  }
  return "?";
}

}  // namespace sitlnet::side_by_side

#endif  // SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CASE_H_
