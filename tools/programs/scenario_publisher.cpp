// scenario_publisher: drives a scenario through the pipeline's processes as the operator does.
// It waits until every process it needs reports on STATUS. Without the simulator it stands in for
// the world and publishes the scenario's terrain on TERRAIN (in parts when large) every period
// while the run lasts; with
// --until sim the simulator (anymal_sim) is the world and publishes it. Then a PLAN_REQUEST from
// the scenario's start to its goal (a random 64-bit id, repeated every second until answered); it
// waits for ROOT_PATH and CONTACT_PLAN carrying that id, checks the plan with
// the plan checker, with --until sim waits for the simulator's verdict on the walked plan, and
// prints a summary. A FAILED status from any process (on an input handled after the start) ends
// the run with the process's name and reason. With --until loop (the replanning loop: anymal_sim
// --replan, contact_planner --horizon-steps K) it follows the run instead: progress every few
// seconds (steps walked, distance to the goal, plans), then the outcome, the replans and their
// latency (from the first ROBOT_STATE of a wait received here to the CONTACT_PLAN answering it);
// a contact planner's FAILED answer only costs a replan, the simulator's verdict ends the run.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/cli/cli.h"
#include "rbcp/nodes/run_record.h"
#include "rbcp/nodes/supervisor_process.h"
#include "rbcp/plan_checker/plan_checker.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/random_id.h"
#include "rbcp/transport/run_loop.h"
#include "rbcp/transport/status_reporter.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"

namespace {

using namespace rbcp;
using Clock = std::chrono::steady_clock;

constexpr int kOk = 0, kPlanningFailed = 1, kNoAnswer = 3;

/// A ROOT_PATH that answers `request`'s question: it ends at the requested goal (the id alone
/// could be another client's).
bool AnswersGoal(const rbcp_msgs::root_path_t& path, const rbcp_msgs::plan_request_t& request) {
  constexpr double kGoalTolerance_m = 0.01;  // the root planner ends its paths at the goal's xy
  if (path.points.empty()) return false;
  // A path towards a goal the map does not show yet (a mapped terrain) ends short of it.
  if (!path.reaches_goal) return true;
  const auto& end = path.points.back().position;
  return std::hypot(end[0] - request.goal_position[0], end[1] - request.goal_position[1]) <= kGoalTolerance_m;
}

/// A message that cannot be decoded is logged and otherwise ignored.
void Malformed(const std::string& why) { std::cerr << "scenario_publisher: " << why << "\n"; }

/// A cloud the terrain mapper rejects (malformed, or one too many between two of its steps) is
/// one cloud less: the map goes on with the next. Said, and no end of a run at any stage.
bool OneCloudLost(const rbcp_msgs::process_status_t& failure) {
  if (failure.process != "terrain_mapper") return false;
  std::cout << "terrain_mapper: " << failure.reason << std::endl;
  return true;
}

/// Every process's STATUS: whether it was heard, its latest result, and failures on inputs it
/// handled after it was first heard (a heartbeat repeats an old result; `handled` tells them apart).
class StatusBoard {
 public:
  StatusBoard(lcm::LCM& lcm, const std::string& channel)
      : subscription_(lcm, channel, [this](const rbcp_msgs::process_status_t& msg) { On(msg); }, Malformed) {}

  bool Heard(const std::string& process) const { return processes_.count(process) > 0; }
  /// The latest OK of the process on an input handled after it was first heard.
  std::optional<rbcp_msgs::process_status_t> NewOk(const std::string& process) const {
    auto it = processes_.find(process);
    if (it == processes_.end() || !it->second.ok) return std::nullopt;
    return it->second.ok;
  }
  /// The oldest failure not yet taken; it stays available as last_failure().
  std::optional<rbcp_msgs::process_status_t> TakeFailure() {
    if (failures_.empty()) return std::nullopt;
    last_failure_ = failures_.front();
    failures_.erase(failures_.begin());
    return last_failure_;
  }
  const std::optional<rbcp_msgs::process_status_t>& last_failure() const { return last_failure_; }
  /// "anymal_sim busy, contact_planner ok (restarted 1x), ...": every process heard, by name.
  std::string States() const {
    std::string out;
    for (const auto& [name, p] : processes_) {
      out += (out.empty() ? "" : ", ") + name + " " + transport::StatusName(p.state);
      if (p.instances > 1) out += " (restarted " + std::to_string(p.instances - 1) + "x)";
    }
    return out;
  }
  /// Supervisor events not yet taken (restarts, processes given up on).
  std::vector<rbcp_msgs::process_status_t> TakeSupervisorEvents() { return std::exchange(supervisor_events_, {}); }

 private:
  struct Process {
    int32_t pid = 0;
    int instances = 1;    ///< a new pid under the same name is a restarted process
    int64_t handled = 0;  ///< inputs handled when last heard
    int8_t state = rbcp_msgs::process_status_t::ALIVE;
    std::optional<rbcp_msgs::process_status_t> ok;
  };
  void On(const rbcp_msgs::process_status_t& status) {
    const rbcp_msgs::process_status_t* msg = &status;
    auto it = processes_.find(msg->process);
    if (it == processes_.end()) {
      Process& p = processes_[msg->process];
      p.pid = msg->pid;
      p.handled = msg->handled;
      p.state = msg->state;
      return;
    }
    it->second.state = msg->state;
    if (msg->pid != it->second.pid) {
      // A restarted process counts its inputs from zero again.
      it->second.pid = msg->pid;
      it->second.instances += 1;
      it->second.handled = 0;
    }
    if (msg->handled <= it->second.handled) return;  // nothing new handled
    if (nodes::IsSupervisorName(msg->process)) {
      it->second.handled = msg->handled;
      supervisor_events_.push_back(*msg);
      return;
    }
    it->second.handled = msg->handled;
    if (msg->state == rbcp_msgs::process_status_t::FAILED) failures_.push_back(*msg);
    if (msg->state == rbcp_msgs::process_status_t::OK) it->second.ok = *msg;
  }
  std::map<std::string, Process> processes_;
  std::vector<rbcp_msgs::process_status_t> failures_;
  std::vector<rbcp_msgs::process_status_t> supervisor_events_;
  std::optional<rbcp_msgs::process_status_t> last_failure_;
  transport::EveryMessage<rbcp_msgs::process_status_t> subscription_;
};

enum class Waited { kDone, kFailed, kTimeout, kStopped };

/// Handles LCM traffic until done() (kDone), a process fails (kFailed, printed), timeout_s
/// passes (kTimeout) or the program is signalled. tick() runs between waits.
Waited WaitUntil(lcm::LCM& lcm, StatusBoard& board, double timeout_s, const std::function<bool()>& done,
                 const std::function<void()>& tick = {}) {
  const auto start = Clock::now();
  while (!transport::StopRequested()) {
    if (done()) return Waited::kDone;
    if (auto f = board.TakeFailure(); f && !OneCloudLost(*f)) {
      std::cerr << "scenario_publisher: " << f->process << " failed: " << f->reason << "\n";
      return Waited::kFailed;
    }
    if (std::chrono::duration<double>(Clock::now() - start).count() > timeout_s) return Waited::kTimeout;
    if (tick) tick();
    lcm.handleTimeout(20);
  }
  return Waited::kStopped;
}

/// Handles LCM traffic for at most timeout_s until done(); failures are left for WaitUntil.
void Pump(lcm::LCM& lcm, double timeout_s, const std::function<bool()>& done) {
  const auto start = Clock::now();
  while (!done() && std::chrono::duration<double>(Clock::now() - start).count() < timeout_s) lcm.handleTimeout(20);
}

/// The replanning loop seen from outside: a RunRecord fed with the receive times here.
class LoopWatch {
 public:
  explicit LoopWatch(lcm::LCM& lcm)
      : start_(Clock::now()),
        states_(lcm, channels::kRobotState, [this](const rbcp_msgs::robot_state_t& msg) { OnState(msg); }, Malformed),
        controller_(lcm, channels::kControllerStatus,
                    [this](const rbcp_msgs::controller_status_t& msg) { record.OnControllerStatus(Now(), msg); },
                    Malformed),
        plans_(lcm, channels::kContactPlan, [this](const rbcp_msgs::contact_plan_t& msg) { OnPlan(msg); }, Malformed) {}
  nodes::RunRecord record;

 private:
  int64_t Now() const {
    return std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start_).count();
  }
  void OnState(const rbcp_msgs::robot_state_t& msg) { record.OnRobotState(Now(), msg); }
  void OnPlan(const rbcp_msgs::contact_plan_t& msg) {
    try {
      record.OnContactPlan(Now(), msg);
    } catch (const InputError& e) {
      std::cerr << "scenario_publisher: malformed CONTACT_PLAN: " << e.what() << "\n";
    }
  }
  Clock::time_point start_;
  transport::EveryMessage<rbcp_msgs::robot_state_t> states_;
  transport::EveryMessage<rbcp_msgs::controller_status_t> controller_;
  transport::EveryMessage<rbcp_msgs::contact_plan_t> plans_;
};

/// --until loop: follows the run until the simulator's verdict, printing progress every 5 s.
class LoopFollower {
 public:
  LoopFollower(lcm::LCM& lcm, StatusBoard& board, LoopWatch& watch, const Scenario& scenario,
               const rbcp_msgs::plan_request_t& request, double run_timeout_s, double first_plan_timeout_s,
               std::string summary)
      : lcm_(lcm),
        board_(board),
        watch_(watch),
        scenario_(scenario),
        request_(request),
        run_timeout_s_(run_timeout_s),
        first_plan_timeout_s_(first_plan_timeout_s),
        summary_(std::move(summary)),
        start_(Clock::now()),
        next_print_(start_ + std::chrono::seconds(5)),
        next_request_(start_ + std::chrono::seconds(1)) {}

  /// Returns the exit status.
  int Run() {
    std::cout << "loop: the robot walks to the goal, replanning at every step" << std::endl;
    while (!transport::StopRequested()) {
      lcm_.handleTimeout(20);
      RepeatRequest();
      if (auto rc = TakeSupervisorEvents()) return *rc;
      if (auto rc = TakeFailures()) return *rc;
      if (const auto ok = board_.NewOk("anymal_sim")) return Finish(kOk, "the robot reached the goal: " + ok->reason);
      if (auto rc = CheckTimeouts()) return *rc;
      PrintProgress();
    }
    return Finish(kNoAnswer, "stopped");
  }

 private:
  double Elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

  /// The goal again every second (same request), for a root planner that restarted since.
  void RepeatRequest() {
    if (Clock::now() < next_request_) return;
    next_request_ += std::chrono::seconds(1);
    lcm_.publish(channels::kPlanRequest, &request_);
  }

  /// The supervisor's restarts are counted; a process it gave up on ends the run.
  std::optional<int> TakeSupervisorEvents() {
    for (const auto& e : board_.TakeSupervisorEvents()) {
      std::cout << e.process << ": " << e.reason << std::endl;
      if (e.state == rbcp_msgs::process_status_t::FAILED) return Finish(kPlanningFailed, e.process + ": " + e.reason);
      if (e.reason.find(" restarted (pid ") != std::string::npos) restarts_ += 1;
    }
    return std::nullopt;
  }

  /// A contact planner's failure costs a replan, and so does a root planner's (its new path from
  /// where the robot stands: the robot goes on along the previous one); a cloud the terrain
  /// mapper rejects is one cloud less; another process's failure ends the run.
  std::optional<int> TakeFailures() {
    while (auto f = board_.TakeFailure()) {
      if (f->process == "contact_planner") {
        planner_failures_ += 1;
        std::cout << "contact_planner: no plan for this step boundary: " << f->reason << std::endl;
        continue;
      }
      if (f->process == "root_planner") {
        planner_failures_ += 1;
        std::cout << "root_planner: no new root path from where the robot stands: " << f->reason << std::endl;
        continue;
      }
      if (OneCloudLost(*f)) continue;
      std::cout << f->process << ": FAILED: " << f->reason << std::endl;
      return Finish(kPlanningFailed, f->process == "anymal_sim" ? "the robot did not reach the goal: " + f->reason
                                                                 : f->process + " failed: " + f->reason);
    }
    return std::nullopt;
  }

  std::optional<int> CheckTimeouts() {
    // No plan and no answer at all: the pipeline is not in the loop's mode. A contact planner that
    // answers FAILED is in it (the root planner then plans the next guide, the robot asks again).
    if (watch_.record.Plans() == 0 && planner_failures_ == 0 && Elapsed() > first_plan_timeout_s_) {
      std::cerr << "scenario_publisher: no CONTACT_PLAN within " << first_plan_timeout_s_
                << " s: is contact_planner running with --horizon-steps, and anymal_sim with --replan?\n";
      return Finish(kNoAnswer, "no CONTACT_PLAN from contact_planner");
    }
    if (Elapsed() > run_timeout_s_) return Finish(kNoAnswer, "no verdict within " + FixedNumber(run_timeout_s_, 0) + " s");
    return std::nullopt;
  }

  void PrintProgress() {
    if (Clock::now() < next_print_ || !watch_.record.Latest()) return;
    next_print_ += std::chrono::seconds(5);
    const auto& s = *watch_.record.Latest();
    const auto& c = watch_.record.LatestController();
    const double dx = s.base_position[0] - scenario_.goal.position.x(), dy = s.base_position[1] - scenario_.goal.position.y();
    std::cout << "loop: " << FixedNumber(static_cast<double>(s.utime) * 1e-6, 1) << " s simulated, "
              << (c ? c->steps_done : 0) << " steps, " << FixedNumber(std::hypot(dx, dy), 2) << " m to the goal, "
              << watch_.record.Plans() << " plans" << (c && c->awaiting_plan ? ", waiting for a plan" : "") << "; "
              << board_.States() << std::endl;
  }

  /// Prints the summary line with the outcome; returns rc.
  int Finish(int rc, const std::string& outcome) const {
    const auto& s = watch_.record.Latest();
    const auto& c = watch_.record.LatestController();
    std::ostringstream os;
    os << summary_ << ", " << outcome << "; " << (s ? FixedNumber(static_cast<double>(s->utime) * 1e-6, 1) : "0")
       << " s simulated in " << FixedNumber(Elapsed(), 1) << " s wall, " << (c ? c->steps_done : 0) << " steps, "
       << watch_.record.Plans() << " plans (" << planner_failures_ << " failed replans), " << restarts_
       << " process restarts, replanning latency median "
       << FixedNumber(nodes::Percentile(watch_.record.LatenciesMs(), 0.5), 1) << " ms, 95th percentile "
       << FixedNumber(nodes::Percentile(watch_.record.LatenciesMs(), 0.95), 1) << " ms, walking after "
       << FixedNumber(watch_.record.StartupWallS(), 1) << " s of start-up, waited for plans "
       << FixedNumber(100.0 * watch_.record.WaitingShare(), 1) << " % of the walk";
    std::cout << os.str() << std::endl;
    return rc;
  }

  lcm::LCM& lcm_;
  StatusBoard& board_;
  LoopWatch& watch_;
  const Scenario& scenario_;
  const rbcp_msgs::plan_request_t& request_;
  double run_timeout_s_;
  double first_plan_timeout_s_;
  std::string summary_;
  Clock::time_point start_;
  Clock::time_point next_print_;
  Clock::time_point next_request_;
  int restarts_ = 0;
  int planner_failures_ = 0;
};

void PrintSurfaces(const Scenario& scenario, const std::vector<AffordanceSurface>& surfaces, double extract_ms) {
  double area = 0.0;
  for (const auto& s : surfaces) area += s.area;
  std::cout << "scenario " << scenario.name << ": " << scenario.terrain_mesh.NumTriangles()
            << " terrain triangles published on TERRAIN\n"
            << "affordance_extractor: " << surfaces.size() << " contact surfaces (" << area << " m^2) on AFFORDANCES";
  if (extract_ms >= 0.0) std::cout << ", extracted in " << extract_ms << " ms";
  std::cout << "\n";
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const auto& s = surfaces[i];
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& v : s.vertices) c += v / static_cast<double>(s.vertices.size());
    std::printf("  surface %2zu: %zu vertices, area %.4f m^2, centre (%.3f, %.3f, %.3f), slope %.1f deg\n", i,
                s.vertices.size(), s.area, c.x(), c.y(), c.z(), std::acos(std::min(1.0, s.normal.z())) * 180.0 / M_PI);
  }
  std::fflush(stdout);
}

/// The command line.
struct Options {
  cli::CommonOptions common;
  std::string scenario_path;
  std::string until = "contact";  ///< the last answer to wait for
  double timeout_s = 10.0;
  double period_s = 1.0;
  double budget_s = 5.0;
  double sim_timeout_s = 900.0;
  int seed = 1;
  int64_t request_id = 0;
};

void AddOptions(CLI::App& app, Options& o) {
  cli::AddCommonOptions(app, o.common);
  app.add_option("--scenario", o.scenario_path, "scenario YAML")->required()->check(CLI::ExistingFile);
  app.add_option("--request-id", o.request_id,
                 "id of the plan request; 0 (default): a random 64-bit id, so that no other client's request or "
                 "answer is taken for this run's")
      ->capture_default_str();
  app.add_option("--until", o.until,
                 "last answer to wait for: affordance, root, contact, sim (one plan walked whole) or loop (the "
                 "replanning loop walks to the goal)")
      ->capture_default_str()->check(CLI::IsMember({"affordance", "root", "contact", "sim", "loop"}));
  app.add_option("--sim-timeout", o.sim_timeout_s, "with --until sim: give up after this many seconds of walking")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--timeout", o.timeout_s, "give up after this many seconds without the awaited answer")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--period", o.period_s, "without the simulator: publish the terrain this often while the run lasts [s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--time-budget", o.budget_s, "root planning time budget of the request [s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--seed", o.seed, "random seed of the request")->capture_default_str();
  app.description(
      "Drives a scenario through the pipeline's processes: TERRAIN -> AFFORDANCES, then a PLAN_REQUEST\n"
      "from the scenario's start to its goal -> ROOT_PATH -> CONTACT_PLAN; checks the plan and prints a\n"
      "summary; with --until sim the simulator (anymal_sim) publishes the terrain, walks the plan and reports\n"
      "the outcome. Exit status: 0 answered (the plan passes the checker and, with --until sim, the robot\n"
      "reached the goal), 1 a process failed, the plan fails the checker or the run failed, 2 bad input,\n"
      "3 no answer in time.");
}

/// TERRAIN, from the simulator or, without it, from here: every period while the run lasts, as
/// the simulator sends it, so a process that lost it hears it again (a large terrain goes in
/// parts, on TERRAIN/PART).
class TerrainSender {
 public:
  TerrainSender(lcm::LCM& lcm, const Scenario& scenario, bool simulated, double period_s)
      : simulated_(simulated), period_s_(period_s), next_(Clock::now()), publisher_(lcm) {
    if (!simulated_) msg_ = transport::ToTerrainMsg(scenario.terrain_mesh, utime_, scenario.name);
  }

  /// Sends the terrain when it is due (never with the simulator); a new problem is said on stderr.
  void Tick() {
    if (simulated_ || Clock::now() < next_) return;
    msg_.utime = utime_;
    const std::string problem = publisher_.Publish(channels::kTerrain, msg_);
    if (!problem.empty() && problem != problem_) std::cerr << "scenario_publisher: " << problem << "\n";
    problem_ = problem;
    utime_ += static_cast<int64_t>(period_s_ * 1e6);
    next_ = Clock::now() + std::chrono::milliseconds(static_cast<int>(period_s_ * 1000));
  }

  /// Prints what is sent from here (nothing with the simulator).
  void Print() const {
    if (simulated_) return;
    std::cout << "terrain: " << msg_.num_triangles << " triangles, "
              << FixedNumber(msg_.getEncodedSize() / (1024.0 * 1024.0), 1) << " MB on " << channels::kTerrain;
    if (publisher_.parted_messages() > 0) {
      std::cout << " in " << publisher_.parts_sent() << " parts (" << transport::PartChannel(channels::kTerrain) << ")";
    }
    std::cout << ", every " << period_s_ << " s" << std::endl;
  }

  /// "" or why the last terrain could not be sent.
  const std::string& problem() const { return problem_; }
  /// The simulated time of the next terrain sent from here [us] (0 with the simulator).
  int64_t utime() const { return utime_; }

 private:
  bool simulated_;
  double period_s_;
  int64_t utime_ = 0;
  Clock::time_point next_;
  transport::MessagePublisher publisher_;
  rbcp_msgs::terrain_mesh_t msg_;
  std::string problem_;
};

/// One run of the scenario through the pipeline, step by step. A step returns nothing to go on,
/// or the exit status the run ends with (after the summary line).
class ScenarioRun {
 public:
  ScenarioRun(const Options& o, const Scenario& scenario)
      : o_(o),
        scenario_(scenario),
        loop_(o.until == "loop"),
        simulated_(o.until == "sim" || loop_),
        lcm_(transport::OpenLcm(o.common.lcm_url)),
        board_(*lcm_, channels::kStatus),
        affordances_(*lcm_, channels::kAffordances),
        root_path_(*lcm_, channels::kRootPath),
        contact_plan_(*lcm_, channels::kContactPlan),
        summary_("summary: " + scenario.name) {
    transport::InstallStopHandlers();
    if (loop_) watch_.emplace(*lcm_);
  }

  int Run() {
    if (auto rc = AwaitProcesses()) return *rc;
    if (auto rc = SendTerrain()) return *rc;
    if (auto rc = AwaitSurfaces()) return *rc;
    if (o_.until == "affordance") return Finish(kOk, "");
    SendRequest();
    if (auto rc = AwaitRootPath()) return *rc;
    if (o_.until == "root") return Finish(kOk, "");
    if (loop_) {
      return LoopFollower(*lcm_, board_, *watch_, scenario_, request_, o_.sim_timeout_s, o_.timeout_s, summary_).Run();
    }
    if (auto rc = AwaitContactPlan()) return *rc;
    if (auto rc = CheckPlan()) return *rc;
    return AwaitWalk();
  }

 private:
  using Step = std::optional<int>;

  int Finish(int rc, const std::string& last) {
    std::cout << summary_ << (last.empty() ? "" : ", ") << last << std::endl;
    return rc;
  }
  int NoAnswer(const std::string& what, const std::string& process) {
    std::cerr << "scenario_publisher: no " << what << " within " << o_.timeout_s << " s: is " << process
              << " running on this LCM URL?\n";
    return Finish(kNoAnswer, "no " + what + " from " + process);
  }
  int StoppedOrFailed(Waited w, const std::string& stage) {
    if (w != Waited::kFailed) return Finish(kNoAnswer, "stopped during " + stage);
    const auto& f = *board_.last_failure();
    return Finish(kPlanningFailed, stage + " failed: " + f.process + ": " + f.reason);
  }
  /// The end of a wait for `what` from `process` during `stage`: nothing when it came.
  Step AfterWait(Waited w, const std::string& what, const std::string& process, const std::string& stage) {
    if (w == Waited::kTimeout) return NoAnswer(what, process);
    if (w != Waited::kDone) return StoppedOrFailed(w, stage);
    return std::nullopt;
  }

  /// Every process is up: nothing published before would reach it.
  Step AwaitProcesses() {
    std::vector<std::string> processes = {"affordance_extractor"};
    if (o_.until != "affordance") processes.push_back("root_planner");
    if (o_.until == "contact" || simulated_) processes.push_back("contact_planner");
    if (simulated_) processes.push_back("anymal_sim");
    for (const auto& process : processes) {
      const Waited w = WaitUntil(*lcm_, board_, o_.timeout_s, [&] { return board_.Heard(process); });
      if (auto rc = AfterWait(w, "STATUS", process, "startup")) return rc;
    }
    return std::nullopt;
  }

  Step SendTerrain() {
    terrain_.emplace(*lcm_, scenario_, simulated_, o_.period_s);
    terrain_->Tick();
    if (!terrain_->problem().empty()) return Finish(kPlanningFailed, "the terrain cannot be sent: " + terrain_->problem());
    terrain_->Print();
    return std::nullopt;
  }

  Step AwaitSurfaces() {
    std::optional<rbcp_msgs::affordance_set_t> surfaces_msg;
    const Waited w = WaitUntil(
        *lcm_, board_, o_.timeout_s, [&] { return (surfaces_msg = affordances_.Take()).has_value(); },
        [&] { terrain_->Tick(); });
    if (auto rc = AfterWait(w, "AFFORDANCES", "affordance_extractor", "affordance extraction")) return rc;
    // The extractor's OK status follows its AFFORDANCES.
    Pump(*lcm_, 0.2, [&] { return board_.NewOk("affordance_extractor").has_value(); });
    const auto extracted = board_.NewOk("affordance_extractor");
    const auto surfaces = transport::FromAffordanceMsg(*surfaces_msg);
    PrintSurfaces(scenario_, surfaces, extracted ? extracted->compute_ms : -1.0);
    summary_ += ": " + std::to_string(surfaces.size()) + " surfaces";
    return std::nullopt;
  }

  /// PLAN_REQUEST from the scenario's start to its goal.
  void SendRequest() {
    request_.utime = terrain_->utime();
    request_.request_id = o_.request_id != 0 ? o_.request_id : transport::RandomId();
    request_.use_start = true;
    request_.start_position[0] = scenario_.start.position.x();
    request_.start_position[1] = scenario_.start.position.y();
    request_.start_yaw = scenario_.start.yaw;
    request_.goal_position[0] = scenario_.goal.position.x();
    request_.goal_position[1] = scenario_.goal.position.y();
    request_.goal_yaw = scenario_.goal.yaw;
    request_.time_budget = o_.budget_s;
    request_.seed = o_.seed;
    lcm_->publish(channels::kPlanRequest, &request_);
    next_request_ = Clock::now() + std::chrono::seconds(1);
    std::cout << "plan request " << request_.request_id << " on PLAN_REQUEST: (" << request_.start_position[0] << ", "
              << request_.start_position[1] << ") -> (" << request_.goal_position[0] << ", "
              << request_.goal_position[1] << "), seed " << o_.seed << "\n";
  }

  /// The request again every second until it is answered: an answer lost on the way (or a
  /// request lost) costs a second, not the run; a repeat is answered with the same answer.
  void RepeatRequest() {
    terrain_->Tick();
    if (Clock::now() < next_request_) return;
    next_request_ = Clock::now() + std::chrono::seconds(1);
    lcm_->publish(channels::kPlanRequest, &request_);
  }

  /// ROOT_PATH answering the request.
  Step AwaitRootPath() {
    const Waited w = WaitUntil(
        *lcm_, board_, o_.timeout_s,
        [&] {
          auto p = root_path_.Take();
          if (p && p->request_id == request_.request_id && AnswersGoal(*p, request_)) path_ = std::move(p);
          return path_.has_value();
        },
        [&] { RepeatRequest(); });
    if (auto rc = AfterWait(w, "ROOT_PATH", "root_planner", "root planning")) return rc;
    Pump(*lcm_, 0.2, [&] { return board_.NewOk("root_planner").has_value(); });
    const double duration_s = path_->points.empty() ? 0.0 : path_->points.back().t - path_->points.front().t;
    const auto root_ok = board_.NewOk("root_planner");
    std::cout << "root_planner: path of " << FixedNumber(duration_s, 2) << " s (" << path_->num_points
              << " points) on ROOT_PATH";
    if (root_ok) std::cout << ", planned in " << FixedNumber(root_ok->compute_ms, 1) << " ms";
    std::cout << "\n";
    summary_ += ", root path of " + FixedNumber(duration_s, 2) + " s" +
                (root_ok ? " in " + FixedNumber(root_ok->compute_ms, 1) + " ms" : std::string());
    return std::nullopt;
  }

  /// CONTACT_PLAN along the path.
  Step AwaitContactPlan() {
    const Waited w = WaitUntil(
        *lcm_, board_, o_.timeout_s,
        [&] {
          auto p = contact_plan_.Take();
          // The plan of this request, made on the terrain its root path was planned on.
          if (p && p->request_id == request_.request_id && p->terrain_id == path_->terrain_id) plan_msg_ = std::move(p);
          return plan_msg_.has_value();
        },
        [&] { RepeatRequest(); });
    if (auto rc = AfterWait(w, "CONTACT_PLAN", "contact_planner", "contact planning")) return rc;
    Pump(*lcm_, 0.2, [&] { return board_.NewOk("contact_planner").has_value(); });
    const auto contact_ok = board_.NewOk("contact_planner");
    const int steps = std::max(0, plan_msg_->num_states - 1);
    std::cout << "contact_planner: " << plan_msg_->num_states << " states on CONTACT_PLAN";
    if (contact_ok) std::cout << ": " << contact_ok->reason << " (" << FixedNumber(contact_ok->compute_ms, 1) << " ms)";
    std::cout << "\n";
    summary_ += ", " + std::to_string(steps) + " contact steps" +
                (contact_ok ? " in " + FixedNumber(contact_ok->compute_ms, 1) + " ms" : std::string());
    return std::nullopt;
  }

  /// The independent check of the plan; without the simulator it ends the run.
  Step CheckPlan() {
    try {
      const PlanCheckReport report =
          CheckPlanForScenario(o_.common.config_dir, scenario_, transport::FromContactPlanMsg(*plan_msg_));
      for (const auto& v : report.violations) std::cout << "  state " << v.state << ": " << v.check << ": " << v.detail << "\n";
      std::cout << "plan check: " << report.Summary() << "\n";
      summary_ += report.ok ? ", the plan passes the checker" : ", the plan does not pass the checker";
      if (!simulated_) return Finish(report.ok ? kOk : kPlanningFailed, "");
    } catch (const InputError& e) {
      std::cout << "plan check: cannot check the plan: " << e.what() << "\n";
      return Finish(kPlanningFailed, "the plan cannot be checked");
    }
    return std::nullopt;
  }

  /// The simulator walks the plan and judges the run.
  int AwaitWalk() {
    std::cout << "anymal_sim: walking the plan ..." << std::endl;
    const auto walk_start = Clock::now();
    const Waited w = WaitUntil(*lcm_, board_, o_.sim_timeout_s, [&] { return board_.NewOk("anymal_sim").has_value(); });
    const double walk_s = std::chrono::duration<double>(Clock::now() - walk_start).count();
    if (w == Waited::kTimeout) return NoAnswer("outcome", "anymal_sim");
    if (w == Waited::kFailed && board_.last_failure()->process == "anymal_sim") {
      std::cout << "anymal_sim: FAILED: " << board_.last_failure()->reason << "\n";
      return Finish(kPlanningFailed, "the robot did not reach the goal: " + board_.last_failure()->reason);
    }
    if (w != Waited::kDone) return StoppedOrFailed(w, "execution");
    const auto walked = board_.NewOk("anymal_sim");
    std::cout << "anymal_sim: " << walked->reason << " (" << FixedNumber(walk_s, 1) << " s wall)\n";
    return Finish(kOk, "the robot walked the plan: " + walked->reason);
  }

  const Options& o_;
  const Scenario& scenario_;
  const bool loop_;       ///< --until loop: the replanning loop walks to the goal
  const bool simulated_;  ///< the simulator is the world
  std::unique_ptr<lcm::LCM> lcm_;
  StatusBoard board_;
  transport::LatestMessage<rbcp_msgs::affordance_set_t> affordances_;
  transport::LatestMessage<rbcp_msgs::root_path_t> root_path_;
  transport::LatestMessage<rbcp_msgs::contact_plan_t> contact_plan_;
  std::optional<LoopWatch> watch_;
  std::optional<TerrainSender> terrain_;
  std::string summary_;  ///< the summary line so far
  rbcp_msgs::plan_request_t request_{};
  Clock::time_point next_request_;
  std::optional<rbcp_msgs::root_path_t> path_;
  std::optional<rbcp_msgs::contact_plan_t> plan_msg_;
};

int Run(const Options& o) {
  const Scenario scenario = LoadScenario(o.scenario_path);
  return ScenarioRun(o, scenario).Run();
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("scenario_publisher", argc, argv, AddOptions, Run); }
