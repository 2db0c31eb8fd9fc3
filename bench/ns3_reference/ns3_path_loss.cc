// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Compiled as C++17: ns-3 3.37's headers do not compile as C++20.
//
// ns-3 3.37's path loss per link, for mac_phy_sim's path-loss models to be
// checked against (mac_phy_sim/test/ns3_path_loss_test.cc reads the CSV).
// Every link is evaluated with every box of the list present as an ns-3
// Building, at 0 dBm transmitted power: the loss is minus the received power.
// "link" rows are one pair (deterministic models); "mean" rows are `pairs`
// independent pairs on the same geometry, each evaluated once (ns-3's
// LOS/NLOSv draw, blockage and shadowing), with the mean and standard
// deviation of their losses. "corr" rows measure the shadowing's correlation
// after a move: `pairs` pairs start with station b at (r, 0, z) from a at the
// origin (r = b's horizontal distance from a), are evaluated there, then b
// moves to the row's position; the row holds the sample correlation of the
// two losses and the standard deviation of the second. ns-3 3.37 stores the
// relative position (0, 0, 0) at a pair's first draw, so the pair is
// evaluated twice at the start and the second value is the one correlated.
// Usage: ns3_path_loss <out.csv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "ns3/buildings-module.h"
#include "ns3/core-module.h"
#include "ns3/mobility-module.h"
#include "ns3/network-module.h"
#include "ns3/propagation-module.h"

using namespace ns3;

namespace {

constexpr double kV2vFrequencyHz = 5.9e9;  // path_loss_frequency_mhz 5900 on mac_phy_sim's side.

struct BoxSpec {
  double cx, cy, cz, sx, sy, sz;
};
// One-box NLOS at y = 0, two boxes in a row at y = 200, and a wall 1 m thick at y = -4000 for
// the NLOS correlation rows; all other links run far from them.
const std::vector<BoxSpec> kBoxes = {{50, 0, 5, 10, 10, 10},
                                     {30, 200, 5, 10, 10, 10},
                                     {70, 200, 5, 10, 10, 10},
                                     {5.5, -4000, 5, 1, 80, 10}};

struct LinkSpec {
  std::string model;  // two_ray, two_ray_h1_l2, v2v_urban, v2v_highway
  Vector a, b;
  bool shadowing;
  int pairs;
};

std::vector<LinkSpec> Links() {
  std::vector<LinkSpec> links;
  // Two-ray: below MinDistance, Friis below the crossover (863 m at 2 m), fourth power beyond.
  for (double d : {0.3, 1.0, 10.0, 100.0, 500.0, 863.0, 900.0, 2000.0}) {
    links.push_back({"two_ray", Vector(0, -1000, 2), Vector(d, -1000, 2), false, 1});
  }
  links.push_back({"two_ray", Vector(0, -1000, 1.5), Vector(50, -1000, 30), false, 1});
  links.push_back({"two_ray", Vector(0, -1000, 1.5), Vector(3000, -1000, 30), false, 1});
  links.push_back({"two_ray", Vector(0, -1000, 0.5), Vector(400, -1000, 0.5), false, 1});
  links.push_back({"two_ray_h1_l2", Vector(0, -1000, 0), Vector(50, -1000, 1), false, 1});
  links.push_back({"two_ray_h1_l2", Vector(0, -1000, 0), Vector(300, -1000, 1), false, 1});
  for (const std::string model : {"v2v_urban", "v2v_highway"}) {
    // Antennas above 1.6 m: NLOSv costs what LOS costs, so the loss is deterministic.
    for (double d : {3.0, 10.0, 50.0, 200.0, 800.0}) {
      links.push_back({model, Vector(0, -500, 2), Vector(d, -500, 2.5), false, 1});
    }
    links.push_back({model, Vector(0, 0, 2), Vector(100, 0, 2), false, 1});     // One box.
    links.push_back({model, Vector(0, 0, 12), Vector(100, 0, 12), false, 1});   // Above it.
    links.push_back({model, Vector(0, 200, 2), Vector(100, 200, 2), false, 1});  // Two boxes.
    links.push_back({model, Vector(0, 0, 2), Vector(100, 0, 20), false, 1});    // Over the top.
    links.push_back({model, Vector(0, 0, 2), Vector(100, 0, 14), false, 1});    // Through the top.
    // Random parts: LOS/NLOSv draw with blockage (antennas below the cars, and one above);
    // shadowing alone (LOS at 3 m, NLOS behind the box).
    links.push_back({model, Vector(0, -300, 1.5), Vector(100, -300, 1.5), false, 4000});
    links.push_back({model, Vector(0, -300, 1.5), Vector(300, -300, 2.0), false, 4000});
    links.push_back({model, Vector(0, -300, 2), Vector(3, -300, 2), true, 4000});
    links.push_back({model, Vector(0, 0, 2), Vector(100, 0, 2), true, 4000});
  }
  return links;
}

// Correlation rows: b moves along a circle around a by a chord of `moved_m`. LOS (a at y =
// -2000; p_LOS = 1 up to 4.28 m urban, 9.75 m highway), or NLOS behind the wall at y = -4000
// (radius 30 m: every chord here keeps the wall across the link; correlation distance 13 m).
struct CorrSpec {
  std::string model;
  double radius_m, moved_m;
  double a_y_m = -2000;
};
const std::vector<CorrSpec> kCorrs = {{"v2v_urban", 4.2, 1},         {"v2v_urban", 4.2, 5},
                                      {"v2v_highway", 9.7, 10},      {"v2v_highway", 9.7, 19},
                                      {"v2v_urban", 30, 2, -4000},   {"v2v_urban", 30, 8, -4000},
                                      {"v2v_highway", 30, 13, -4000}};

Ptr<PropagationLossModel> MakeModel(const std::string& name) {
  if (name == "two_ray" || name == "two_ray_h1_l2") {
    Ptr<TwoRayGroundPropagationLossModel> model = CreateObject<TwoRayGroundPropagationLossModel>();
    if (name == "two_ray_h1_l2") {
      model->SetAttribute("HeightAboveZ", DoubleValue(1));
      model->SetAttribute("SystemLoss", DoubleValue(2));
    }
    return model;
  }
  Ptr<ThreeGppPropagationLossModel> model;
  Ptr<ChannelConditionModel> condition;
  if (name == "v2v_urban") {
    model = CreateObject<ThreeGppV2vUrbanPropagationLossModel>();
    condition = CreateObject<ThreeGppV2vUrbanChannelConditionModel>();
  } else {
    model = CreateObject<ThreeGppV2vHighwayPropagationLossModel>();
    condition = CreateObject<ThreeGppV2vHighwayChannelConditionModel>();
  }
  model->SetAttribute("Frequency", DoubleValue(kV2vFrequencyHz));
  model->SetChannelConditionModel(condition);
  return model;
}

Ptr<MobilityModel> MakeNode(const Vector& position) {
  Ptr<Node> node = CreateObject<Node>();
  Ptr<ConstantPositionMobilityModel> mobility = CreateObject<ConstantPositionMobilityModel>();
  mobility->SetPosition(position);
  node->AggregateObject(mobility);
  BuildingsHelper::Install(node);
  return mobility;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: ns3_path_loss <out.csv>\n";
    return 2;
  }
  for (const BoxSpec& box : kBoxes) {
    Ptr<Building> building = CreateObject<Building>();
    building->SetBoundaries(Box(box.cx - box.sx / 2, box.cx + box.sx / 2, box.cy - box.sy / 2,
                                box.cy + box.sy / 2, box.cz - box.sz / 2, box.cz + box.sz / 2));
  }
  std::ofstream out(argv[1]);
  out << "# ns-3 3.37 (Debian libns3-dev) path loss per link at 0 dBm, written by\n"
         "# bench/ns3_reference/ns3_path_loss; checked by mac_phy_sim/test/ns3_path_loss_test.cc.\n"
         "# box rows: centre (ax, ay, az) and size (bx, by, bz) in m, yaw 0. v2v at 5.9 GHz.\n"
         "# corr rows: b starts at (|b - a| horizontally, a.y, b.z); mean column = correlation.\n";
  out << "kind,model,ax,ay,az,bx,by,bz,shadowing,pairs,ns3_mean_loss_db,ns3_std_loss_db\n";
  for (const BoxSpec& box : kBoxes) {
    out << "box,box," << box.cx << ',' << box.cy << ',' << box.cz << ',' << box.sx << ','
        << box.sy << ',' << box.sz << ",0,0,0,0\n";
  }
  out.precision(10);
  for (const LinkSpec& link : Links()) {
    Ptr<PropagationLossModel> model = MakeModel(link.model);
    if (link.model.rfind("v2v", 0) == 0) {
      model->SetAttribute("ShadowingEnabled", BooleanValue(link.shadowing));
    }
    double sum = 0, sum2 = 0;
    for (int k = 0; k < link.pairs; ++k) {
      const double loss_db = -model->CalcRxPower(0, MakeNode(link.a), MakeNode(link.b));
      sum += loss_db;
      sum2 += loss_db * loss_db;
    }
    const double mean = sum / link.pairs;
    const double std_db = link.pairs > 1 ? std::sqrt(std::max(0.0, sum2 / link.pairs - mean * mean)) : 0;
    out << (link.pairs > 1 ? "mean," : "link,") << link.model << ',' << link.a.x << ','
        << link.a.y << ',' << link.a.z << ',' << link.b.x << ',' << link.b.y << ',' << link.b.z
        << ',' << link.shadowing << ',' << link.pairs << ',' << mean << ',' << std_db << '\n';
  }
  for (const CorrSpec& corr : kCorrs) {
    Ptr<PropagationLossModel> model = MakeModel(corr.model);
    model->SetAttribute("ShadowingEnabled", BooleanValue(true));
    const double angle = 2 * std::asin(corr.moved_m / (2 * corr.radius_m));
    const Vector a(0, corr.a_y_m, 2), start(corr.radius_m, corr.a_y_m, 2);
    const Vector moved(corr.radius_m * std::cos(angle),
                       corr.a_y_m + corr.radius_m * std::sin(angle), 2);
    constexpr int kPairs = 4000;
    double s1 = 0, s2 = 0, s11 = 0, s22 = 0, s12 = 0;
    for (int k = 0; k < kPairs; ++k) {
      Ptr<MobilityModel> from = MakeNode(a), to = MakeNode(start);
      model->CalcRxPower(0, from, to);  // Stores (0, 0, 0) as the relative position.
      const double before = -model->CalcRxPower(0, from, to);
      to->SetPosition(moved);
      const double after = -model->CalcRxPower(0, from, to);
      s1 += before, s2 += after, s11 += before * before, s22 += after * after,
          s12 += before * after;
    }
    const double n = kPairs;
    const double var1 = s11 / n - s1 / n * s1 / n, var2 = s22 / n - s2 / n * s2 / n;
    const double r = (s12 / n - s1 / n * s2 / n) / std::sqrt(var1 * var2);
    out << "corr," << corr.model << ',' << a.x << ',' << a.y << ',' << a.z << ',' << moved.x
        << ',' << moved.y << ',' << moved.z << ",1," << kPairs << ',' << r << ','
        << std::sqrt(var2) << '\n';
  }
  Simulator::Destroy();
  return 0;
}
