// scene_json: what a viewer needs besides a plan, as one JSON object on stdout: the scenario's
// terrain mesh, its contact surfaces (affordance extraction with the given parameters) and the
// robot (joint tree, collision primitives, planning parameters, torque limits, and
// the link poses of the reference stance from rbcp::RobotModel so a viewer can check its own
// kinematics). Without a scenario, the robot alone.
//
// Rotations are quaternions [x, y, z, w]; every pose is {"xyz", "quaternion"}.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "rbcp/affordance/affordance_config.h"
#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/stance/stance_config.h"
#include "rbcp/core/config_dir.h"
#include "rbcp/core/error.h"
#include "rbcp/plan_checker/plan_json.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "view_json.h"

namespace {

using nlohmann::json;

json Vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
json Vec2(const Eigen::Vector2d& v) { return json::array({v.x(), v.y()}); }

json Pose(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.rotation());
  return {{"xyz", Vec(pose.translation())}, {"quaternion", json::array({q.x(), q.y(), q.z(), q.w()})}};
}

std::string JointType(rbcp::RobotJoint::Type type) {
  switch (type) {
    case rbcp::RobotJoint::Type::kRevolute: return "revolute";
    case rbcp::RobotJoint::Type::kContinuous: return "continuous";
    case rbcp::RobotJoint::Type::kFixed: return "fixed";
  }
  return "other";
}

/// The robot's joints, breadth first from the root link: a joint never precedes the joint that
/// places its parent link.
json Joints(const rbcp::RobotModel& robot) {
  json joints = json::array();
  for (const rbcp::RobotJoint& j : robot.Joints()) {
    joints.push_back({{"name", j.name},
                      {"type", JointType(j.type)},
                      {"parent", j.parent_link},
                      {"child", j.child_link},
                      {"origin", Pose(j.origin)},
                      {"axis", Vec(j.axis)}});
  }
  return joints;
}

json Robot(const std::string& config_dir) {
  const std::string urdf_path = config_dir + "/robots/anymal_b.urdf";
  const rbcp::RobotModel robot = rbcp::RobotModel::Load(urdf_path, config_dir + "/robots/anymal_b.yaml");
  const rbcp::StanceConfig stance_config = rbcp::StanceConfig::LoadFile(config_dir + "/stance.yaml");

  json links = json::array();
  for (const rbcp::RobotLink& link : robot.Links()) {
    links.push_back({{"name", link.name},
                     {"leg", link.leg ? json(std::string(rbcp::LegName(*link.leg))) : json(nullptr)},
                     {"mass", link.mass}});
  }
  json shapes = json::array();
  for (const rbcp::CollisionShape& s : robot.CollisionShapes()) {
    json shape = {{"name", s.name}, {"link", s.link}, {"origin", Pose(s.pose_link)}};
    switch (s.kind) {
      case rbcp::CollisionShape::Kind::kBox:
        shape["kind"] = "box";
        shape["size"] = Vec(s.box_size);
        break;
      case rbcp::CollisionShape::Kind::kCylinder:
        shape["kind"] = "cylinder";
        shape["radius"] = s.radius;
        shape["length"] = s.length;
        break;
      case rbcp::CollisionShape::Kind::kSphere:
        shape["kind"] = "sphere";
        shape["radius"] = s.radius;
        break;
    }
    shapes.push_back(shape);
  }
  json joint_order = json::array(), q_reference = json::array();
  const rbcp::JointVector& q = robot.ReferenceConfiguration();
  for (int i = 0; i < rbcp::kNumJoints; ++i) {
    joint_order.push_back(rbcp::JointName(i));
    q_reference.push_back(q[i]);
  }
  json reference_poses = json::object();
  const std::vector<Eigen::Isometry3d> poses = robot.LinkPoses(q);
  for (std::size_t i = 0; i < poses.size(); ++i) reference_poses[robot.Links()[i].name] = Pose(poses[i]);

  return {{"urdf", urdf_path},
          {"links", links},
          {"joints", Joints(robot)},
          {"shapes", shapes},
          {"joint_order", joint_order},
          {"reference_configuration", q_reference},
          {"reference_link_poses", reference_poses},
          {"nominal_base_height", robot.NominalBaseHeight()},
          {"torque_limit_Nm", robot.ContinuousTorqueLimit()},
          {"urdf_effort_limit_Nm", robot.TorqueLimit()},
          {"support_margin_m", stance_config.support_margin_m},
          {"foot_radius", robot.FootRadius()},
          {"foot_contact_offset", Vec(robot.FootContactOffset())}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Prints a scenario's terrain mesh, its contact surfaces and the robot description as one JSON\n"
               "object (for tools/view); without --scenario, the robot description alone (for a live page).\n"
               "The JSON is described in docs/json_schema.md. Reads files; talks no LCM.\n"
               "Exit status: 0 printed, 2 bad input."};
  std::string scenario_path, config_dir = rbcp::DefaultConfigDir();
  app.add_option("--scenario", scenario_path, "scenario YAML")->check(CLI::ExistingFile);
  app.add_option("--config-dir", config_dir,
                 "folder with affordance.yaml, stance.yaml and robots/ (default: $RBCP_CONFIG_DIR, "
                 "else the installed PREFIX/share/rbcp/config, else the checkout's config/)")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    json out = {{"robot", Robot(config_dir)}};
    rbcp::AddSchemaKeys(out);
    if (!scenario_path.empty()) {
      const rbcp::Scenario scenario = rbcp::LoadScenario(scenario_path);
      rbcp::AffordanceExtractor extractor(rbcp::AffordanceConfig::LoadFile(config_dir + "/affordance.yaml"));
      out["scenario"] = scenario.name;
      out["scenario_file"] = scenario_path;
      out["start"] = {{"position", Vec2(scenario.start.position)}, {"yaw", scenario.start.yaw}};
      out["goal"] = {{"position", Vec2(scenario.goal.position)}, {"yaw", scenario.goal.yaw}};
      out["terrain"] = rbcp::view::TerrainJson(scenario.terrain_mesh);
      out["contact_surfaces"] = rbcp::view::SurfacesJson(extractor.Extract(scenario.terrain_mesh));
    }
    std::cout << out.dump() << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "scene_json: " << e.what() << std::endl;
    return 2;
  }
}
