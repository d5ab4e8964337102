// The locked-phase figures of Fig. 5 on signals whose phases are known: u_v(t) = m + a cos(w t +
// phi_v) at the response frequency w = omega_f / 4, with the vertices split over the ranks. One,
// two (pi apart) and four (pi/2 apart) phases must be told apart, the mean taken out, the
// amplitude recovered, and the figures must not depend on how the vertices are split.
#include "pipelines/fem_rd/locked_phase.hpp"

#include "par/comm.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

namespace texsim::pipelines::fem_rd {
namespace {

constexpr double kOmegaF = 1.69, kDt = 0.25;
constexpr std::int64_t kSteps = 400, kVertices = 1200;

/// The figures for u_v(t) = 2 + 0.7 cos(detuning w t + phase(v)) (+ a forcing-frequency
/// ripple), the global vertices split evenly over the ranks.
nlohmann::json figures(const std::function<double(std::int64_t)>& phase, double detuning = 1) {
  const par::Comm comm = par::world();
  const std::int64_t begin = kVertices * comm.rank / comm.size;
  const std::int64_t end = kVertices * (comm.rank + 1) / comm.size;
  LockedPhase locked(kOmegaF, kDt, kSteps, std::int32_t(end - begin));
  std::vector<double> u(std::size_t(end - begin));
  for (std::int64_t step = 0; step < kSteps; ++step) {
    const double t = double(step + 1) * kDt;
    for (std::int64_t v = begin; v < end; ++v)
      u[std::size_t(v - begin)] =
          2 + 0.7 * std::cos(detuning * kOmegaF / 4 * t + phase(v)) + 0.1 * std::cos(kOmegaF * t);
    locked.add(step, u);
  }
  return locked.metrics(comm);
}

TEST(LockedPhase, OneTwoAndFourPhasesAreToldApart) {
  const double pi = std::numbers::pi;
  const auto one = figures([](std::int64_t) { return 0.4; });
  EXPECT_NEAR(one["order_1"].get<double>(), 1.0, 0.02);
  EXPECT_EQ(one["phases"].get<int>(), 1);
  EXPECT_NEAR(one["amplitude_mean"].get<double>(), 0.7, 0.03);

  const auto two = figures([&](std::int64_t v) { return 0.4 + (v % 2) * pi; });
  EXPECT_LT(two["order_1"].get<double>(), 0.05);
  EXPECT_NEAR(two["order_2"].get<double>(), 1.0, 0.02);
  EXPECT_EQ(two["phases"].get<int>(), 2);

  const auto four = figures([&](std::int64_t v) { return 0.4 + double(v % 4) * pi / 2; });
  EXPECT_LT(four["order_1"].get<double>(), 0.05);
  EXPECT_LT(four["order_2"].get<double>(), 0.05);
  EXPECT_NEAR(four["order_4"].get<double>(), 1.0, 0.02);
  EXPECT_EQ(four["phases"].get<int>(), 4);

  EXPECT_NEAR(four["phase_drift_deg"].get<double>(), 0.0, 0.01);
  EXPECT_TRUE(four["locked"].get<bool>());

  // Phases spread evenly round the circle: no order.
  const auto none = figures([&](std::int64_t v) { return 2 * pi * double(v) / kVertices; });
  EXPECT_LT(none["order_4"].get<double>(), 0.05);
  EXPECT_EQ(none["phases"].get<int>(), 0);
}

TEST(LockedPhase, AResponseOffTheQuarterFrequencyDriftsAndIsNotLocked) {
  // 10% fast: the phase advances by 36 degrees a response period, though every vertex shares it.
  const auto drifting = figures([](std::int64_t) { return 0.4; }, 1.1);
  EXPECT_NEAR(drifting["phase_drift_deg"].get<double>(), 36.0, 2.0);
  EXPECT_FALSE(drifting["locked"].get<bool>());
  EXPECT_GT(drifting["order_1"].get<double>(), 0.99);
  EXPECT_EQ(drifting["phases"].get<int>(), 0);
}

TEST(LockedPhase, TheWindowIsTheLastTwoResponsePeriods) {
  const auto window = figures([](std::int64_t) { return 0.0; })["window"];
  const double period = 2 * std::numbers::pi / (kOmegaF / 4);
  EXPECT_NEAR(window[1].get<double>() - window[0].get<double>(), 2 * period, kDt);
  EXPECT_DOUBLE_EQ(window[1].get<double>(), double(kSteps) * kDt);
}

TEST(LockedPhase, FiguresAreTheSameBitsOnAnySplit) {
  // The same signals on 1 and 3 ranks (the two ctests) must give these exact bits: compare with
  // the split-independent reference computed on one rank here.
  const auto split = figures([](std::int64_t v) { return 0.01 * double(v % 97); });
  const par::Comm self{MPI_COMM_SELF, 0, 1};
  LockedPhase whole(kOmegaF, kDt, kSteps, std::int32_t(kVertices));
  std::vector<double> u(kVertices);
  for (std::int64_t step = 0; step < kSteps; ++step) {
    const double t = double(step + 1) * kDt;
    for (std::int64_t v = 0; v < kVertices; ++v)
      u[std::size_t(v)] =
          2 + 0.7 * std::cos(kOmegaF / 4 * t + 0.01 * double(v % 97)) + 0.1 * std::cos(kOmegaF * t);
    whole.add(step, u);
  }
  EXPECT_EQ(split.dump(), whole.metrics(self).dump());
}

} // namespace
} // namespace texsim::pipelines::fem_rd
