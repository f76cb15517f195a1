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
#include "rbcp/core/config_fields.h"
#include "rbcp/core/triangle_mesh.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/root_planner/convex_polytope.h"
#include "rbcp/root_planner/double_integrator.h"
#include "rbcp/root_planner/reachability_checker.h"
#include "rbcp/root_planner/root_path.h"
#include "rbcp/root_planner/trunk_shape.h"

namespace rbcp {

class RobotModel;

/// The sampler of the RRT: a point on a contact surface (area-weighted with a probability,
/// otherwise a surface chosen uniformly), raised by the nominal base height plus a uniform offset.
struct RootSamplerConfig {
  double area_weighted_probability = 0.3;
  std::array<double, 2> height_offset = {-0.05, 0.05};  ///< [min, max]
  double zero_velocity_probability = 0.3;
  int attempts = 20;
  int repair_moves = 8;
  double repair_step = 0.03;
  double bounds_margin = 0.5;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("area_weighted_probability", &area_weighted_probability, "", bounds::Closed(0, 1),
             "probability of choosing a contact surface by area (otherwise uniformly among the surfaces)");
    v->Visit("height_offset", &height_offset, "m", bounds::Any(),
             "[min, max] of the uniform offset added to the surface point plus the nominal base height");
    v->Rule("height_offset", height_offset[0] <= height_offset[1], "[min, max] with min <= max",
            "[" + ConfigNumber(height_offset[0]) + ", " + ConfigNumber(height_offset[1]) + "]");
    v->Visit("zero_velocity_probability", &zero_velocity_probability, "", bounds::Closed(0, 1),
             "probability of a sample at rest; otherwise a horizontal velocity of random direction and a speed "
             "uniform in [0, horizontal v_max]");
    v->Visit("attempts", &attempts, "", bounds::AtLeast(1),
             "a sample is redrawn until it satisfies the reachability condition, at most this often");
    v->Visit("repair_moves", &repair_moves, "", bounds::AtLeast(0),
             "an invalid sample is first moved vertically at most this often: up while the trunk collides, down "
             "while a leg reaches no surface");
    v->Visit("repair_step", &repair_step, "m", bounds::Positive(),
             "the first such move; then the bracket between a too-low and a too-high height is halved");
    v->Visit("bounds_margin", &bounds_margin, "m", bounds::NonNegative(),
             "the state space extends this far beyond the surfaces, start and goal");
  }
};

/// Parameters of root planning (config/root_planner.yaml). Frames: base frame x forward, y left,
/// z up; world frame z up.
struct RootPlannerConfig {
  /// Folder of the leg ROMs (LF.obj, RF.obj, LH.obj, RH.obj), as written in the file (relative
  /// to the configuration folder unless absolute), and the shapes read from it.
  std::string rom_folder = "robots/anymal_b_roms";
  std::array<ConvexPolytope, kNumLegs> roms;
  TrunkShapeConfig trunk;
  double surface_depth = 0.005;
  KinodynamicLimits limits{{0.3, 1.0}, {0.3, 5.0}};
  YawModel yaw{0.3};
  double max_yaw_rate = 15.0;
  double time_step = 0.05;
  int validation_substeps = 1;
  RootSamplerConfig sampler;
  int max_iterations = 20000;
  int shortcut_iterations = 500;
  int straighten_iterations = 200;
  double straighten_knot_spacing = 0.5;
  double max_piece_duration = 50.0;
  double max_surface_gap = 0.45;
  /// A root path is a guide for the contact planner. When the contact planner finds no plan
  /// along it (no foothold, or out of its budget), the pipeline (the offline pipeline, and the
  /// root planner process on the contact planner's FAILED status) plans the same request again
  /// with the next guide seed (GuideSeed), at most this many times: per request offline, per
  /// stance the robot waits in for the process.
  int guide_retries = 2;

  template <class Visitor>
  void Serialize(Visitor* v) {
    v->Visit("rom_folder", &rom_folder,
             "folder of the legs' range-of-motion shapes LF.obj, RF.obj, LH.obj, RH.obj (base frame), relative "
             "to the configuration folder unless absolute");
    v->Visit("trunk", &trunk, "the trunk's collision shape: a box with a keel under the belly");
    v->Visit("surface_depth", &surface_depth, "m", bounds::Positive(),
             "contact surfaces become convex prisms this deep below their polygon");
    v->Map("limits", "double-integrator bounds per axis: |v| <= v_max, |a| <= a_max", [this](auto* m) {
      m->Map("horizontal", "x and y", [this](auto* h) {
        h->Visit("v_max", &limits.horizontal.v_max, "m/s", bounds::Positive(), "speed bound");
        h->Visit("a_max", &limits.horizontal.a_max, "m/s^2", bounds::Positive(), "acceleration bound");
      });
      m->Map("vertical", "z (v_max = a_max = 0 keeps the base at the start height)", [this](auto* z) {
        z->Visit("v_max", &limits.vertical.v_max, "m/s", bounds::NonNegative(), "speed bound");
        z->Visit("a_max", &limits.vertical.a_max, "m/s^2", bounds::NonNegative(), "acceleration bound");
        z->Rule("a_max", (limits.vertical.a_max > 0.0) == (limits.vertical.v_max > 0.0),
                "v_max and a_max both > 0 (z moves) or both 0 (z fixed)",
                ConfigNumber(limits.vertical.a_max) + " with v_max " + ConfigNumber(limits.vertical.v_max));
      });
    });
    v->Visit("yaw_blend_speed", &yaw.blend_speed, "m/s", bounds::Positive(),
             "horizontal speed from which the yaw fully follows the velocity; below it the heading is blended "
             "with the yaw the trunk keeps at rest");
    v->Visit("max_yaw_rate", &max_yaw_rate, "rad/s", bounds::Positive(),
             "largest yaw rate along the path, checked between validation samples");
    v->Visit("time_step", &time_step, "s", bounds::Positive(),
             "steered pieces last multiples of it; also the output sampling step");
    v->Visit("validation_substeps", &validation_substeps, "", bounds::AtLeast(1),
             "every piece is validated every time_step / validation_substeps");
    v->Visit("sampler", &sampler, "the RRT's samples");
    v->Visit("max_iterations", &max_iterations, "", bounds::AtLeast(1),
             "the search stops after this many RRT iterations (the path depends only on the inputs and the seed)");
    v->Visit("shortcut_iterations", &shortcut_iterations, "", bounds::AtLeast(0),
             "random-shortcut iterations after a path is found");
    v->Visit("straighten_iterations", &straighten_iterations, "", bounds::AtLeast(0),
             "then horizontal straightening: runs of knots moved onto the straight line between the run's ends");
    v->Visit("straighten_knot_spacing", &straighten_knot_spacing, "s", bounds::Any().AtLeast(time_step, "time_step"),
             "path time between the knots of the straightening");
    v->Visit("max_piece_duration", &max_piece_duration, "s", bounds::Any().Above(time_step, "time_step"),
             "steered pieces longer than this are rejected");
    v->Visit("max_surface_gap", &max_surface_gap, "m", bounds::Positive(),
             "two contact surfaces this close are joined; a goal no chain of joined surfaces reaches from the "
             "start's is answered goal_unreachable before any search");
    v->Visit("guide_retries", &guide_retries, "", bounds::Closed(0, 100),
             "when no contact plan follows a root path, the request is planned again with the next guide seed, at "
             "most this many times");
  }

  /// Reads the keys of config/root_planner.yaml (strict) and the ROMs of rom_folder, resolved
  /// against config_dir when relative. Throws InputError.
  static RootPlannerConfig Load(const YamlMap& map, const std::string& config_dir);
  /// Load() on a file.
  static RootPlannerConfig LoadFile(const std::string& path, const std::string& config_dir);
  /// Throws InputError naming `where` and the first out-of-range key.
  void Validate(const std::string& where = "RootPlannerConfig") const { ValidateConfig(*this, where); }
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
  /// RRT iterations at most, when > 0 and below RootPlannerConfig::max_iterations (which bounds
  /// every query): a caller trying several goals shares one query's iterations among them.
  int max_iterations = 0;
  /// The start is where the robot stands, measured, at rest. The reachability condition is
  /// conservative: a robot stretched over an edge (fore feet on a block, hind feet on the floor)
  /// or standing low can violate it where it stands. Such a start is not refused: the path begins
  /// with a straight joining move, at most kMaxStartJoinM long, to the nearest state where the
  /// condition holds (RootPlanResult::start_join_m). A requested start (false) must satisfy it.
  bool start_is_measured = false;
};

/// The longest joining move from a measured start that violates the reachability condition to
/// the state the search starts from [m] (RootPlanRequest::start_is_measured).
inline constexpr double kMaxStartJoinM = 0.25;

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
  /// Length of the joining move the path begins with from a measured start where the
  /// reachability condition fails [m]; 0 when the path starts with the search's own path.
  double start_join_m = 0.0;
  bool ok() const { return status == RootPlanStatus::kOk; }
};

/// Plans root paths for one robot. Holds no per-terrain state: Plan() builds the reachability
/// checker for the terrain it is given. Thread-compatible (one Plan at a time per instance).
/// Why the robot cannot be planned from where it was measured.
struct MeasuredBaseProblem {
  enum class Kind {
    kNoTerrain,      ///< no terrain under the base
    kInsideTerrain,  ///< the terrain rises above the base, to terrain_top_z
  };
  Kind kind;
  Eigen::Vector3d base_W;      ///< the measured base [m]
  double terrain_top_z = 0.0;  ///< kInsideTerrain: the terrain's height at the base's xy [m]

  /// E.g. "the measured base at (1.00, 0.00, 0.40) is inside the terrain, which rises to z 0.60 there".
  std::string Describe() const;
};

/// RootPlanner::GoalsToward's search.
struct GoalsTowardOptions {
  double spacing_m = 0.1;       ///< candidates on a grid this fine [m]
  double min_progress_m = 0.3;  ///< a candidate at least this much nearer the goal than the start [m]
  double ahead_m = 0.5;         ///< known terrain this far beyond a candidate, towards the goal [m]
  double apart_m = 0.3;         ///< candidates returned at least this far apart [m]
  int max_goals = 4;            ///< candidates returned at most
  int max_evaluations = 2000;   ///< candidates checked at most
  double frontier_m = 0.3;      ///< FrontierGoals: unknown terrain this near a candidate [m]
  double visited_m = 0.5;       ///< FrontierGoals: a candidate at least this far from where the robot waited [m]
  /// The robot's feet at the start lie within this distance of the terrain under its base (the
  /// hips 0.28 m ahead and behind, a foot up to ~0.25 m from below its hip) [m].
  double start_surfaces_m = 0.6;
};

class RootPlanner {
 public:
  /// Throws InputError if the config is out of range (RootPlannerConfig::Problem).
  RootPlanner(const RobotModel& robot, RootPlannerConfig config);

  /// Base position standing on the terrain at xy: the highest terrain point below plus the
  /// robot's nominal base height; nullopt when there is no terrain at xy.
  std::optional<Eigen::Vector3d> StandingPosition(const TriangleMesh& terrain, const Eigen::Vector2d& xy) const;

  /// Why a measured base at `base_W` cannot be planned from, or nullopt when it can: terrain at
  /// its xy rising above the base means the robot is inside it (a box added where it stands, a
  /// terrain that changed under it), and StandingPosition would silently lift it onto the top.
  std::optional<MeasuredBaseProblem> CheckMeasuredBase(const TriangleMesh& terrain, const Eigen::Vector3d& base_W) const;

  /// Plans from the request's start to its goal over `terrain` with the given contact surfaces.
  /// A request with a non-finite number or a time budget <= 0 is answered with kInvalidInput.
  /// Throws InputError for a terrain or surfaces the reachability checker cannot be built on.
  RootPlanResult Plan(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                      const RootPlanRequest& request) const;
  /// Same, from rest at start_W to rest at goal_W.
  RootPlanResult Plan(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                      const Eigen::Vector3d& start_W, double start_yaw, const Eigen::Vector3d& goal_W, double goal_yaw,
                      unsigned seed, double time_budget_s) const;

  /// Where to plan toward on a terrain known only in part (a map that grows as the robot walks):
  /// the goal's standing position first when it satisfies the reachability condition at the
  /// goal's yaw, then standing positions on a grid over the contact surfaces, the nearest to the
  /// goal first, that are at least min_progress_m nearer the goal than the start, have known
  /// terrain ahead_m further towards the goal (the front feet stand ahead of the base), lie
  /// apart_m from those already taken, lie visited_m from every one of `dead_ends` (where the map
  /// showed no way nearer the goal before) and satisfy the condition facing the goal with some
  /// surface in reach joined (a chain of surfaces, each within max_surface_gap of the next) to one
  /// within start_surfaces_m of the terrain under the start: a patch of the map seen beyond a
  /// gap the robot cannot step across is no goal. At most max_goals; empty when nothing
  /// qualifies: the map shows no way on yet.
  std::vector<Eigen::Vector3d> GoalsToward(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                                           const Eigen::Vector2d& start_xy, const Eigen::Vector2d& goal_xy,
                                           double goal_yaw, const GoalsTowardOptions& options,
                                           const std::vector<Eigen::Vector2d>& dead_ends = {}) const;

  /// Where to look on when GoalsToward finds nothing (the known terrain nearer the goal is cut
  /// off: a wall, a dead end): standing positions on the contact surfaces with unknown terrain
  /// within frontier_m (the edge of what the map shows, where the cameras see more), at least
  /// visited_m from every position in `visited` (where the robot has waited already), the
  /// nearest to the goal first, apart_m apart, that satisfy the condition facing the goal. At
  /// most max_goals; empty when nothing qualifies.
  std::vector<Eigen::Vector3d> FrontierGoals(const TriangleMesh& terrain, const std::vector<AffordanceSurface>& surfaces,
                                             const Eigen::Vector2d& goal_xy, const std::vector<Eigen::Vector2d>& visited,
                                             const GoalsTowardOptions& options) const;

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
