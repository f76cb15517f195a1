// replay_log: replays the world's side of a recorded run (the simulator's TERRAIN and ROBOT_STATE,
// the operator's and the simulator's PLAN_REQUEST) into running planner processes
// (affordance_extractor, root_planner, contact_planner --horizon-steps K, as the run had them) and
// checks that they answer as they did in the recording: the same contact surfaces, root paths and
// contact plans, within a numerical tolerance.
//
// The rule (what is deterministic given the inputs, and what is not):
//  * Inputs go out in the recorded order, at the recorded pace (the log's receive times).
//  * Where the recording holds a planner's answer with new content (a CONTACT_PLAN answering a
//    wait of the robot, or the contact planner's FAILED answer to one; a ROOT_PATH or AFFORDANCES
//    that differs from the one before), the replay waits until the replayed planner has given
//    that answer before it sends the next input, and shifts its clock by the wait. The simulator
//    stood still while the robot waited for its plan, so its later messages depended on that
//    answer; waiting keeps the planners' inputs in the recorded causal order however fast they
//    plan on this machine. Meanwhile a waiting robot's state goes out again every 5 ms, as the
//    simulator repeats it (a planner busy planning ahead may lose the first one).
//  * Answers are compared per input, never by arrival time: each CONTACT_PLAN by the ROBOT_STATE
//    it started from (start_utime), each FAILED answer by its input_utime, root paths and surface
//    sets in the order of their distinct contents (the planners repeat an unchanged output every
//    second, as often as the wall clock allows: repeats are not counted). The planners' `utime`
//    fields are left out: they are the newest simulated time the planner had heard when it
//    finished, which depends on how many ROBOT_STATEs arrived meanwhile.
//  * Still timing-dependent, and so not reproducible in general: a planner whose wall-clock time
//    budget runs out (the answer is then a timeout failure), and the contact planner's check of
//    the stance feet while the robot walks a step (it looks at the newest ROBOT_STATE whenever it
//    is free: a foot that slides more than 3 cm only briefly may be seen in one run and not in the
//    other), and a root path the root planner replans from the newest ROBOT_STATE while the robot
//    walks (after a change of the terrain: which state is the newest when it plans depends on
//    timing; replans at a wait, where the state stands still, do not). A recording that shows
//    any of these may be reported as differing: record runs without them (a plain walk, as
//    tools/record-replay-log does).
// Every planner is seeded: the root planner by the request's seed; the others are deterministic.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "rbcp/core/error.h"
#include "rbcp/core/format.h"
#include "rbcp/cli/cli.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/latest_message.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/run_loop.h"
#include "rbcp_msgs/affordance_set_t.hpp"
#include "rbcp_msgs/contact_plan_t.hpp"
#include "rbcp_msgs/controller_status_t.hpp"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/robot_state_t.hpp"
#include "rbcp_msgs/root_path_t.hpp"
#include "log_messages.h"

namespace {

using namespace rbcp;
using Clock = std::chrono::steady_clock;

constexpr int kReproduced = 0, kDiffers = 1, kNoAnswer = 3;

/// Compares two messages field by field: the largest difference of their numbers and the first
/// field that differs beyond the tolerance (or in a count, an id or a flag).
class Diff {
 public:
  explicit Diff(double tolerance) : tolerance_(tolerance) {}
  void Num(const std::string& field, double a, double b) {
    const double d = std::abs(a - b);
    if (std::isfinite(d)) max_ = std::max(max_, d);
    if ((d > tolerance_ || std::isnan(d)) && first_.empty()) {
      std::ostringstream os;
      os.precision(17);
      os << field << ": recorded " << a << ", replayed " << b;
      first_ = os.str();
    }
  }
  template <std::size_t N>
  void Nums(const std::string& field, const double (&a)[N], const double (&b)[N]) {
    for (std::size_t i = 0; i < N; ++i) Num(field + "[" + std::to_string(i) + "]", a[i], b[i]);
  }
  void Exact(const std::string& field, long long a, long long b) {
    if (a != b && first_.empty()) first_ = field + ": recorded " + std::to_string(a) + ", replayed " + std::to_string(b);
  }
  bool ok() const { return first_.empty(); }
  const std::string& first() const { return first_; }
  double max() const { return max_; }

 private:
  double tolerance_;
  double max_ = 0.0;
  std::string first_;
};

void Compare(const rbcp_msgs::affordance_set_t& a, const rbcp_msgs::affordance_set_t& b, Diff& d) {
  d.Exact("num_surfaces", a.num_surfaces, b.num_surfaces);
  for (std::size_t i = 0; d.ok() && i < a.surfaces.size() && i < b.surfaces.size(); ++i) {
    const auto& sa = a.surfaces[i];
    const auto& sb = b.surfaces[i];
    const std::string f = "surface " + std::to_string(i);
    d.Exact(f + " num_vertices", sa.num_vertices, sb.num_vertices);
    for (std::size_t v = 0; d.ok() && v < sa.vertices.size() && v < sb.vertices.size(); ++v) {
      for (int k = 0; k < 3; ++k) d.Num(f + " vertex " + std::to_string(v), sa.vertices[v][k], sb.vertices[v][k]);
    }
    d.Nums(f + " normal", sa.normal, sb.normal);
    d.Num(f + " area", sa.area, sb.area);
  }
}

void Compare(const rbcp_msgs::root_path_t& a, const rbcp_msgs::root_path_t& b, Diff& d) {
  d.Exact("request_id", a.request_id, b.request_id);
  d.Exact("num_points", a.num_points, b.num_points);
  for (std::size_t i = 0; d.ok() && i < a.points.size() && i < b.points.size(); ++i) {
    const std::string f = "point " + std::to_string(i);
    d.Num(f + " t", a.points[i].t, b.points[i].t);
    d.Nums(f + " position", a.points[i].position, b.points[i].position);
    d.Nums(f + " velocity", a.points[i].velocity, b.points[i].velocity);
    d.Nums(f + " orientation", a.points[i].orientation, b.points[i].orientation);
  }
}

void Compare(const rbcp_msgs::contact_plan_t& a, const rbcp_msgs::contact_plan_t& b, Diff& d) {
  d.Exact("request_id", a.request_id, b.request_id);
  d.Exact("plan_seq", a.plan_seq, b.plan_seq);
  d.Exact("reaches_goal", a.reaches_goal, b.reaches_goal);
  d.Exact("num_states", a.num_states, b.num_states);
  for (std::size_t i = 0; d.ok() && i < a.states.size() && i < b.states.size(); ++i) {
    const auto& sa = a.states[i];
    const auto& sb = b.states[i];
    const std::string f = "state " + std::to_string(i);
    d.Exact(f + " moving_leg", sa.moving_leg, sb.moving_leg);
    d.Nums(f + " base_position", sa.base_position, sb.base_position);
    d.Nums(f + " base_rpy", sa.base_rpy, sb.base_rpy);
    d.Nums(f + " joint_position", sa.joint_position, sb.joint_position);
    for (int leg = 0; leg < 4; ++leg) {
      d.Nums(f + " foot_position[" + std::to_string(leg) + "]", sa.foot_position[leg], sb.foot_position[leg]);
      d.Nums(f + " foot_normal[" + std::to_string(leg) + "]", sa.foot_normal[leg], sb.foot_normal[leg]);
    }
  }
}

/// The same content, `utime` aside (a repeat of an unchanged output).
template <typename Msg>
bool SameContent(Msg a, Msg b) {
  a.utime = 0;
  b.utime = 0;
  const int n = a.getEncodedSize();
  if (n != b.getEncodedSize()) return false;
  std::vector<uint8_t> ea(static_cast<std::size_t>(n)), eb(static_cast<std::size_t>(n));
  a.encode(ea.data(), 0, n);
  b.encode(eb.data(), 0, n);
  return ea == eb;
}

/// A planner's outputs in order, each distinct content once.
template <typename Msg>
struct Distinct {
  std::vector<Msg> items;
  void Add(const Msg& m) {
    if (items.empty() || !SameContent(items.back(), m)) items.push_back(m);
  }
};

/// What the planners said: distinct surface sets and root paths, the contact planner's answers
/// to the robot's waits (plans by start_utime, failures by input_utime), who is up.
struct Answers {
  Distinct<rbcp_msgs::affordance_set_t> surfaces;
  Distinct<rbcp_msgs::root_path_t> paths;
  std::map<int64_t, rbcp_msgs::contact_plan_t> plans;
  std::map<int64_t, std::string> failures;
  std::set<std::pair<int32_t, int64_t>> failures_seen;  // (pid, handled): each failure once
  std::set<std::string> heard;

  void OnSurfaces(const rbcp_msgs::affordance_set_t& m) { surfaces.Add(m); }
  void OnPath(const rbcp_msgs::root_path_t& m) { paths.Add(m); }
  void OnPlan(const rbcp_msgs::contact_plan_t& m) {
    plans.emplace(m.start_utime, m);
  }
  void OnStatus(const rbcp_msgs::process_status_t& m) {
    heard.insert(m.process);
    if (m.process == "contact_planner" && m.state == rbcp_msgs::process_status_t::FAILED &&
        failures_seen.emplace(m.pid, m.handled).second) {
      failures.emplace(m.input_utime, m.reason);
    }
  }
};

/// The replayed planners' answers, as they come over LCM (AFFORDANCES whole or in parts).
class Listener {
 public:
  explicit Listener(lcm::LCM& lcm)
      : surfaces_(lcm, channels::kAffordances, [this](const rbcp_msgs::affordance_set_t& m) { answers.OnSurfaces(m); }, Malformed),
        paths_(lcm, channels::kRootPath, [this](const rbcp_msgs::root_path_t& m) { answers.OnPath(m); }, Malformed),
        plans_(lcm, channels::kContactPlan, [this](const rbcp_msgs::contact_plan_t& m) { answers.OnPlan(m); }, Malformed),
        statuses_(lcm, channels::kStatus, [this](const rbcp_msgs::process_status_t& m) { answers.OnStatus(m); }, Malformed) {}
  Answers answers;

 private:
  static void Malformed(const std::string& why) { std::cerr << "replay_log: " << why << "\n"; }
  transport::EveryMessage<rbcp_msgs::affordance_set_t> surfaces_;
  transport::EveryMessage<rbcp_msgs::root_path_t> paths_;
  transport::EveryMessage<rbcp_msgs::contact_plan_t> plans_;
  transport::EveryMessage<rbcp_msgs::process_status_t> statuses_;
};

struct Event {
  int64_t timestamp = 0;  ///< the logger's receive time [us]
  std::string channel;
  std::vector<uint8_t> data;
  template <typename Msg>
  Msg Decode() const {
    Msg m;
    if (m.decode(data.data(), 0, static_cast<int>(data.size())) < 0) throw InputError("malformed " + channel + " message in the log");
    return m;
  }
};

/// What the replay waits for after a recorded event (the replayed counterpart of a recorded answer).
struct Awaited {
  enum class Kind { kSurfaces, kPath, kPlan, kFailure } kind;
  std::size_t count = 0;  ///< kSurfaces, kPath: this many distinct outputs
  int64_t utime = 0;      ///< kPlan, kFailure: the answer to the ROBOT_STATE of this utime
  std::string What() const {
    switch (kind) {
      case Kind::kSurfaces: return "contact surface set " + std::to_string(count) + " (AFFORDANCES)";
      case Kind::kPath: return "root path " + std::to_string(count) + " (ROOT_PATH)";
      case Kind::kPlan: return "the CONTACT_PLAN from the ROBOT_STATE of utime " + std::to_string(utime);
      case Kind::kFailure: return "the contact planner's answer to the ROBOT_STATE of utime " + std::to_string(utime);
    }
    return "";
  }
  bool Done(const Answers& a) const {
    switch (kind) {
      case Kind::kSurfaces: return a.surfaces.items.size() >= count;
      case Kind::kPath: return a.paths.items.size() >= count;
      case Kind::kPlan:
      case Kind::kFailure: return a.plans.count(utime) > 0 || a.failures.count(utime) > 0;
    }
    return true;
  }
};

/// Progress lines on stderr (none with --quiet).
using Say = std::function<void(const std::string&)>;

/// Writes `events` to `path` without the LCM self test and with ROBOT_STATE thinned: while the
/// robot walks, one state every 1 / walking_state_hz of simulated time (and the first after a
/// wait); while it waits, each state once (the simulator repeats the same state every few ms).
/// A CONTROLLER_STATUS goes with the ROBOT_STATE of its utime: kept when that state is.
int WriteThinned(const std::vector<Event>& events, const std::string& path, double walking_state_hz, const Say& say) {
  lcm::LogFile out(path, "w");
  if (!out.good()) throw InputError("cannot write " + path);
  const auto period_us = static_cast<int64_t>(1e6 / walking_state_hz);
  std::optional<int64_t> last_walking;
  std::set<int64_t> waiting;  // utimes of the wait states written
  bool was_waiting = false;
  std::size_t kept = 0, states = 0;
  std::optional<Event> status;  // the CONTROLLER_STATUS heard last, written with its state
  const auto write = [&](const Event& e) {
    lcm::LogEvent le{};
    le.timestamp = e.timestamp;
    le.channel = e.channel;
    le.datalen = static_cast<int32_t>(e.data.size());
    le.data = const_cast<uint8_t*>(e.data.data());
    if (out.writeEvent(&le) != 0) throw InputError("cannot write " + path);
  };
  for (const Event& e : events) {
    if (e.channel == "LCM_SELF_TEST") continue;
    if (e.channel == channels::kControllerStatus) {
      status = e;
      continue;
    }
    if (e.channel == channels::kRobotState) {
      ++states;
      const auto state = e.Decode<rbcp_msgs::robot_state_t>();
      std::optional<rbcp_msgs::controller_status_t> controller;
      if (status) controller = status->Decode<rbcp_msgs::controller_status_t>();
      if (controller && controller->utime != state.utime) controller.reset();
      const bool awaiting = controller && controller->awaiting_plan;
      bool keep = false;
      if (awaiting) {
        keep = waiting.insert(state.utime).second;
      } else {
        keep = was_waiting || !last_walking || state.utime - *last_walking >= period_us;
        if (keep) last_walking = state.utime;
      }
      was_waiting = awaiting;
      if (!keep) continue;
      ++kept;
      if (controller) write(*status);
      status.reset();
    }
    write(e);
  }
  say("wrote " + path + ": " + std::to_string(kept) + " of " + std::to_string(states) + " ROBOT_STATE messages kept");
  return 0;
}

/// The log's messages, whole.
std::vector<Event> ReadEvents(const std::string& path, const Say& say) {
  std::vector<Event> events;
  logs::ReadLogMessages(
      path,
      [&](int64_t timestamp, const std::string& channel, const void* data, std::size_t size) {
        const auto* bytes = static_cast<const uint8_t*>(data);
        events.push_back({timestamp, channel, std::vector<uint8_t>(bytes, bytes + size)});
      },
      [&](const std::string& problem) { say("skipped " + problem); });
  return events;
}

/// A recorded run as the replay uses it: the inputs to send, and the answers that came.
struct Recording {
  Answers answers;                           ///< what the planners answered
  std::vector<Event> schedule;               ///< the inputs, in order
  std::vector<std::vector<Awaited>> before;  ///< before[i]: the answers to wait for before schedule[i] goes out
  std::vector<bool> waiting;                 ///< waiting[i]: schedule[i] is a ROBOT_STATE of a robot waiting for a plan
};

/// The world's side of a run: what the replay sends.
bool IsInput(const std::string& channel) {
  return channel == channels::kTerrain || channel == channels::kRobotState || channel == channels::kPlanRequest ||
         channel == channels::kControllerStatus;
}

/// Adds a planner's answer to `recorded`; returns what the replay waits for when the answer is new.
std::optional<Awaited> RecordAnswer(const Event& e, Answers& recorded) {
  if (e.channel == channels::kAffordances) {
    const std::size_t n = recorded.surfaces.items.size();
    recorded.OnSurfaces(e.Decode<rbcp_msgs::affordance_set_t>());
    if (recorded.surfaces.items.size() > n) return Awaited{Awaited::Kind::kSurfaces, n + 1, 0};
  } else if (e.channel == channels::kRootPath) {
    const std::size_t n = recorded.paths.items.size();
    recorded.OnPath(e.Decode<rbcp_msgs::root_path_t>());
    if (recorded.paths.items.size() > n) return Awaited{Awaited::Kind::kPath, n + 1, 0};
  } else if (e.channel == channels::kContactPlan) {
    const auto plan = e.Decode<rbcp_msgs::contact_plan_t>();
    const bool is_new = recorded.plans.count(plan.start_utime) == 0;
    recorded.OnPlan(plan);
    if (is_new) return Awaited{Awaited::Kind::kPlan, 0, plan.start_utime};
  } else if (e.channel == channels::kStatus) {
    const auto status = e.Decode<rbcp_msgs::process_status_t>();
    const std::size_t n = recorded.failures.size();
    recorded.OnStatus(status);
    if (recorded.failures.size() > n) return Awaited{Awaited::Kind::kFailure, 0, status.input_utime};
  }
  return std::nullopt;
}

/// The inputs in order, each with the recorded answers that came before it.
Recording Schedule(const std::vector<Event>& events) {
  Recording r;
  std::vector<Awaited> pending;  // recorded answers since the last input
  bool awaiting = false;         // the last CONTROLLER_STATUS says the robot waits
  for (const Event& e : events) {
    if (IsInput(e.channel)) {
      if (e.channel == channels::kControllerStatus) awaiting = e.Decode<rbcp_msgs::controller_status_t>().awaiting_plan;
      r.schedule.push_back(e);
      r.before.push_back(std::exchange(pending, {}));
      r.waiting.push_back(e.channel == channels::kRobotState && awaiting);
    } else if (auto answer = RecordAnswer(e, r.answers)) {
      pending.push_back(*answer);
    }
  }
  return r;
}

/// The recorded inputs sent over LCM to the running planners, and their answers heard.
class Replay {
 public:
  Replay(const cli::CommonOptions& common, double timeout_s)
      : timeout_s_(timeout_s),
        max_runtime_s_(common.max_runtime_s),
        lcm_(transport::OpenLcm(common.lcm_url)),
        listener_(*lcm_),
        publisher_(*lcm_) {
    transport::InstallStopHandlers();
    program_start_ = Clock::now();
  }

  /// Whether every planner reports on STATUS within the timeout (if not, said on stderr).
  bool PlannersUp() {
    for (const char* process : {"affordance_extractor", "root_planner", "contact_planner"}) {
      if (!PumpUntil([&] { return listener_.answers.heard.count(process) > 0; }, timeout_s_)) {
        std::cerr << "replay_log: no STATUS from " << process << " within " << timeout_s_
                  << " s: is it running on this LCM URL?\n";
        return false;
      }
    }
    return true;
  }

  /// Sends the inputs at the recorded pace, the clock shifted by every wait for an answer, then
  /// hears the answers to the last ones. False when an answer did not come or the replay was
  /// stopped (said on stderr).
  bool Run(const Recording& recording) {
    start_ = Clock::now();
    t0_ = recording.schedule.front().timestamp;
    for (std::size_t i = 0; i < recording.schedule.size(); ++i) {
      if (Stopped()) {
        std::cerr << "replay_log: stopped before the end of the log\n";
        return false;
      }
      for (const Awaited& wait : recording.before[i]) {
        if (!AwaitAnswer(recording, i, wait)) return false;
      }
      const auto due = Due(recording.schedule[i]);
      while (Clock::now() < due) {
        lcm_->handleTimeout(std::max(1, static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(due - Clock::now()).count())));
      }
      Publish(recording.schedule[i]);
    }
    PumpUntil([] { return false; }, 1.0);
    seconds_ = std::chrono::duration<double>(Clock::now() - start_).count();
    return true;
  }

  const Answers& answers() const { return listener_.answers; }
  /// How long Run took [s].
  double seconds() const { return seconds_; }

 private:
  /// SIGINT, SIGTERM or --max-runtime end the replay (exit 3: the answers were not all heard).
  bool Stopped() const {
    return transport::StopRequested() ||
           (max_runtime_s_ > 0.0 && std::chrono::duration<double>(Clock::now() - program_start_).count() > max_runtime_s_);
  }

  bool PumpUntil(const std::function<bool()>& done, double seconds) {
    const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    while (!done() && Clock::now() < end && !Stopped()) lcm_->handleTimeout(5);
    return done();
  }

  /// A large TERRAIN goes in parts, as the simulator sent it.
  void Publish(const Event& e) {
    const std::string problem = publisher_.PublishEncoded(e.channel, e.data.data(), e.data.size());
    if (!problem.empty()) throw InputError("cannot replay " + e.channel + ": " + problem);
  }

  /// When `e` goes out: at its recorded time after the first input, shifted by the waits so far.
  Clock::time_point Due(const Event& e) const { return start_ + shift_ + std::chrono::microseconds(e.timestamp - t0_); }

  /// Waits for the replayed counterpart of a recorded answer that came before input i.
  bool AwaitAnswer(const Recording& recording, std::size_t i, const Awaited& wait) {
    const auto waited_from = Clock::now();
    // While the robot waits for its plan, the simulator repeats its state every 5 ms: a
    // planner that was busy when the first one came (and whose socket dropped it) hears it.
    auto next_repeat = Clock::now() + std::chrono::milliseconds(5);
    const auto answered_or_repeat = [&] {
      if (wait.Done(listener_.answers)) return true;
      if (i > 0 && recording.waiting[i - 1] && Clock::now() >= next_repeat) {
        next_repeat += std::chrono::milliseconds(5);
        if (i > 1 && recording.schedule[i - 2].channel == channels::kControllerStatus) Publish(recording.schedule[i - 2]);
        Publish(recording.schedule[i - 1]);
      }
      return false;
    };
    if (!PumpUntil(answered_or_repeat, timeout_s_)) {
      if (Stopped()) std::cerr << "replay_log: stopped before the end of the log, waiting for " << wait.What() << "\n";
      else std::cerr << "replay_log: no answer within " << timeout_s_ << " s: " << wait.What() << "\n";
      return false;
    }
    const auto due = Due(recording.schedule[i]);
    if (Clock::now() > due) shift_ += Clock::now() - std::max(waited_from, due);
    return true;
  }

  double timeout_s_;
  double max_runtime_s_;
  std::unique_ptr<lcm::LCM> lcm_;
  Listener listener_;
  transport::MessagePublisher publisher_;
  Clock::time_point program_start_;
  Clock::time_point start_;  ///< when the first input was due
  int64_t t0_ = 0;           ///< the first input's recorded time [us]
  Clock::duration shift_{0};
  double seconds_ = 0.0;
};

/// The recorded answers against the replayed ones, per input: every difference and every missing
/// answer printed on stdout.
class Comparison {
 public:
  Comparison(const Answers& recorded, const Answers& replayed, double tolerance)
      : recorded_(recorded), replayed_(replayed), tolerance_(tolerance) {
    CompareDistinct("contact surface set", recorded.surfaces, replayed.surfaces);
    CompareDistinct("root path", recorded.paths, replayed.paths);
    ComparePlans();
    CompareFailures();
  }

  /// Notes the replayed plans that answer inputs the recording has no answer to.
  void SayUnanswered(const Say& say) const {
    for (const auto& [utime, plan] : replayed_.plans) {
      if (recorded_.plans.count(utime) == 0 && recorded_.failures.count(utime) == 0) {
        say("note: a CONTACT_PLAN from the ROBOT_STATE of utime " + std::to_string(utime) +
            " that the recording has no answer to (the recording ended first)");
      }
    }
  }

  /// Prints the verdict on stdout; returns the exit status.
  int PrintVerdict(double replay_s) const {
    std::ostringstream summary;
    summary << "replay_log: " << recorded_.surfaces.items.size() << " contact surface set(s), "
            << recorded_.paths.items.size() << " root path(s), " << recorded_.plans.size() << " contact plan(s) ("
            << states_ << " states) and " << recorded_.failures.size() << " failed replan(s) compared in "
            << FixedNumber(replay_s, 1) << " s; largest difference " << largest_ << " (tolerance " << tolerance_ << "): ";
    if (differences_ == 0) {
      std::cout << summary.str() << "the planners reproduced the recorded answers" << std::endl;
      return kReproduced;
    }
    std::cout << summary.str() << differences_ << " answer(s) differ or are missing" << std::endl;
    return kDiffers;
  }

 private:
  void Report(const std::string& what, const Diff& d) {
    largest_ = std::max(largest_, d.max());
    if (d.ok()) return;
    ++differences_;
    std::cout << "replay_log: DIFFERS: " << what << ": " << d.first() << std::endl;
  }
  void Missing(const std::string& what) {
    ++differences_;
    std::cout << "replay_log: MISSING: " << what << std::endl;
  }

  /// Surface sets and root paths, in the order of their distinct contents.
  template <typename Msg>
  void CompareDistinct(const std::string& name, const Distinct<Msg>& recorded, const Distinct<Msg>& replayed) {
    for (std::size_t i = 0; i < recorded.items.size(); ++i) {
      const std::string what = name + " " + std::to_string(i + 1);
      if (i >= replayed.items.size()) { Missing(what); continue; }
      Diff d(tolerance_);
      Compare(recorded.items[i], replayed.items[i], d);
      Report(what, d);
    }
  }

  void ComparePlans() {
    for (const auto& [utime, plan] : recorded_.plans) {
      const std::string what = "CONTACT_PLAN " + std::to_string(plan.plan_seq) + " from the ROBOT_STATE of utime " + std::to_string(utime);
      const auto it = replayed_.plans.find(utime);
      if (it == replayed_.plans.end()) {
        const auto f = replayed_.failures.find(utime);
        Missing(what + (f != replayed_.failures.end() ? " (the replayed planner failed: " + f->second + ")" : ""));
        continue;
      }
      Diff d(tolerance_);
      Compare(plan, it->second, d);
      Report(what, d);
      states_ += plan.num_states;
    }
  }

  void CompareFailures() {
    for (const auto& [utime, reason] : recorded_.failures) {
      const std::string what = "the failed replan from the ROBOT_STATE of utime " + std::to_string(utime);
      const auto it = replayed_.failures.find(utime);
      if (it == replayed_.failures.end()) { Missing(what + " (recorded: " + reason + ")"); continue; }
      if (it->second != reason) {
        ++differences_;
        std::cout << "replay_log: DIFFERS: " << what << ": recorded '" << reason << "', replayed '" << it->second << "'\n";
      }
    }
  }

  const Answers& recorded_;
  const Answers& replayed_;
  double tolerance_;
  int differences_ = 0;
  double largest_ = 0.0;
  int states_ = 0;  ///< states of the recorded plans that were compared
};

/// The command line.
struct Options {
  cli::CommonOptions common;
  std::string log_path;
  double tolerance = 1e-6;
  double timeout_s = 30.0;
  std::string thin_path;
  double walking_state_hz = 50.0;
};

void AddOptions(CLI::App& app, Options& o) {
  cli::AddCommonOptions(app, o.common);
  app.add_option("--log", o.log_path, "the LCM log of a run (tools/launch's run.lcmlog)")->required()->check(CLI::ExistingFile);
  app.add_option("--tolerance", o.tolerance, "largest difference of a number taken as equal")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--timeout", o.timeout_s, "longest wait for a planner's answer, and for the planners to be up [s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--write-thinned", o.thin_path,
                 "instead of replaying: write the log to this file with ROBOT_STATE thinned while the robot walks "
                 "(--walking-state-hz of simulated time; every state of a wait kept once), a smaller log that "
                 "replays the same (the planners act only on the states of a robot waiting at a step boundary)");
  app.add_option("--walking-state-hz", o.walking_state_hz, "with --write-thinned: ROBOT_STATE kept while walking [Hz]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.description(
      "Replays the world's side of a recorded run (TERRAIN, ROBOT_STATE, CONTROLLER_STATUS, PLAN_REQUEST of an\nLCM log that "
      "tools/launch recorded) into running planner processes (affordance_extractor, root_planner,\n"
      "contact_planner with the run's --horizon-steps) and checks that they reproduce their recorded\n"
      "answers: the contact surfaces, the root paths, and each CONTACT_PLAN (or failure) answering a wait of\n"
      "the robot, compared per input within --tolerance (utime fields aside). Inputs go out in the\n"
      "recorded order and pace; at each recorded answer the replay waits for the replayed one.\n"
      "tools/replay-log starts the planners and runs it. Exit status: 0 reproduced, 1 an answer differs\n"
      "or is missing, 2 bad input, 3 a planner did not answer in time.");
}

int Run(const Options& o) {
  const Say say = [&](const std::string& line) {
    if (!o.common.quiet) std::cerr << "replay_log: " << line << "\n";
  };
  const std::vector<Event> events = ReadEvents(o.log_path, say);
  if (!o.thin_path.empty()) return WriteThinned(events, o.thin_path, o.walking_state_hz, say);
  const Recording recording = Schedule(events);
  const Answers& recorded = recording.answers;
  if (recorded.plans.empty()) throw InputError(o.log_path + ": no CONTACT_PLAN in the log: nothing to reproduce");
  say(std::to_string(recording.schedule.size()) + " inputs to replay; the recording answered with " +
      std::to_string(recorded.surfaces.items.size()) + " contact surface set(s), " +
      std::to_string(recorded.paths.items.size()) + " root path(s), " + std::to_string(recorded.plans.size()) +
      " contact plan(s) and " + std::to_string(recorded.failures.size()) + " failed replan(s)");

  Replay replay(o.common, o.timeout_s);
  if (!replay.PlannersUp()) return kNoAnswer;
  say("the planners are up; replaying " + o.log_path);
  if (!replay.Run(recording)) return kNoAnswer;

  const Comparison comparison(recorded, replay.answers(), o.tolerance);
  comparison.SayUnanswered(say);
  return comparison.PrintVerdict(replay.seconds());
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("replay_log", argc, argv, AddOptions, Run); }
