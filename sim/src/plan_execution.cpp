#include "rbcp/sim/plan_execution.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/core/pose.h"
#include "rbcp/equilibrium/support_polygon.h"

namespace rbcp::sim {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

double AngleDiff(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * M_PI)); }

}  // namespace

PlanExecution::PlanExecution(const RobotModel& robot, const Scenario& scenario, const SimConfig& sim_config,
                             const ControllerConfig& controller_config, const StanceRules& stance_rules)
    : robot_(robot), config_(sim_config), scenario_(scenario) {
  config_.Validate();
  world_ = std::make_unique<BulletWorld>(robot_, scenario_.terrain, config_.physics);
  controller_ = std::make_unique<PlanController>(robot_, controller_config, stance_rules, &scenario_.terrain_mesh);
}

PlanExecution::~PlanExecution() = default;

void PlanExecution::Reset(const Eigen::Vector3d& base_W, const Eigen::Quaterniond& orientation_W,
                          const JointVector& q) {
  // Lift the robot until its lowest foot sphere is drop_height_m above the terrain under it.
  world_->ResetRobot(base_W, orientation_W, q);
  double lift = -std::numeric_limits<double>::infinity();
  const double r = robot_.FootRadius();
  for (const Eigen::Vector3d& c : world_->FootCentersW()) {
    const std::optional<double> ground = TerrainHeightAt(scenario_.terrain_mesh, c.head<2>());
    if (ground) lift = std::max(lift, *ground - (c.z() - r));
  }
  if (!std::isfinite(lift)) lift = 0.0;
  world_->ResetRobot(base_W + Eigen::Vector3d(0, 0, lift + config_.drop_height_m), orientation_W, q);
  outcome_ = ExecutionOutcome{};
  decided_ = false;
  next_sample_s_ = 0.0;
  foot_frame_W_.fill(std::nullopt);
  slide_W_.fill(Eigen::Vector3d::Zero());
  last_contact_s_.fill(0.0);
  saturated_since_.fill(-1.0);
  touching_.clear();
  controller_ = std::make_unique<PlanController>(robot_, controller_->Config(), controller_->Stance().Rules(),
                                                 &scenario_.terrain_mesh);
  controller_->SetAwaitPlans(await_plans_);
}

void PlanExecution::SetTerrain(std::vector<TerrainElement> terrain) {
  TriangleMesh mesh = BuildTerrainMesh(terrain);  // throws for an invalid element
  world_->SetTerrain(terrain);
  scenario_.terrain = std::move(terrain);
  scenario_.terrain_mesh = std::move(mesh);
  controller_->SetTerrain(&scenario_.terrain_mesh);
}

void PlanExecution::SetAwaitPlans(bool await) {
  await_plans_ = await;
  controller_->SetAwaitPlans(await);
}

bool PlanExecution::CanContinue() const {
  if (!has_plan_) return false;
  const ContactPlan& plan = controller_->Plan();
  return controller_->Status().step + 1 < static_cast<int>(plan.states.size()) || plan.reaches_goal;
}

bool PlanExecution::Awaiting() const {
  if (!await_plans_) return false;
  const ControllerPhase phase = controller_->Status().phase;
  return phase == ControllerPhase::kAwait || (!has_plan_ && phase == ControllerPhase::kHold);
}

void PlanExecution::Start(const ContactPlan& plan) {
  if (plan.states.empty()) throw InputError("simulator: expected a plan with at least one state, got none");
  const WholeBodyState& first = plan.states.front();
  Reset(first.base_position, Eigen::Quaterniond(RotationFromRpy(first.base_rpy)), first.joints);
  GivePlan(plan);
}

void PlanExecution::StandAt(const BaseGoal& pose) {
  const std::optional<double> ground = TerrainHeightAt(scenario_.terrain_mesh, pose.position);
  if (!ground) throw InputError("simulator: no terrain under the start position");
  const Eigen::Vector3d base(pose.position.x(), pose.position.y(), *ground + robot_.NominalBaseHeight());
  Reset(base, Eigen::Quaterniond(Eigen::AngleAxisd(pose.yaw, Eigen::Vector3d::UnitZ())),
        robot_.ReferenceConfiguration());
  has_plan_ = false;
  outcome_.steps_total = 0;
  timeout_s_ = std::numeric_limits<double>::infinity();
}

void PlanExecution::GivePlan(const ContactPlan& plan) {
  // A plan is walked at a few seconds per step: one of thousands of steps would keep the run
  // going for hours of simulated time; it is rejected before the controller takes it.
  if (plan.states.size() > kMaxPlanSteps + 1) {
    throw InputError("simulator: expected a plan of at most " + std::to_string(kMaxPlanSteps) + " steps, got " +
                     std::to_string(plan.states.size() - 1));
  }
  if (decided_) {
    // A new plan after a verdict starts a new judged run from where the robot is.
    decided_ = false;
    outcome_ = ExecutionOutcome{};
    next_sample_s_ = world_->Time();
    saturated_since_.fill(-1.0);
  }
  if (has_plan_) {
    controller_->ReplacePlan(plan);
  } else {
    controller_->StartPlan(plan);
  }
  plan_ = plan;
  has_plan_ = true;
  outcome_.steps_total = static_cast<int>(plan.states.size()) - 1;
  timeout_s_ = world_->Time() + config_.outcome.timeout_base_s + config_.outcome.timeout_per_step_s * outcome_.steps_total;
}

bool PlanExecution::Tick() {
  // After the verdict the world goes on (the controller holds its stance), unjudged.
  const RobotState state = world_->State();
  if (!decided_ && state.t + 1e-12 >= next_sample_s_) {
    Sample(state);
    next_sample_s_ += 1.0 / config_.outcome.trace_rate_hz;
  }
  const JointVector commanded = controller_->Update(state);
  world_->SetJointTorques(commanded);
  for (int i = 0; i < config_.StepsPerTick(); ++i) world_->Step();
  if (decided_) return false;
  if (Awaiting()) timeout_s_ += world_->Time() - state.t;  // waiting for a plan is not walking it
  Judge(world_->State(), commanded);
  return !decided_;
}

const ExecutionOutcome& PlanExecution::Run() {
  while (Tick()) {
  }
  return outcome_;
}

TraceSample MeasuredTraceSample(const RobotModel& robot, const RobotState& state) {
  TraceSample s;
  s.t = state.t;
  s.base_position = state.base_position_W;
  const Eigen::Matrix3d R = state.base_orientation_W.normalized().toRotationMatrix();
  s.base_rpy = RpyFromRotation(R);
  const Eigen::Isometry3d base = Eigen::Translation3d(state.base_position_W) * Eigen::Isometry3d(R);
  const std::array<Eigen::Vector3d, kNumLegs> feet_B = robot.FootPositions(state.q);
  std::vector<Eigen::Vector3d> support;
  for (std::size_t i = 0; i < kNumLegs; ++i) {
    s.feet[i] = base * feet_B[i];
    if (state.foot_contact[i]) support.push_back(s.feet[i]);
  }
  s.contact = state.foot_contact;
  s.joints = state.q;
  s.torques = state.tau;
  if (support.size() >= 3) s.support_margin_m = SupportPolygonMargin(support, base * robot.CenterOfMass(state.q));
  s.cop = MeasuredCentreOfPressure(robot, state).position.head<2>();
  return s;
}

CentreOfPressure MeasuredCentreOfPressure(const RobotModel& robot, const RobotState& state) {
  const Eigen::Isometry3d base = Eigen::Translation3d(state.base_position_W) * state.base_orientation_W.normalized();
  const std::array<Eigen::Vector3d, kNumLegs> feet_B = robot.FootPositions(state.q);
  std::vector<Eigen::Vector3d> feet_W;
  std::vector<double> fz;
  for (std::size_t i = 0; i < kNumLegs; ++i) {
    if (!state.foot_contact[i]) continue;
    feet_W.push_back(base * feet_B[i]);
    fz.push_back(state.foot_force_W[i].z());
  }
  return ComputeCentreOfPressure(feet_W, fz);
}

nlohmann::json TraceSampleToJson(const TraceSample& s) {
  const auto rounded = [](const JointVector& v, double unit) {
    nlohmann::json a = nlohmann::json::array();
    for (int j = 0; j < kNumJoints; ++j) a.push_back(std::round(v[j] / unit) * unit);
    return a;
  };
  nlohmann::json feet = nlohmann::json::array();
  for (Leg leg : kAllLegs) {
    const std::size_t i = static_cast<std::size_t>(Index(leg));
    feet.push_back({{"leg", std::string(LegName(leg))},
                    {"position", {s.feet[i].x(), s.feet[i].y(), s.feet[i].z()}},
                    {"contact", s.contact[i]}});
  }
  const auto xy_or_null = [](const Eigen::Vector2d& v) {
    return v.allFinite() ? nlohmann::json::array({v.x(), v.y()}) : nlohmann::json();
  };
  nlohmann::json j = {{"t", s.t},
                      {"base",
                       {{"position", {s.base_position.x(), s.base_position.y(), s.base_position.z()}},
                        {"rpy", {s.base_rpy.x(), s.base_rpy.y(), s.base_rpy.z()}}}},
                      {"feet", feet},
                      {"joints", rounded(s.joints, 1e-5)},
                      {"torques", rounded(s.torques, 1e-3)},
                      {"support_margin_m", std::isfinite(s.support_margin_m) ? nlohmann::json(s.support_margin_m)
                                                                             : nlohmann::json()},
                      {"com_reference", xy_or_null(s.com_reference)},
                      {"zmp_reference", xy_or_null(s.zmp_reference)},
                      {"cop", xy_or_null(s.cop)}};
  if (s.step >= 0) j["step"] = s.step;
  if (!s.phase.empty()) j["phase"] = s.phase;
  return j;
}

void PlanExecution::Sample(const RobotState& state) {
  TraceSample s = MeasuredTraceSample(robot_, state);
  // The true world's feet: the lowest point of each foot sphere.
  const auto centres = world_->FootCentersW();
  for (std::size_t i = 0; i < centres.size(); ++i) s.feet[i] = centres[i] - Eigen::Vector3d(0, 0, robot_.FootRadius());
  const ControllerStatus& status = controller_->Status();
  s.step = status.step;
  s.phase = ToString(status.phase);
  if (const WalkingPattern* pattern = controller_->Pattern()) {
    s.com_reference = pattern->ComAt(controller_->PatternTime()).position;
    s.zmp_reference = pattern->ZmpReferenceAt(controller_->PatternTime());
  }
  outcome_.trace.push_back(s);
}

ExecutionFailure PlanExecution::Failure(const std::string& what, const std::string& leg,
                                        const std::string& detail) const {
  const ControllerStatus& status = controller_->Status();
  ExecutionFailure f;
  f.what = what;
  f.t = world_->Time();
  f.step = status.step;
  f.leg = leg;
  f.phase = ToString(status.phase);
  f.detail = detail;
  f.should_have_caught = ShouldHaveCaught(f);
  return f;
}

std::string PlanExecution::ShouldHaveCaught(const ExecutionFailure& f) const {
  const ControllerStatus& status = controller_->Status();
  // The phase of the step the failure happened in (StanceChecker::CheckStep's).
  std::optional<StepPhase> phase;
  switch (status.phase) {
    case ControllerPhase::kShift: phase = StepPhase::kShift; break;
    case ControllerPhase::kUnload: phase = StepPhase::kLiftOff; break;
    case ControllerPhase::kSwing:
    case ControllerPhase::kSearch: phase = StepPhase::kSwing; break;
    case ControllerPhase::kLoad: phase = StepPhase::kTouchDown; break;
    default: break;
  }
  if (f.what == "no_ground") phase = StepPhase::kSwing;  // the foot reached down at the end of its swing
  if (!phase) return "";
  const std::string swing_leg = status.swing_leg ? std::string(LegName(*status.swing_leg)) : "";
  const bool of_swing_leg = !swing_leg.empty() && f.leg.rfind(swing_leg, 0) == 0;
  StanceCheck check = StanceCheck::kOk;
  std::string why;
  if (f.what == "torque_saturation") {
    if (*phase == StepPhase::kSwing && of_swing_leg) {
      check = StanceCheck::kSwingBody;
      why = "the swinging leg held against the trunk or the terrain";
    } else {
      check = StanceCheck::kTorque;
    }
  } else if (f.what == "fall") {
    const bool tilt = f.detail.rfind("roll or pitch", 0) == 0;
    check = tilt ? StanceCheck::kSupport
                 : (*phase == StepPhase::kSwing && of_swing_leg ? StanceCheck::kSwingTerrain : StanceCheck::kCollision);
  } else if (f.what == "foot_slip") {
    check = StanceCheck::kBalance;
    why = "the stance's friction";
  } else if (f.what == "no_ground") {
    check = StanceCheck::kReach;
    why = "the foothold is not where the plan has it";
  } else {
    return "";
  }
  std::string out = std::string(ToString(*phase)) + ": " + ToString(check) + (why.empty() ? "" : " (" + why + ")");
  // Where the plan's own step fails the stance rules on the world as it is, say so.
  const ContactPlan& plan = controller_->Plan();
  const int k = status.step;
  if (k >= 1 && k < static_cast<int>(plan.states.size())) {
    const StanceVerdict verdict = controller_->Stance().CheckStep(plan.states[static_cast<std::size_t>(k - 1)],
                                                                   plan.states[static_cast<std::size_t>(k)]);
    if (!verdict.ok()) out += "; the step fails it: " + verdict.Describe();
  }
  return out;
}

void JudgeAgainstGoal(ExecutionOutcome& outcome, const ContactPlan& plan, const BaseGoal& goal, double tolerance_m) {
  if (!outcome.ok() || plan.states.empty()) return;
  const double off = (plan.states.back().base_position.head<2>() - goal.position).norm();
  if (off <= tolerance_m) return;
  ExecutionFailure f;
  f.what = "short_of_goal";
  f.t = outcome.sim_time_s;
  f.step = outcome.steps_total;
  f.detail = "the plan was walked whole, but it ends " + FixedNumber(off, 2) + " m from the scenario's goal (at most " +
             FixedNumber(tolerance_m, 2) + " m)";
  outcome.failure = std::move(f);
  outcome.reached_goal = false;
}

void PlanExecution::Abort(const std::string& what, const std::string& detail) {
  if (!decided_) Decide(Failure(what, "", detail));
}

void PlanExecution::Decide(std::optional<ExecutionFailure> failure) {
  decided_ = true;
  outcome_.failure = std::move(failure);
  outcome_.reached_goal = !outcome_.failure;
  const RobotState state = world_->State();
  outcome_.sim_time_s = state.t;
  const ControllerStatus& status = controller_->Status();
  outcome_.steps_executed = status.steps_done;
  outcome_.early_touchdowns = status.early_touchdowns;
  outcome_.late_touchdowns = status.late_touchdowns;
  if (has_plan_) outcome_.final_base_error_m = (state.base_position_W - plan_.states.back().base_position).norm();
  Sample(state);
}

void PlanExecution::Judge(const RobotState& state, const JointVector& commanded) {
  const ControllerStatus& status = controller_->Status();
  const double limit = robot_.ContinuousTorqueLimit();
  outcome_.max_torque_ratio = std::max(outcome_.max_torque_ratio, state.tau.cwiseAbs().maxCoeff() / limit);
  if (status.phase == ControllerPhase::kSwing) {
    outcome_.min_support_margin_m = std::min(outcome_.min_support_margin_m, status.support_margin_m);
  }
  // The failures in the world, each judged only while the ones before have not happened.
  const std::vector<TerrainContact> contacts = world_->TerrainContacts();
  std::optional<ExecutionFailure> failure = BodyContactFailure(contacts);
  if (!failure && has_plan_) failure = TiltFailure(state, status);
  if (!failure) failure = SlipFailure(state, status, contacts);
  if (!failure) failure = SaturationFailure(state.t, commanded);
  if (failure) {
    Decide(std::move(failure));
    return;
  }
  JudgeEnd(state, status);
}

std::optional<ExecutionFailure> PlanExecution::BodyContactFailure(const std::vector<TerrainContact>& contacts) {
  // The trunk or a thigh on the terrain is a fall; the other links' contacts are collisions,
  // counted once from the tick they start.
  std::map<std::string, bool> touching;
  for (const TerrainContact& c : contacts) {
    if (c.is_foot) continue;
    if (c.link == "base" || EndsWith(c.link, "_THIGH")) {
      return Failure("fall", c.leg ? std::string(LegName(*c.leg)) : "",
                     c.link + " touches the terrain at (" + FixedNumber(c.position_W.x()) + ", " +
                         FixedNumber(c.position_W.y()) + ", " + FixedNumber(c.position_W.z()) + ")");
    }
    touching[c.link] = true;
  }
  for (const auto& [link, on] : touching) {
    if (!touching_.count(link)) {
      outcome_.collisions += 1;
      outcome_.collision_links[link] += 1;
    }
  }
  touching_ = std::move(touching);
  return std::nullopt;
}

std::optional<ExecutionFailure> PlanExecution::TiltFailure(const RobotState& state,
                                                           const ControllerStatus& status) const {
  // Against the plan's states on either side of the step being walked: the tilt from the closer.
  const Eigen::Vector3d rpy = RpyFromRotation(state.base_orientation_W.toRotationMatrix());
  double tilt = std::numeric_limits<double>::infinity();
  for (int k : {status.step - 1, status.step}) {
    if (k < 0 || k >= static_cast<int>(plan_.states.size())) continue;
    const Eigen::Vector3d& planned = plan_.states[static_cast<std::size_t>(k)].base_rpy;
    tilt = std::min(tilt, std::max(AngleDiff(rpy.x(), planned.x()), AngleDiff(rpy.y(), planned.y())));
  }
  if (!std::isfinite(tilt) || tilt <= config_.outcome.max_tilt_rad) return std::nullopt;
  return Failure("fall", "", "roll or pitch " + FixedNumber(tilt) + " rad from the plan's");
}

std::optional<ExecutionFailure> PlanExecution::SlipFailure(const RobotState& state, const ControllerStatus& status,
                                                           const std::vector<TerrainContact>& contacts) {
  // A stance foot in contact does not slide from where it touched down. A foot is a sphere fixed
  // to the shank, so as the trunk moves over it the sphere rolls and its centre moves
  // r * (rotation) without any sliding (0.95 rad of shank rotation, 3 cm, over a long stance);
  // what is measured is the sliding of the contact point: each tick the centre's displacement less
  // the rolling displacement (rotation vector x r n, n the terrain normal), along the terrain. The
  // leg the current step moves is not a stance foot until its step is done (its swing may brush
  // the terrain).
  const double t = state.t;
  const auto frames = world_->FootFramesW();
  std::array<Eigen::Vector3d, kNumLegs> normals;
  normals.fill(Eigen::Vector3d::UnitZ());
  for (const TerrainContact& c : contacts) {
    if (c.is_foot && c.leg) normals[static_cast<std::size_t>(Index(*c.leg))] = c.normal_W;
  }
  for (Leg leg : kAllLegs) {
    const std::size_t i = static_cast<std::size_t>(Index(leg));
    if (status.swing_leg == leg) {
      foot_frame_W_[i].reset();
      continue;
    }
    if (state.foot_contact[i]) {
      last_contact_s_[i] = t;
      if (!foot_frame_W_[i]) {
        slide_W_[i].setZero();
      } else {
        const Eigen::AngleAxisd turn(frames[i].linear() * foot_frame_W_[i]->linear().transpose());
        const Eigen::Vector3d& n = normals[i];
        const Eigen::Vector3d rolled = (turn.angle() * turn.axis()).cross(robot_.FootRadius() * n);
        Eigen::Vector3d slid = frames[i].translation() - foot_frame_W_[i]->translation() - rolled;
        slid -= slid.dot(n) * n;
        slide_W_[i] += slid;
        const double slip = slide_W_[i].norm();
        outcome_.max_slip_m = std::max(outcome_.max_slip_m, slip);
        if (slip > config_.outcome.max_slip_m) {
          return Failure("foot_slip", std::string(LegName(leg)),
                         std::string(LegName(leg)) + " slid " + FixedNumber(slip) + " m from where it touched down");
        }
      }
      foot_frame_W_[i] = frames[i];
    } else if (foot_frame_W_[i] && t - last_contact_s_[i] > config_.outcome.contact_release_s) {
      foot_frame_W_[i].reset();
    }
  }
  return std::nullopt;
}

std::optional<ExecutionFailure> PlanExecution::SaturationFailure(double t, const JointVector& commanded) {
  // Each joint's time at the limit runs from the first tick of its command there.
  const double limit = robot_.ContinuousTorqueLimit();
  for (int j = 0; j < kNumJoints; ++j) {
    const std::size_t k = static_cast<std::size_t>(j);
    if (std::abs(commanded[j]) >= limit - 1e-9) {
      if (saturated_since_[k] < 0.0) saturated_since_[k] = t;
      if (t - saturated_since_[k] > config_.outcome.max_saturation_s) {
        return Failure("torque_saturation", JointName(j),
                       JointName(j) + " held at the " + FixedNumber(limit, 0) + " N m limit for " +
                           FixedNumber(t - saturated_since_[k], 2) + " s");
      }
    } else {
      saturated_since_[k] = -1.0;
    }
  }
  return std::nullopt;
}

void PlanExecution::JudgeEnd(const RobotState& state, const ControllerStatus& status) {
  if (status.phase == ControllerPhase::kFailed) {
    const bool no_ground = status.failure_leg && !state.foot_contact[static_cast<std::size_t>(Index(*status.failure_leg))] &&
                           status.failure.find("no ground") != std::string::npos;
    Decide(Failure(no_ground ? "no_ground" : "controller",
                   status.failure_leg ? std::string(LegName(*status.failure_leg)) : "", status.failure));
    return;
  }
  if (has_plan_ && status.phase == ControllerPhase::kDone) {
    const double error = (state.base_position_W - plan_.states.back().base_position).norm();
    const bool four = std::all_of(state.foot_contact.begin(), state.foot_contact.end(), [](bool c) { return c; });
    if (error <= config_.outcome.goal_tolerance_m && four) {
      Decide(std::nullopt);
    } else {
      Decide(Failure("goal_missed", "",
                     "plan executed, but the base is " + FixedNumber(error) + " m from the final base" +
                         (four ? "" : " and not every foot is on the ground")));
    }
    return;
  }
  if (state.t > timeout_s_) {
    Decide(Failure("timeout", "", "the run outlasted " + FixedNumber(timeout_s_, 1) + " s"));
  }
}

nlohmann::json OutcomeToJson(const ExecutionOutcome& o) {
  nlohmann::json j;
  j["sim_ok"] = o.ok();
  j["reached_goal"] = o.reached_goal;
  j["fell"] = o.fell();
  j["sim_time_s"] = o.sim_time_s;
  if (o.failure) {
    j["failure"] = {{"what", o.failure->what}, {"t", o.failure->t}, {"step", o.failure->step},
                    {"leg", o.failure->leg.empty() ? nlohmann::json() : nlohmann::json(o.failure->leg)},
                    {"phase", o.failure->phase},
                    {"detail", o.failure->detail},
                    {"should_have_caught", o.failure->should_have_caught.empty()
                                               ? nlohmann::json()
                                               : nlohmann::json(o.failure->should_have_caught)}};
  } else {
    j["failure"] = nullptr;
  }
  j["max_torque_ratio"] = o.max_torque_ratio;
  j["collisions"] = o.collisions;
  j["collision_links"] = o.collision_links;
  j["steps_total"] = o.steps_total;
  j["steps_executed"] = o.steps_executed;
  j["early_touchdowns"] = o.early_touchdowns;
  j["late_touchdowns"] = o.late_touchdowns;
  j["final_base_error_m"] = o.final_base_error_m;
  j["max_slip_m"] = o.max_slip_m;
  j["min_support_margin_m"] =
      std::isfinite(o.min_support_margin_m) ? nlohmann::json(o.min_support_margin_m) : nlohmann::json();
  nlohmann::json trace = nlohmann::json::array();
  for (const TraceSample& s : o.trace) trace.push_back(TraceSampleToJson(s));
  j["sim_trace"] = trace;
  return j;
}

void WriteTickCsvHeader(std::ostream& out) {
  out << "t,phase,step,swing_leg,support_margin_m,base_x,base_y,base_z,roll,pitch,yaw,ref_x,ref_y,ref_z";
  for (int j = 0; j < kNumJoints; ++j) out << ",q_" << JointName(j);
  for (int j = 0; j < kNumJoints; ++j) out << ",tau_" << JointName(j);
  for (Leg leg : kAllLegs) out << ",contact_" << LegName(leg);
  for (Leg leg : kAllLegs) out << ",fz_" << LegName(leg);
  out << ",cop_x,cop_y,cop_margin_m,zmp_x,zmp_y,swing_x,swing_y,swing_z,lag_s\n";
}

void WriteTickCsvRow(std::ostream& out, const PlanExecution& execution) {
  const RobotState s = execution.State();
  const ControllerStatus& status = execution.Controller().Status();
  const BaseReference& ref = execution.Controller().Reference();
  const Eigen::Vector3d rpy = RpyFromRotation(s.base_orientation_W.normalized().toRotationMatrix());
  out << FixedNumber(s.t, 4) << ',' << ToString(status.phase) << ',' << status.step << ','
      << (status.swing_leg ? LegName(*status.swing_leg) : "") << ',' << FixedNumber(status.support_margin_m, 4);
  for (int k = 0; k < 3; ++k) out << ',' << FixedNumber(s.base_position_W[k], 4);
  for (int k = 0; k < 3; ++k) out << ',' << FixedNumber(rpy[k], 4);
  for (int k = 0; k < 3; ++k) out << ',' << FixedNumber(ref.position_W[k], 4);
  for (int j = 0; j < kNumJoints; ++j) out << ',' << FixedNumber(s.q[j], 4);
  for (int j = 0; j < kNumJoints; ++j) out << ',' << FixedNumber(s.tau[j], 2);
  for (std::size_t i = 0; i < kNumLegs; ++i) out << ',' << (s.foot_contact[i] ? 1 : 0);
  for (std::size_t i = 0; i < kNumLegs; ++i) out << ',' << FixedNumber(s.foot_force_W[i].z(), 1);
  // The centre of pressure of the vertical foot forces, and how far inside the feet in contact.
  const CentreOfPressure cop = MeasuredCentreOfPressure(execution.Robot(), s);
  out << ',' << FixedNumber(cop.position.x(), 4) << ',' << FixedNumber(cop.position.y(), 4) << ','
      << FixedNumber(cop.margin_m, 4);
  // The ZMP the walking pattern plans now (none in the static crawl).
  const WalkingPattern* pattern = execution.Controller().Pattern();
  const Eigen::Vector2d zmp = pattern != nullptr ? pattern->ZmpAt(execution.Controller().PatternTime())
                                                 : Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  out << ',' << FixedNumber(zmp.x(), 4) << ',' << FixedNumber(zmp.y(), 4);
  // Where the swinging foot is to be now (none with four feet down).
  const bool swinging = status.phase == ControllerPhase::kSwing || status.phase == ControllerPhase::kSearch;
  for (int k = 0; k < 3; ++k) {
    out << ',' << FixedNumber(swinging ? execution.Controller().SwingTarget()[k] : std::numeric_limits<double>::quiet_NaN(), 4);
  }
  out << ',' << FixedNumber(status.lag_s, 3) << '\n';
}

}  // namespace rbcp::sim
