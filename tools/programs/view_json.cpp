#include "view_json.h"

#include <Eigen/Geometry>
#include <string>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/sim/plan_execution.h"
#include "rbcp/transport/convert.h"

namespace rbcp::view {
namespace {

using nlohmann::json;

json Vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
json Vec(const double* v) { return json::array({v[0], v[1], v[2]}); }

}  // namespace

json TerrainJson(const TriangleMesh& mesh) {
  json vertices = json::array(), triangles = json::array();
  for (const auto& v : mesh.vertices) vertices.push_back(Vec(v));
  for (const auto& t : mesh.triangles) triangles.push_back(json::array({t[0], t[1], t[2]}));
  return {{"vertices", vertices}, {"triangles", triangles}};
}

json SurfacesJson(const std::vector<AffordanceSurface>& surfaces) {
  json out = json::array();
  for (const auto& s : surfaces) {
    json vertices = json::array();
    for (const auto& v : s.vertices) vertices.push_back(Vec(v));
    out.push_back({{"vertices", vertices}, {"normal", Vec(s.normal)}, {"area", s.area}});
  }
  return out;
}

json TerrainJson(const rbcp_msgs::terrain_mesh_t& msg) {
  json j = TerrainJson(transport::FromTerrainMsg(msg));
  j["scenario"] = msg.scenario_name;
  return j;
}

json SurfacesJson(const rbcp_msgs::affordance_set_t& msg) { return SurfacesJson(transport::FromAffordanceMsg(msg)); }

json RootPathJson(const rbcp_msgs::root_path_t& msg) {
  json path = json::array();
  for (const auto& p : msg.points) {
    const Eigen::Quaterniond q(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3]);
    const double yaw = q.norm() > 0.0 ? RpyFromRotation(q.normalized().toRotationMatrix()).z() : 0.0;
    path.push_back({{"t", p.t}, {"position", Vec(p.position)}, {"velocity", Vec(p.velocity)}, {"yaw", yaw}});
  }
  return path;
}

json ContactPlanJson(const rbcp_msgs::contact_plan_t& msg) {
  return {{"plan_seq", msg.plan_seq},
          {"start_t", 1e-6 * static_cast<double>(msg.start_utime)},
          {"reaches_goal", msg.reaches_goal},
          {"states", ContactPlanToJson(transport::FromContactPlanMsg(msg))}};
}

json RobotStateJson(const RobotModel& robot, const rbcp_msgs::robot_state_t& msg,
                    const rbcp_msgs::controller_status_t* controller) {
  sim::TraceSample sample = sim::MeasuredTraceSample(robot, transport::FromRobotStateMsg(msg));
  if (controller == nullptr) return sim::TraceSampleToJson(sample);
  const ControllerProgress progress = transport::FromControllerStatusMsg(*controller);
  sample.step = progress.step;
  sample.phase = progress.phase;
  json j = sim::TraceSampleToJson(sample);
  j["plan_seq"] = progress.plan_seq;
  j["steps_done"] = progress.steps_done;
  j["awaiting_plan"] = progress.awaiting_since.has_value();
  j["base_error_m"] = progress.base_error_m;
  return j;
}

json StatusJson(const rbcp_msgs::process_status_t& msg) {
  static const char* const kStates[] = {"alive", "busy", "ok", "failed"};
  const std::string state = msg.state >= 0 && msg.state <= 3 ? kStates[msg.state] : "unknown";
  return {{"t", 1e-6 * static_cast<double>(msg.utime)},
          {"process", msg.process},
          {"state", state},
          {"reason", msg.reason},
          {"compute_ms", msg.compute_ms}};
}

}  // namespace rbcp::view
