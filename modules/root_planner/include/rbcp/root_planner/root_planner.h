#pragma once
/// Root (trunk) path planning: a kinodynamic bidirectional RRT (built on OMPL's planner
/// framework) over root position and velocity whose states must satisfy the reachability
/// condition, followed by random-shortcut smoothing and straightening in the horizontal plane
/// (RootPlannerConfig::straighten_iterations).
///
/// States are (position, velocity) of the base in the world frame; yaw follows the horizontal
/// velocity (see YawModel). Trees are extended with the time-optimal double-integrator steering
/// all the way to a sample, keeping the valid prefix (start tree) or suffix (goal tree). Every
/// steered piece lasts a multiple of `time_step` and is validated at every multiple of
/// time_step / validation_substeps, so the states of the final path at every multiple of
/// time_step from its start are states that were validated.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/root_planner/convex_polytope.h"
#include "rbcp/root_planner/double_integrator.h"
#include "rbcp/root_planner/reachability_checker.h"
#include "rbcp/root_planner/root_path.h"
#include "rbcp/root_planner/trunk_shape.h"

namespace rbcp {

class RobotModel;

/// Parameters of root planning (config/root_planner.yaml).
struct RootPlannerConfig {
  /// Folder of the leg ROMs (LF.obj, RF.obj, LH.obj, RH.obj), as written in the file (relative
  /// to the configuration folder unless absolute), and the shapes read from it.
  std::string rom_folder = "robots/anymal_b_roms";
  std::array<ConvexPolytope, kNumLegs> roms;
  TrunkShapeConfig trunk;
  double surface_depth = 0.005;  ///< [m] contact surfaces become prisms this deep

  KinodynamicLimits limits{{0.3, 1.0}, {0.3, 5.0}};
  YawModel yaw{0.3};
  /// [rad/s] the yaw may change by at most this rate times the interval between validation
  /// samples (keeps the trunk from swinging round when it speeds up against its rest yaw).
  double max_yaw_rate = 15.0;

  double time_step = 0.05;       ///< [s] steering durations are multiples of it; output sampling step
  int validation_substeps = 2;   ///< states are validated every time_step / validation_substeps

  /// Sampler: a point on a contact surface (area-weighted with this probability, otherwise a
  /// surface chosen uniformly), raised by the nominal base height plus a uniform offset.
  double area_weighted_probability = 0.3;
  double height_offset_min = -0.05;  ///< [m]
  double height_offset_max = 0.05;   ///< [m]
  /// Probability of a zero sampled velocity; otherwise horizontal velocity with a uniform
  /// direction and a speed uniform in [0, horizontal v_max], vertical velocity zero.
  double zero_velocity_probability = 0.3;
  int sample_attempts = 20;          ///< a sample is redrawn until valid, at most this often
  /// An invalid sample is first moved vertically, at most this often: up while the trunk
  /// collides, down while a leg reaches no surface (first by repair_step [m], then halving).
  int repair_moves = 8;
  double repair_step = 0.03;
  double bounds_margin = 0.5;        ///< [m] the state space extends this far beyond the surfaces

  /// The search stops after this many RRT iterations: with the iteration counts of the smoothing
  /// below, the path depends only on the inputs and the seed, never on the machine's load. The
  /// request's time budget is a safety limit; reaching it is a timeout.
  int max_iterations = 20000;
  int shortcut_iterations = 100;     ///< random-shortcut iterations after a path is found
  /// Horizontal straightening after the shortcuts: runs of knots (every straighten_knot_spacing
  /// [s] of path time) moved onto the straight line between the run's ends, heights and times
  /// kept, while the path stays valid and gets no longer (0: none).
  int straighten_iterations = 0;
  double straighten_knot_spacing = 0.5;  ///< [s]
  double max_piece_duration = 50.0;  ///< [s] longer steered pieces are rejected
  /// [m] two contact surfaces this close are joined (a step bridges the gap); a goal whose
  /// surfaces are joined to none of the start's is answered kGoalUnreachable before any search.
  double max_surface_gap = 0.45;
  /// A root path is a guide for the contact planner. When the contact planner finds no plan
  /// along it (no foothold, or out of its budget), the pipeline (the offline pipeline, and the
  /// root planner process on the contact planner's FAILED status) plans the same request again
  /// with the next guide seed (GuideSeed), at most this many times (0: never): per request
  /// offline, per stance the robot waits in for the process.
  int guide_retries = 2;

  /// Reads the keys of config/root_planner.yaml (strict) and the ROMs of rom_folder, resolved
  /// against config_dir when relative. Throws InputError.
  static RootPlannerConfig Load(const YamlMap& map, const std::string& config_dir);
  /// Load() on a file.
  static RootPlannerConfig LoadFile(const std::string& path, const std::string& config_dir);
  /// The first out-of-range parameter as "'key': expected X, got Y", or empty when valid.
  std::string Problem() const;
};

enum class RootPlanStatus {
  kOk,            ///< a path was found
  kInvalidInput,  ///< the request holds a non-finite number or a time budget <= 0 (reason says which)
  kStartInvalid,  ///< the start state violates the reachability condition (reason says how)
  kGoalInvalid,   ///< the goal state violates it
  /// No chain of contact surfaces, each within max_surface_gap of the next, joins the surfaces
  /// in reach at the start to those in reach at the goal: no footholds lead there.
  kGoalUnreachable,
  kTimeout,       ///< no path within the time budget
};

/// "ok", "invalid_input", "start_invalid", "goal_invalid", "goal_unreachable", "timeout".
std::string ToString(RootPlanStatus status);

/// The seed of a request's k-th guide (root path): k = 0 is the request's own seed; the next
/// ones, planned when no contact plan follows the previous guide (guide_retries), lie far apart
/// so that two requests' guides do not repeat each other.
unsigned GuideSeed(unsigned seed, int k);

/// One planning query. Positions are base positions in the world frame [m]; yaw [rad].
struct RootPlanRequest {
  PointState start;              ///< start position and velocity
  double start_yaw = 0.0;
  Eigen::Vector3d goal = Eigen::Vector3d::Zero();  ///< goal position, reached at rest
  double goal_yaw = 0.0;
  unsigned seed = 1;             ///< same seed and inputs, same path (or a timeout)
  double time_budget_s = 1.0;    ///< wall-clock safety limit of the whole query [s]
};

/// The answer to a query.
struct RootPlanResult {
  RootPlanStatus status = RootPlanStatus::kTimeout;
  std::string reason;                  ///< empty when ok
  RootPath path;                       ///< the smoothed path (empty unless ok)
  std::vector<RootPathSample> samples; ///< the path every time_step, and its end
  double planning_time_s = 0.0;        ///< wall-clock time of the whole query [s]
  double search_time_s = 0.0;          ///< of which the RRT search [s]
  double duration_before_shortcut_s = 0.0;  ///< duration of the RRT path [s]
  int iterations = 0;                  ///< RRT iterations
  int tree_states = 0;                 ///< states in both trees at the end
  long validity_checks = 0;            ///< reachability tests (search, sampling, shortcut)
  bool ok() const { return status == RootPlanStatus::kOk; }
};

/// Plans root paths for one robot. Holds no per-terrain state: Plan() builds the reachability
/// checker for the terrain it is given. Thread-compatible (one Plan at a time per instance).
class RootPlanner {
 public:
  /// Throws InputError if the config is out of range (RootPlannerConfig::Problem).
  RootPlanner(const RobotModel& robot, RootPlannerConfig config);

  /// Base position standing on the terrain at xy: the highest terrain point below plus the
  /// robot's nominal base height; nullopt when there is no terrain at xy.
  std::optional<Eigen::Vector3d> StandingPosition(const TriangleMesh& terrain, const Eigen::Vector2d& xy) const;

  /// Why a measured base at `base_W` cannot be planned from, or empty: terrain at its xy rising
  /// above the base means the robot is inside it (a box added where it stands, a terrain that
  /// changed under it), and StandingPosition would silently lift it onto the top.
  std::string MeasuredBaseProblem(const TriangleMesh& terrain, const Eigen::Vector3d& base_W) const;

  /// Plans from the request's start to its goal over `terrain` with the given contact surfaces.
  /// A request with a non-finite number or a time budget <= 0 is answered with kInvalidInput.
  /// Throws InputError for a terrain or surfaces the reachability checker cannot be built on.
  RootPlanResult Plan(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                      const RootPlanRequest& request) const;
  /// Same, from rest at start_W to rest at goal_W.
  RootPlanResult Plan(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                      const Eigen::Vector3d& start_W, double start_yaw, const Eigen::Vector3d& goal_W, double goal_yaw,
                      unsigned seed, double time_budget_s) const;

  /// A reachability checker for a terrain with this planner's ROMs and trunk shape.
  ReachabilityChecker MakeChecker(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces) const;

  const RootPlannerConfig& config() const { return config_; }
  double NominalBaseHeight() const { return nominal_base_height_; }

 private:
  RootPlannerConfig config_;
  ConvexPolytope trunk_;
  double nominal_base_height_ = 0.0;
};

}  // namespace rbcp
