// run_log: turns the LCM log of a run (tools/launch records build/logs/RUN/run.lcmlog) into one
// JSON object that check_plan and the other tools read: the plan the robot walked ("states"), the
// simulator's verdict, the replans and their latency (from the logger's receive times), the
// robot's trace at 20 Hz of simulated time, and the world the run saw (terrain, contact surfaces,
// root path) for tools/view, and the planners' compute times (from their STATUS answers).
#include <algorithm>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/cli/cli.h"
#include "rbcp/nodes/run_record.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/message_parts.h"
#include "rbcp/transport/wire_check.h"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"
#include "view_json.h"

namespace {

using namespace rbcp;

/// One message of the log, whole: as logged, or put back together from its parts.
struct Event {
  int64_t timestamp;
  const void* data;
  std::size_t size;
};

template <typename Msg>
bool Decode(const Event& e, Msg* msg) {
  return transport::DecodeMessage(e.data, e.size, *msg).empty();
}

/// The answers of one planning process: the wall time of each input it handled (OK) and how many
/// inputs it failed on.
struct Answers {
  std::vector<double> ok_ms;
  int failed = 0;
};

nlohmann::json AnswersJson(const Answers& a) {
  double sum = 0.0, max = 0.0;
  for (double ms : a.ok_ms) {
    sum += ms;
    max = std::max(max, ms);
  }
  const double n = static_cast<double>(a.ok_ms.size());
  return {{"count", a.ok_ms.size()},
          {"failed", a.failed},
          {"mean", a.ok_ms.empty() ? 0.0 : sum / n},
          {"median", nodes::Percentile(a.ok_ms, 0.5)},
          {"max", max},
          {"total", sum},
          {"first", a.ok_ms.empty() ? 0.0 : a.ok_ms.front()}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Turns the LCM log of a run (tools/launch records build/logs/RUN/run.lcmlog) into JSON: the plan the\n"
               "robot walked (\"states\", as check_plan reads it), the simulator's verdict (sim_ok, outcome, sim_time_s),\n"
               "the plans and replans with their latency (median and 95th percentile, from the log's receive times:\n"
               "the first ROBOT_STATE a plan starts from to that CONTACT_PLAN) and the robot's trace (sim_trace, 20 Hz).\n"
               "With the trace: joints and torques, the CoM's margin in the polygon of the feet in contact, and\n"
               "each replan's time and latency (replans); the planners' compute times (compute_ms: per process,\n"
               "the wall time of every input answered OK, from STATUS). A walked plan missing from the log is left out of\n"
               "\"states\" and named in missing_plans. The JSON is described in docs/json_schema.md.\n"
               "Reads a file; talks no LCM. Exit status: 0 written, 2 bad input."};
  cli::CommonOptions common;
  cli::AddOfflineOptions(app, common);
  std::string log_path;
  app.add_option("--log", log_path, "the LCM log of a run")->required()->check(CLI::ExistingFile);
  return cli::GuardedMain("run_log", app, argc, argv, [&]() -> int {
    const RobotModel robot = RobotModel::LoadDefault(common.config_dir);
    lcm::LogFile log(log_path, "r");
    if (!log.good()) throw InputError("cannot read the LCM log " + log_path);
    nodes::RunRecord record;
    std::string scenario;
    std::optional<rbcp_msgs::process_status_t> verdict;
    std::optional<rbcp_msgs::terrain_mesh_t> terrain;
    std::optional<rbcp_msgs::affordance_set_t> surfaces;
    std::optional<rbcp_msgs::root_path_t> root_path;
    std::optional<rbcp_msgs::plan_request_t> request;
    int root_paths = 0;
    long events = 0, malformed = 0;
    // Each answer once: STATUS repeats the latest one as a heartbeat, with the same count of
    // inputs handled by that process instance.
    std::set<std::tuple<std::string, int32_t, int64_t>> answered;
    std::map<std::string, Answers> answers = {{"affordance_extractor", {}}, {"root_planner", {}}, {"contact_planner", {}}};
    std::vector<double> plan_steps;
    const auto handle = [&](const std::string& channel, const Event& e) {
      if (channel == channels::kRobotState) {
        rbcp_msgs::robot_state_t msg;
        if (Decode(e, &msg)) record.OnRobotState(e.timestamp, msg); else ++malformed;
      } else if (channel == channels::kControllerStatus) {
        rbcp_msgs::controller_status_t msg;
        if (Decode(e, &msg)) record.OnControllerStatus(e.timestamp, msg); else ++malformed;
      } else if (channel == channels::kContactPlan) {
        rbcp_msgs::contact_plan_t msg;
        if (!Decode(e, &msg)) { ++malformed; return; }
        try {
          record.OnContactPlan(e.timestamp, msg);
          plan_steps.push_back(std::max(0, msg.num_states - 1));
        } catch (const InputError&) {
          ++malformed;
        }
      } else if (channel == channels::kStatus) {
        rbcp_msgs::process_status_t msg;
        if (!Decode(e, &msg)) { ++malformed; return; }
        const bool decided = msg.state == rbcp_msgs::process_status_t::OK || msg.state == rbcp_msgs::process_status_t::FAILED;
        if (msg.process == "anymal_sim" && decided) verdict = msg;
        const auto planner = answers.find(msg.process);
        if (decided && planner != answers.end() && answered.emplace(msg.process, msg.pid, msg.handled).second) {
          if (msg.state == rbcp_msgs::process_status_t::OK) planner->second.ok_ms.push_back(msg.compute_ms);
          else planner->second.failed += 1;
        }
      } else if (channel == channels::kTerrain) {
        rbcp_msgs::terrain_mesh_t msg;
        if (!Decode(e, &msg)) { ++malformed; return; }
        if (scenario.empty()) scenario = msg.scenario_name;
        terrain = std::move(msg);  // the newest terrain
      } else if (channel == channels::kAffordances) {
        rbcp_msgs::affordance_set_t msg;
        if (Decode(e, &msg)) surfaces = std::move(msg); else ++malformed;
      } else if (channel == channels::kRootPath) {
        rbcp_msgs::root_path_t msg;
        if (!Decode(e, &msg)) { ++malformed; return; }
        if (!root_path) root_path = std::move(msg);  // the first: the path from the start to the goal
        ++root_paths;
      } else if (channel == channels::kPlanRequest && !request) {
        rbcp_msgs::plan_request_t msg;
        if (Decode(e, &msg)) request = msg; else ++malformed;
      }
    };
    // A message sent in parts (TERRAIN/PART) counts once it is whole, at its last part's time.
    transport::PartJoiner joiner;
    while (const lcm::LogEvent* e = log.readNextEvent()) {
      ++events;
      const int64_t timestamp = e->timestamp;
      const std::string problem = joiner.Add(
          e->channel, e->data, static_cast<std::size_t>(e->datalen),
          [&](const std::string& channel, const void* data, std::size_t size) { handle(channel, {timestamp, data, size}); });
      if (!problem.empty()) ++malformed;
    }
    if (!record.Latest()) throw InputError(log_path + ": no ROBOT_STATE in " + std::to_string(events) + " events");
    // A plan the logger missed (UDP drops it under load) leaves a gap, named in missing_plans.
    std::vector<std::string> missing_plans;
    const ContactPlan walked = record.ExecutedPlan(&missing_plans);
    nlohmann::json j;
    AddSchemaKeys(j);
    j["scenario"] = scenario;
    j["states"] = ContactPlanToJson(walked);
    j["steps"] = walked.states.empty() ? 0 : static_cast<int>(walked.states.size()) - 1;
    j["missing_plans"] = missing_plans;
    const bool ok = verdict && verdict->state == rbcp_msgs::process_status_t::OK;
    j["sim_ok"] = ok;
    j["reached_goal"] = ok;
    j["outcome"] = verdict ? nlohmann::json(verdict->reason) : nlohmann::json("no verdict in the log");
    j["sim_time_s"] = static_cast<double>(record.Latest()->utime) * 1e-6;
    j["plans"] = record.Plans();
    j["goal_plans"] = record.GoalPlans();
    j["unanswered_waits"] = record.UnansweredWaits();
    const auto& lat = record.LatenciesMs();
    j["replan_latency_ms"] = {{"count", lat.size()},
                              {"median", nodes::Percentile(lat, 0.5)},
                              {"p95", nodes::Percentile(lat, 0.95)}};
    nlohmann::json replans = nlohmann::json::array();
    for (std::size_t i = 0; i < lat.size(); ++i) {
      replans.push_back({{"t", record.LatencyTimesS()[i]}, {"latency_ms", lat[i]}});
    }
    j["replans"] = replans;
    nlohmann::json compute = nlohmann::json::object();
    for (const auto& [process, a] : answers) compute[process] = AnswersJson(a);
    j["compute_ms"] = compute;
    double steps_sum = 0.0;
    for (double s : plan_steps) steps_sum += s;
    j["plan_steps_mean"] = plan_steps.empty() ? 0.0 : steps_sum / static_cast<double>(plan_steps.size());
    // The world as the run saw it, for a viewer: terrain, contact surfaces, root path, start, goal.
    const auto or_null = [&](const auto& msg, auto convert) -> nlohmann::json {
      if (!msg) return nullptr;
      try {
        return convert(*msg);
      } catch (const InputError&) {
        ++malformed;
        return nullptr;
      }
    };
    j["terrain"] = or_null(terrain, [](const auto& m) { return view::TerrainJson(m); });
    j["contact_surfaces"] = or_null(surfaces, [](const auto& m) { return view::SurfacesJson(m); });
    j["surfaces"] = j["contact_surfaces"].is_array() ? j["contact_surfaces"].size() : 0;
    j["root_path"] = root_path ? view::RootPathJson(*root_path) : nlohmann::json::array();
    j["root_paths"] = root_paths;
    const rbcp_msgs::robot_state_t& first = record.Trace().front().state;
    const Eigen::Quaterniond q0(first.base_orientation[0], first.base_orientation[1], first.base_orientation[2],
                                first.base_orientation[3]);
    j["start"] = {{"position", {first.base_position[0], first.base_position[1]}},
                  {"yaw", RpyFromRotation(q0.normalized().toRotationMatrix()).z()}};
    j["goal"] = request ? nlohmann::json({{"position", {request->goal_position[0], request->goal_position[1]}},
                                          {"yaw", request->goal_yaw}})
                        : nlohmann::json();
    nlohmann::json trace = nlohmann::json::array();
    for (const auto& s : record.Trace()) {
      try {
        trace.push_back(view::RobotStateJson(robot, s.state, s.controller ? &*s.controller : nullptr));
      } catch (const InputError&) {
        ++malformed;
      }
    }
    j["sim_trace"] = trace;
    j["malformed_messages"] = malformed;
    std::cout << j.dump() << std::endl;
    return 0;
  });
}
