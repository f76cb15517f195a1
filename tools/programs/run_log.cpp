// run_log: turns the LCM log of a run (tools/launch records build/logs/RUN/run.lcmlog) into one
// JSON object that check_plan and the other tools read: the plan the robot walked ("states"), the
// simulator's verdict, the replans and their latency (from the logger's receive times), the
// robot's trace at 20 Hz of simulated time, and the world the run saw (terrain, contact surfaces,
// root path) for tools/view, and the planners' compute times (from their STATUS answers).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/cli/cli.h"
#include "rbcp/mapping/terrain_map.h"
#include "rbcp/nodes/run_record.h"
#include "rbcp/nodes/terrain_mapper_node.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"
#include "rbcp/transport/wire_check.h"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/plan_request_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"
#include "log_messages.h"
#include "view_json.h"

namespace {

using namespace rbcp;

/// The walked path counts as covered where the map knows every cell within this of the base.
constexpr double kPathCoverageRadius_m = 0.1;

/// One message of the log, whole: as logged, or put back together from its parts.
struct Event {
  int64_t timestamp;
  const void* data;
  std::size_t size;
};

template <typename Msg>
bool Decode(const Event& e, Msg* msg) {
  return !transport::DecodeMessage(e.data, e.size, *msg);
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

/// What the log of a run tells, gathered message by message.
struct RunLog {
  nodes::RunRecord record;
  std::string scenario;  ///< the scenario name of the first TERRAIN
  std::optional<rbcp_msgs::process_status_t> verdict;
  /// When the verdict was first published [us, simulated] (its heartbeats repeat it later).
  int64_t verdict_utime = 0;
  std::optional<rbcp_msgs::terrain_mesh_t> terrain;         ///< the newest
  std::optional<rbcp_msgs::affordance_set_t> surfaces;      ///< the newest
  std::optional<rbcp_msgs::root_path_t> root_path;          ///< the first: the path from the start to the goal
  std::optional<rbcp_msgs::plan_request_t> request;         ///< the first
  int root_paths = 0;
  long events = 0, malformed = 0;
  // Each answer once: STATUS repeats the latest one as a heartbeat, with the same count of
  // inputs handled by that process instance.
  std::set<std::tuple<std::string, int32_t, int64_t>> answered;
  std::map<std::string, Answers> answers = {{"affordance_extractor", {}}, {"root_planner", {}}, {"contact_planner", {}}};
  std::vector<double> plan_steps;  ///< the steps of every contact plan
  // --terrain perceived: TERRAIN is the mapper's map; TERRAIN_TRUTH the simulator's terrain.
  std::optional<rbcp_msgs::terrain_mesh_t> true_terrain;  ///< the newest TERRAIN_TRUTH
  std::optional<rbcp_msgs::elevation_map_t> elevation;    ///< the newest ELEVATION_MAP
  std::map<int64_t, int64_t> cloud_received;  ///< per capture utime, when its last cloud was received [us]
  std::vector<double> map_latency_ms;  ///< per map of a capture's time: from its cloud's receipt to the map's
  std::set<int64_t> maps_seen;         ///< utimes of the maps heard
  long clouds = 0, maps = 0;

  void OnMessage(const std::string& channel, const Event& e) {
    if (channel == channels::kRobotState) {
      Take<rbcp_msgs::robot_state_t>(e, [&](const auto& m) { record.OnRobotState(e.timestamp, m); });
    } else if (channel == channels::kControllerStatus) {
      Take<rbcp_msgs::controller_status_t>(e, [&](const auto& m) { record.OnControllerStatus(e.timestamp, m); });
    } else if (channel == channels::kContactPlan) {
      Take<rbcp_msgs::contact_plan_t>(e, [&](const auto& m) { OnContactPlan(e.timestamp, m); });
    } else if (channel == channels::kStatus) {
      Take<rbcp_msgs::process_status_t>(e, [&](const auto& m) { OnStatus(m); });
    } else if (channel == channels::kTerrain) {
      Take<rbcp_msgs::terrain_mesh_t>(e, [&](auto& m) {
        if (scenario.empty()) scenario = m.scenario_name;
        if (true_terrain) OnMap(e.timestamp, m.utime);
        terrain = std::move(m);
      });
    } else if (channel == channels::kTerrainTruth) {
      Take<rbcp_msgs::terrain_mesh_t>(e, [&](auto& m) {
        scenario = m.scenario_name;
        true_terrain = std::move(m);
      });
    } else if (channel == channels::kPointCloud) {
      Take<rbcp_msgs::point_cloud_t>(e, [&](const auto& m) {
        cloud_received[m.utime] = e.timestamp;
        ++clouds;
      });
    } else if (channel == channels::kElevationMap) {
      Take<rbcp_msgs::elevation_map_t>(e, [&](auto& m) { elevation = std::move(m); });
    } else if (channel == channels::kAffordances) {
      Take<rbcp_msgs::affordance_set_t>(e, [&](auto& m) { surfaces = std::move(m); });
    } else if (channel == channels::kRootPath) {
      Take<rbcp_msgs::root_path_t>(e, [&](auto& m) {
        if (!root_path) root_path = std::move(m);
        ++root_paths;
      });
    } else if (channel == channels::kPlanRequest && !request) {
      Take<rbcp_msgs::plan_request_t>(e, [&](const auto& m) { request = m; });
    }
  }

  /// `convert(*msg)`, or null when there is no message or it is malformed (counted).
  template <typename Msg, typename Convert>
  nlohmann::json OrNull(const std::optional<Msg>& msg, Convert convert) {
    if (!msg) return nullptr;
    try {
      return convert(*msg);
    } catch (const InputError&) {
      ++malformed;
      return nullptr;
    }
  }

 private:
  /// Decodes the message and hands it to use(), or counts it malformed.
  template <typename Msg, typename Use>
  void Take(const Event& e, Use use) {
    Msg msg;
    if (Decode(e, &msg)) use(msg); else ++malformed;
  }
  /// A map of the mapper: its latency when it is the map of a capture's time (the mapper sends one
  /// when its clouds' time reaches the next period; a wait's map is sent at the wait's time).
  void OnMap(int64_t timestamp, int64_t utime) {
    // The mapper repeats its latest map every second: only the first copy of each map counts.
    if (!maps_seen.insert(utime).second) return;
    ++maps;
    const auto cloud = cloud_received.find(utime);
    if (cloud != cloud_received.end()) map_latency_ms.push_back(1e-3 * static_cast<double>(timestamp - cloud->second));
  }
  void OnContactPlan(int64_t timestamp, const rbcp_msgs::contact_plan_t& msg) {
    try {
      record.OnContactPlan(timestamp, msg);
      plan_steps.push_back(std::max(0, msg.num_states - 1));
    } catch (const InputError&) {
      ++malformed;
    }
  }
  void OnStatus(const rbcp_msgs::process_status_t& msg) {
    const bool decided = msg.state == rbcp_msgs::process_status_t::OK || msg.state == rbcp_msgs::process_status_t::FAILED;
    if (msg.process == "anymal_sim" && decided) {
      if (!verdict || verdict->state != msg.state || verdict->reason != msg.reason) verdict_utime = msg.utime;
      verdict = msg;
    }
    const auto planner = answers.find(msg.process);
    if (decided && planner != answers.end() && answered.emplace(msg.process, msg.pid, msg.handled).second) {
      if (msg.state == rbcp_msgs::process_status_t::OK) planner->second.ok_ms.push_back(msg.compute_ms);
      else planner->second.failed += 1;
    }
  }
};

/// The plan the robot walked and the simulator's verdict on the run.
void AddWalkedPlan(const RunLog& log, nlohmann::json& j) {
  // A plan the logger missed (UDP drops it under load) leaves a gap, named in missing_plans.
  std::vector<std::string> missing_plans;
  const ContactPlan walked = log.record.ExecutedPlan(&missing_plans);
  j["states"] = ContactPlanToJson(walked);
  j["steps"] = walked.states.empty() ? 0 : static_cast<int>(walked.states.size()) - 1;
  j["missing_plans"] = missing_plans;
  const bool ok = log.verdict && log.verdict->state == rbcp_msgs::process_status_t::OK;
  j["sim_ok"] = ok;
  j["reached_goal"] = ok;
  j["outcome"] = log.verdict ? nlohmann::json(log.verdict->reason) : nlohmann::json("no verdict in the log");
  // The simulated time of the verdict (the simulator goes on publishing while the pipeline stops),
  // else of the last state logged.
  j["sim_time_s"] = static_cast<double>(log.verdict ? log.verdict_utime : log.record.Latest()->utime) * 1e-6;
}

/// The plans, the replans with their latency, and the planners' compute times.
void AddPlanning(const RunLog& log, nlohmann::json& j) {
  const nodes::RunRecord& record = log.record;
  j["plans"] = record.Plans();
  j["goal_plans"] = record.GoalPlans();
  j["unanswered_waits"] = record.UnansweredWaits();
  j["startup_s"] = record.StartupWallS();
  j["waiting_s"] = record.WaitingWallS();
  j["waiting_share"] = record.WaitingShare();
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
  for (const auto& [process, a] : log.answers) compute[process] = AnswersJson(a);
  j["compute_ms"] = compute;
  double steps_sum = 0.0;
  for (double s : log.plan_steps) steps_sum += s;
  j["plan_steps_mean"] = log.plan_steps.empty() ? 0.0 : steps_sum / static_cast<double>(log.plan_steps.size());
}

/// The world as the run saw it, for a viewer: terrain, contact surfaces, root path, start, goal.
void AddWorld(RunLog& log, nlohmann::json& j) {
  j["terrain"] = log.OrNull(log.terrain, [](const auto& m) { return view::TerrainJson(m); });
  j["contact_surfaces"] = log.OrNull(log.surfaces, [](const auto& m) { return view::SurfacesJson(m); });
  j["surfaces"] = j["contact_surfaces"].is_array() ? j["contact_surfaces"].size() : 0;
  j["root_path"] = log.root_path ? view::RootPathJson(*log.root_path) : nlohmann::json::array();
  j["root_paths"] = log.root_paths;
  const rbcp_msgs::robot_state_t& first = log.record.Trace().front().state;
  const Eigen::Quaterniond q0(first.base_orientation[0], first.base_orientation[1], first.base_orientation[2],
                              first.base_orientation[3]);
  j["start"] = {{"position", {first.base_position[0], first.base_position[1]}},
                {"yaw", RpyFromRotation(q0.normalized().toRotationMatrix()).z()}};
  j["goal"] = log.request ? nlohmann::json({{"position", {log.request->goal_position[0], log.request->goal_position[1]}},
                                            {"yaw", log.request->goal_yaw}})
                          : nlohmann::json();
}

/// --terrain perceived: the last map judged against the true terrain (height error over the
/// known cells, coverage of the walked path), and how late maps came after their clouds.
void AddPerception(RunLog& log, nlohmann::json& j) {
  if (!log.true_terrain) {
    j["perception"] = nullptr;
    return;
  }
  nlohmann::json p = {{"clouds", log.clouds},
                      {"maps", log.maps},
                      {"cloud_to_terrain_ms",
                       {{"count", log.map_latency_ms.size()},
                        {"median", nodes::Percentile(log.map_latency_ms, 0.5)},
                        {"p95", nodes::Percentile(log.map_latency_ms, 0.95)}}}};
  p["true_terrain"] = log.OrNull(log.true_terrain, [](const auto& m) { return view::TerrainJson(m); });
  try {
    if (!log.elevation) throw InputError("no ELEVATION_MAP in the log");
    const mapping::ElevationMap map = nodes::FromElevationMapMsg(*log.elevation);
    const mapping::HeightError e = mapping::MeasureHeightError(map, transport::FromTerrainMsg(*log.true_terrain));
    p["height_error_m"] = {{"cells", e.cells}, {"cells_no_truth", e.cells_no_truth}, {"rms", e.rms_m},
                           {"p95", e.p95_m},   {"max", e.max_m}};
    std::vector<Eigen::Vector2d> path;
    for (const auto& s : log.record.Trace()) path.emplace_back(s.state.base_position[0], s.state.base_position[1]);
    p["path_coverage"] = mapping::PathCoverage(map, path, kPathCoverageRadius_m);
    p["known_cells"] = map.KnownCells();
    // The grid, for viewers: heights row by row (cell (ix, iy) at iy * num_x + ix), null where unknown.
    const rbcp_msgs::elevation_map_t& em = *log.elevation;
    nlohmann::json heights = nlohmann::json::array();
    for (std::size_t i = 0; i < em.height.size(); ++i) {
      heights.push_back(std::isfinite(em.height[i]) ? nlohmann::json(em.height[i]) : nlohmann::json(nullptr));
    }
    p["elevation_map"] = {{"origin", {em.origin[0], em.origin[1]}}, {"resolution", em.resolution},
                          {"num_x", em.num_x},  {"num_y", em.num_y}, {"height", heights}};
  } catch (const InputError& e) {
    ++log.malformed;
    p["height_error_m"] = nullptr;
    p["path_coverage"] = nullptr;
    p["problem"] = e.what();
  }
  j["perception"] = p;
}

/// The robot's trace; a state that cannot be shown is counted malformed.
nlohmann::json TraceJson(RunLog& log, const RobotModel& robot) {
  nlohmann::json trace = nlohmann::json::array();
  for (const auto& s : log.record.Trace()) {
    try {
      trace.push_back(view::RobotStateJson(robot, s.state, s.controller ? &*s.controller : nullptr));
    } catch (const InputError&) {
      ++log.malformed;
    }
  }
  return trace;
}

/// The command line.
struct Options {
  cli::CommonOptions common;
  std::string log_path;
};

void AddOptions(CLI::App& app, Options& o) {
  cli::AddOfflineOptions(app, o.common);
  app.add_option("--log", o.log_path, "the LCM log of a run")->required()->check(CLI::ExistingFile);
  app.description(
      "Turns the LCM log of a run (tools/launch records build/logs/RUN/run.lcmlog) into JSON: the plan the\n"
      "robot walked (\"states\", as check_plan reads it), the simulator's verdict (sim_ok, outcome, sim_time_s),\n"
      "the plans and replans with their latency (median and 95th percentile, from the log's receive times:\n"
      "the first ROBOT_STATE a plan starts from to that CONTACT_PLAN) and the robot's trace (sim_trace, 20 Hz).\n"
      "With the trace: joints and torques, the CoM's margin in the polygon of the feet in contact, and\n"
      "each replan's time and latency (replans); the planners' compute times (compute_ms: per process,\n"
      "the wall time of every input answered OK, from STATUS). A walked plan missing from the log is left out of\n"
      "\"states\" and named in missing_plans. The JSON is described in docs/json_schema.md.\n"
      "Reads a file; talks no LCM. Exit status: 0 written, 2 bad input.");
}

int Run(const Options& o) {
  const RobotModel robot = RobotModel::LoadDefault(o.common.config_dir);
  RunLog log;
  log.events = logs::ReadLogMessages(
      o.log_path,
      [&](int64_t timestamp, const std::string& channel, const void* data, std::size_t size) {
        log.OnMessage(channel, {timestamp, data, size});
      },
      [&](const std::string&) { ++log.malformed; });
  if (!log.record.Latest()) throw InputError(o.log_path + ": no ROBOT_STATE in " + std::to_string(log.events) + " events");
  nlohmann::json j;
  AddSchemaKeys(j);
  j["scenario"] = log.scenario;
  AddWalkedPlan(log, j);
  AddPlanning(log, j);
  AddWorld(log, j);
  AddPerception(log, j);
  j["sim_trace"] = TraceJson(log, robot);
  j["malformed_messages"] = log.malformed;
  std::cout << j.dump() << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return rbcp::cli::Main("run_log", argc, argv, AddOptions, Run); }
