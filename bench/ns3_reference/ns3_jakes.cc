// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
// Compiled as C++17: ns-3 3.37's headers do not compile as C++20.
#include "ns3_jakes.h"

#include "ns3/core-module.h"
#include "ns3/jakes-process.h"
#include "ns3/jakes-propagation-loss-model.h"
#include "ns3/mobility-module.h"

using namespace ns3;

std::vector<std::vector<std::complex<double>>> Ns3JakesGains(double doppler_hz, int oscillators,
                                                             int processes, double step_s,
                                                             int steps, uint32_t run) {
  RngSeedManager::SetSeed(1);
  RngSeedManager::SetRun(run);
  const Ptr<JakesPropagationLossModel> model = CreateObject<JakesPropagationLossModel>();
  model->AssignStreams(0);
  std::vector<Ptr<JakesProcess>> jakes;
  for (int k = 0; k < processes; ++k) {
    const Ptr<JakesProcess> process = CreateObjectWithAttributes<JakesProcess>(
        "DopplerFrequencyHz", DoubleValue(doppler_hz), "NumberOfOscillators",
        UintegerValue(oscillators));
    process->SetPropagationLossModel(model);  // Draws its angles, as the model does per pair.
    jakes.push_back(process);
  }
  std::vector<std::vector<std::complex<double>>> gains(processes);
  for (auto& g : gains) g.reserve(steps);
  // GetComplexGain reads Simulator::Now(): sample from events at the sampling instants.
  for (int j = 0; j < steps; ++j) {
    Simulator::Schedule(Seconds(j * step_s), [&jakes, &gains]() {
      for (size_t k = 0; k < jakes.size(); ++k) gains[k].push_back(jakes[k]->GetComplexGain());
    });
  }
  Simulator::Run();
  Simulator::Destroy();
  return gains;
}

bool Ns3JakesIsSymmetric(int pairs, uint32_t run) {
  RngSeedManager::SetSeed(1);
  RngSeedManager::SetRun(run);
  const Ptr<JakesPropagationLossModel> model = CreateObject<JakesPropagationLossModel>();
  model->AssignStreams(0);
  bool symmetric = true;
  std::vector<Ptr<MobilityModel>> nodes;
  for (int i = 0; i < 2 * pairs; ++i) {
    const Ptr<ConstantPositionMobilityModel> m = CreateObject<ConstantPositionMobilityModel>();
    m->SetPosition(Vector(i, 0, 0));
    nodes.push_back(m);
  }
  for (int j = 0; j < 10; ++j) {
    Simulator::Schedule(MilliSeconds(7 * j), [&]() {
      for (int p = 0; p < pairs; ++p) {
        const double ab = model->CalcRxPower(0, nodes[2 * p], nodes[2 * p + 1]);
        const double ba = model->CalcRxPower(0, nodes[2 * p + 1], nodes[2 * p]);
        symmetric = symmetric && ab == ba;
      }
    });
  }
  Simulator::Run();
  Simulator::Destroy();
  return symmetric;
}
