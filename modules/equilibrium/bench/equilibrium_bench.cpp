// Speed of the static-equilibrium queries on ANYmal-sized stances (30.42 kg, mu 0.5,
// 4 generators per contact). The CoM moves between iterations so every query solves its LP.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>

#include "rbcp/equilibrium/static_equilibrium.h"
#include "rbcp/equilibrium/support_polygon.h"

namespace rbcp {
namespace {

constexpr double kMass = 30.42;

std::vector<ContactPoint> Stance(int feet, double tilt_rad) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-tilt_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const std::vector<Eigen::Vector3d> p = {{0.37, 0.26, 0}, {0.37, -0.26, 0}, {-0.37, -0.26, 0}, {-0.37, 0.26, 0}};
  std::vector<ContactPoint> out;
  for (int i = 0; i < feet; ++i) out.push_back({R * p[static_cast<std::size_t>(i)], R * Eigen::Vector3d::UnitZ()});
  return out;
}

Eigen::Vector3d Com(int i) { return {0.05 * std::sin(0.7 * i), 0.04 * std::cos(0.3 * i), 0.45}; }

void BM_Robustness(benchmark::State& state) {
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  eq.SetContacts(Stance(static_cast<int>(state.range(0)), state.range(1) * M_PI / 180.0));
  int i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(eq.Robustness(Com(i++ % 64)).robustness_N);
}
BENCHMARK(BM_Robustness)->ArgNames({"feet", "tilt_deg"})->Args({4, 0})->Args({3, 0})->Args({4, 20})->Args({3, 20});

// A new stance for every query, as when the contact planner tries foothold candidates.
void BM_RobustnessNewContacts(benchmark::State& state) {
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  const auto stance = Stance(static_cast<int>(state.range(0)), 0.0);
  int i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(eq.Robustness(stance, Com(i++ % 64)).robustness_N);
}
BENCHMARK(BM_RobustnessNewContacts)->ArgNames({"feet"})->Arg(4)->Arg(3);

void BM_DistributeForces(benchmark::State& state) {
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  eq.SetContacts(Stance(static_cast<int>(state.range(0)), state.range(1) * M_PI / 180.0));
  int i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(eq.DistributeForces(Com(i++ % 64)).max_normal_force_N);
}
BENCHMARK(BM_DistributeForces)->ArgNames({"feet", "tilt_deg"})->Args({4, 0})->Args({3, 0})->Args({4, 20});

void BM_SupportPolygonMargin(benchmark::State& state) {
  const auto stance = Stance(static_cast<int>(state.range(0)), 0.0);
  std::vector<Eigen::Vector3d> feet;
  for (const auto& c : stance) feet.push_back(c.position);
  int i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(SupportPolygonMargin(feet, Com(i++ % 64)));
}
BENCHMARK(BM_SupportPolygonMargin)->ArgNames({"feet"})->Arg(4)->Arg(3);

}  // namespace
}  // namespace rbcp
