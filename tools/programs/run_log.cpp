// run_log: turns the LCM log of a run (tools/launch records build/logs/RUN/run.lcmlog) into one
// JSON object that check_plan and the other tools read: the plan the robot walked ("states"), the
// simulator's verdict, the replans and their latency (from the logger's receive times), and the
// robot's trace at 20 Hz of simulated time.
#include <iostream>
#include <optional>
#include <string>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/nodes/process.h"
#include "rbcp/nodes/run_record.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/transport/channels.h"
#include "rbcp/transport/convert.h"
#include "rbcp_msgs/process_status_t.hpp"
#include "rbcp_msgs/terrain_mesh_t.hpp"

namespace {

using namespace rbcp;

template <typename Msg>
bool Decode(const lcm::LogEvent& e, Msg* msg) {
  return msg->decode(e.data, 0, static_cast<int>(e.datalen)) >= 0;
}

nlohmann::json TraceSample(const RobotModel& robot, const rbcp_msgs::robot_state_t& msg) {
  const RobotState s = transport::FromRobotStateMsg(msg);
  const Eigen::Isometry3d base = Eigen::Translation3d(s.base_position_W) * s.base_orientation_W;
  const Eigen::Vector3d rpy = RpyFromRotation(s.base_orientation_W.toRotationMatrix());
  const std::array<Eigen::Vector3d, kNumLegs> feet_B = robot.FootPositions(s.q);
  nlohmann::json feet = nlohmann::json::array();
  for (Leg leg : kAllLegs) {
    const int i = Index(leg);
    const Eigen::Vector3d p = base * feet_B[static_cast<std::size_t>(i)];
    feet.push_back({{"leg", std::string(LegName(leg))},
                    {"position", {p.x(), p.y(), p.z()}},
                    {"contact", s.foot_contact[static_cast<std::size_t>(i)]}});
  }
  return {{"t", s.t},
          {"base", {{"position", {s.base_position_W.x(), s.base_position_W.y(), s.base_position_W.z()}},
                    {"rpy", {rpy.x(), rpy.y(), rpy.z()}}}},
          {"feet", feet}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Turns the LCM log of a run (tools/launch records build/logs/RUN/run.lcmlog) into JSON: the plan the\n"
               "robot walked (\"states\", as check_plan reads it), the simulator's verdict (sim_ok, outcome, sim_time_s),\n"
               "the plans and replans with their latency (median and 95th percentile, from the log's receive times:\n"
               "the first ROBOT_STATE a plan starts from to that CONTACT_PLAN) and the robot's trace (sim_trace, 20 Hz).\n"
               "Reads a file; talks no LCM. Exit status: 0 written, 2 bad input."};
  nodes::CommonOptions common;
  nodes::AddCommonOptions(app, common);
  std::string log_path;
  app.add_option("--log", log_path, "the LCM log of a run")->required()->check(CLI::ExistingFile);
  return nodes::GuardedMain("run_log", app, argc, argv, [&]() -> int {
    const RobotModel robot = RobotModel::LoadDefault(common.config_dir);
    lcm::LogFile log(log_path, "r");
    if (!log.good()) throw InputError("cannot read the LCM log " + log_path);
    nodes::RunRecord record;
    std::string scenario;
    std::optional<rbcp_msgs::process_status_t> verdict;
    long events = 0, malformed = 0;
    while (const lcm::LogEvent* e = log.readNextEvent()) {
      ++events;
      const std::string channel = e->channel;
      if (channel == channels::kRobotState) {
        rbcp_msgs::robot_state_t msg;
        if (Decode(*e, &msg)) record.OnRobotState(e->timestamp, msg); else ++malformed;
      } else if (channel == channels::kContactPlan) {
        rbcp_msgs::contact_plan_t msg;
        if (!Decode(*e, &msg)) { ++malformed; continue; }
        try {
          record.OnContactPlan(e->timestamp, msg);
        } catch (const InputError&) {
          ++malformed;
        }
      } else if (channel == channels::kStatus) {
        rbcp_msgs::process_status_t msg;
        if (!Decode(*e, &msg)) { ++malformed; continue; }
        const bool decided = msg.state == rbcp_msgs::process_status_t::OK || msg.state == rbcp_msgs::process_status_t::FAILED;
        if (msg.process == "anymal_sim" && decided) verdict = msg;
      } else if (channel == channels::kTerrain && scenario.empty()) {
        rbcp_msgs::terrain_mesh_t msg;
        if (Decode(*e, &msg)) scenario = msg.scenario_name; else ++malformed;
      }
    }
    if (!record.Latest()) throw InputError(log_path + ": no ROBOT_STATE in " + std::to_string(events) + " events");
    const ContactPlan walked = record.ExecutedPlan();
    nlohmann::json j;
    j["scenario"] = scenario;
    j["states"] = ContactPlanToJson(walked);
    j["steps"] = walked.states.empty() ? 0 : static_cast<int>(walked.states.size()) - 1;
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
    j["malformed_messages"] = malformed;
    nlohmann::json trace = nlohmann::json::array();
    for (const auto& s : record.Trace()) trace.push_back(TraceSample(robot, s));
    j["sim_trace"] = trace;
    std::cout << j.dump() << std::endl;
    return 0;
  });
}
