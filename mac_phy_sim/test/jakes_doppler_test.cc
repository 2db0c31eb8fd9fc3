// Doppler from speed against its definition: f_d = sqrt(v_a^2 + v_b^2) / lambda, integrated
// into a phase that grows at 2 pi f_d, frozen for a still pair.
#include "mac_phy_sim/jakes_doppler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sitlnet::mac {
namespace {

constexpr double kWavelengthM = 299792458.0 / 5.18e9;  // 5.79 cm.

TEST(SpeedDopplerTest, DopplerIsTheSpeedsOverTheWavelength) {
  SpeedDoppler doppler(kWavelengthM);
  doppler.AddStation({0, 0, 0}, 0);
  doppler.AddStation({100, 0, 0}, 0);
  doppler.AddStation({0, 100, 0}, 0);
  EXPECT_EQ(doppler.PhaseRad(0, 1, kNsPerS), 0);  // Still: no phase.
  // Station 0 at 3 m/s along x, station 1 at 4 m/s along z, 10 ms steps.
  for (int k = 1; k <= 100; ++k) {
    const TimeNs t = k * 10 * kNsPerMs;
    doppler.Move(0, {3 * (t / 1e9), 0, 0}, t);
    doppler.Move(1, {100, 0, 4 * (t / 1e9)}, t);
  }
  EXPECT_NEAR(doppler.speed_mps(0), 3, 1e-9);
  EXPECT_NEAR(doppler.speed_mps(1), 4, 1e-9);
  EXPECT_NEAR(doppler.DopplerHz(0, 1), 5 / kWavelengthM, 1e-6);  // sqrt(9 + 16).
  EXPECT_NEAR(doppler.DopplerHz(1, 0), 5 / kWavelengthM, 1e-6);
  EXPECT_NEAR(doppler.DopplerHz(0, 2), 3 / kWavelengthM, 1e-6);
  // Between moves the phase grows at 2 pi f_d.
  const TimeNs t0 = kNsPerS;
  const double slope = (doppler.PhaseRad(0, 1, t0 + 5 * kNsPerMs) - doppler.PhaseRad(0, 1, t0)) /
                       5e-3;
  EXPECT_NEAR(slope, 2 * std::numbers::pi * 5 / kWavelengthM, 1e-6 * slope);
  // Over the run it is the integral: 2 pi (5 / lambda) over 0.99 s (the first 10 ms are
  // still: the first move sets the speed), to rounding.
  EXPECT_NEAR(doppler.PhaseRad(0, 1, t0),
              2 * std::numbers::pi * 5 / kWavelengthM * 0.99, 1e-9 * 2 * std::numbers::pi * 86);
}

TEST(SpeedDopplerTest, PhaseIsContinuousWhenTheSpeedChanges) {
  SpeedDoppler doppler(kWavelengthM);
  doppler.AddStation({0, 0, 0}, 0);
  doppler.AddStation({10, 0, 0}, 0);
  doppler.Move(0, {1, 0, 0}, kNsPerS);  // 1 m/s from now on.
  const double before = doppler.PhaseRad(0, 1, 2 * kNsPerS);
  doppler.Move(0, {3, 0, 0}, 2 * kNsPerS);  // 2 m/s from now on.
  EXPECT_NEAR(doppler.PhaseRad(0, 1, 2 * kNsPerS), before, 1e-9);
  EXPECT_NEAR(doppler.PhaseRad(0, 1, 3 * kNsPerS) - before,
              2 * std::numbers::pi * 2 / kWavelengthM, 1e-9);
  doppler.Move(0, {3, 0, 0}, 2 * kNsPerS);  // Same instant: the speed stays.
  EXPECT_NEAR(doppler.speed_mps(0), 2, 1e-12);
}

}  // namespace
}  // namespace sitlnet::mac
