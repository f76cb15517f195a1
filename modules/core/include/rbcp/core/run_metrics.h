#pragma once
/// The figures of a walked run, defined once for every report of them (sim_bench, the bench
/// table).

#include <Eigen/Core>

namespace rbcp {

/// Mean speed of a run [m/s]: the straight line from where the base started to where it ended,
/// horizontally, over the simulated time; 0 for no time.
inline double RunSpeedMps(const Eigen::Vector2d& start_xy, const Eigen::Vector2d& end_xy, double sim_time_s) {
  return sim_time_s > 0.0 ? (end_xy - start_xy).norm() / sim_time_s : 0.0;
}

/// Mean step period of a run [s]: the simulated time over the steps walked; 0 for no step.
inline double StepPeriodS(double sim_time_s, int steps) { return steps > 0 ? sim_time_s / steps : 0.0; }

}  // namespace rbcp
