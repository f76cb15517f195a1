// scene_json: what a viewer needs besides a plan, as one JSON object on stdout: the scenario's
// terrain mesh, its contact surfaces (affordance extraction with the given parameters) and the
// robot (joint tree from the URDF, collision primitives, planning parameters, and the link poses
// of the reference stance from rbcp::RobotModel so a viewer can check its own kinematics).
//
// Rotations are quaternions [x, y, z, w]; every pose is {"xyz", "quaternion"}.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <deque>
#include <exception>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "rbcp/affordance/affordance_config.h"
#include "rbcp/affordance/affordance_extractor.h"
#include "rbcp/core/error.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"

namespace {

using nlohmann::json;

json Vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
json Vec2(const Eigen::Vector2d& v) { return json::array({v.x(), v.y()}); }

json Pose(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.rotation());
  return {{"xyz", Vec(pose.translation())}, {"quaternion", json::array({q.x(), q.y(), q.z(), q.w()})}};
}

json Pose(const urdf::Pose& pose) {
  const urdf::Rotation& r = pose.rotation;
  return {{"xyz", json::array({pose.position.x, pose.position.y, pose.position.z})},
          {"quaternion", json::array({r.x, r.y, r.z, r.w})}};
}

std::string JointType(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE: return "revolute";
    case urdf::Joint::CONTINUOUS: return "continuous";
    case urdf::Joint::PRISMATIC: return "prismatic";
    case urdf::Joint::FIXED: return "fixed";
    default: return "other";
  }
}

json Terrain(const rbcp::TriangleMesh& mesh) {
  json vertices = json::array(), triangles = json::array();
  for (const auto& v : mesh.vertices) vertices.push_back(Vec(v));
  for (const auto& t : mesh.triangles) triangles.push_back(json::array({t[0], t[1], t[2]}));
  return {{"vertices", vertices}, {"triangles", triangles}};
}

json Surfaces(const std::vector<rbcp::AffordanceSurface>& surfaces) {
  json out = json::array();
  for (const auto& s : surfaces) {
    json vertices = json::array();
    for (const auto& v : s.vertices) vertices.push_back(Vec(v));
    out.push_back({{"vertices", vertices}, {"normal", Vec(s.normal)}, {"area", s.area}});
  }
  return out;
}

/// The URDF's joints, breadth first from the root link: a joint never precedes the joint that
/// places its parent link.
json Joints(const std::string& urdf_path) {
  std::ifstream file(urdf_path);
  std::stringstream xml;
  xml << file.rdbuf();
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(xml.str());
  if (!model) throw rbcp::InputError(urdf_path + ": the URDF does not parse");
  json joints = json::array();
  std::deque<urdf::LinkConstSharedPtr> queue = {model->getRoot()};
  while (!queue.empty()) {
    const urdf::LinkConstSharedPtr link = queue.front();
    queue.pop_front();
    for (const urdf::JointSharedPtr& j : link->child_joints) {
      joints.push_back({{"name", j->name},
                        {"type", JointType(j->type)},
                        {"parent", j->parent_link_name},
                        {"child", j->child_link_name},
                        {"origin", Pose(j->parent_to_joint_origin_transform)},
                        {"axis", json::array({j->axis.x, j->axis.y, j->axis.z})}});
    }
    for (const urdf::LinkSharedPtr& child : link->child_links) queue.push_back(child);
  }
  return joints;
}

json Robot(const std::string& config_dir) {
  const std::string urdf_path = config_dir + "/robots/anymal_b.urdf";
  const rbcp::RobotModel robot = rbcp::RobotModel::Load(urdf_path, config_dir + "/robots/anymal_b.yaml");

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
          {"joints", Joints(urdf_path)},
          {"shapes", shapes},
          {"joint_order", joint_order},
          {"reference_configuration", q_reference},
          {"reference_link_poses", reference_poses},
          {"nominal_base_height", robot.NominalBaseHeight()},
          {"foot_radius", robot.FootRadius()},
          {"foot_contact_offset", Vec(robot.FootContactOffset())}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Prints a scenario's terrain mesh, its contact surfaces and the robot description as one JSON\n"
               "object (for tools/view). Exit status: 0 printed, 2 bad input."};
  std::string scenario_path, config_dir = "config";
  app.add_option("--scenario", scenario_path, "scenario YAML")->required()->check(CLI::ExistingFile);
  app.add_option("--config-dir", config_dir, "folder with affordance.yaml and robots/")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    const rbcp::Scenario scenario = rbcp::LoadScenario(scenario_path);
    rbcp::AffordanceExtractor extractor(rbcp::AffordanceConfig::LoadFile(config_dir + "/affordance.yaml"));
    const json out = {{"scenario", scenario.name},
                      {"scenario_file", scenario_path},
                      {"start", {{"position", Vec2(scenario.start.position)}, {"yaw", scenario.start.yaw}}},
                      {"goal", {{"position", Vec2(scenario.goal.position)}, {"yaw", scenario.goal.yaw}}},
                      {"terrain", Terrain(scenario.terrain_mesh)},
                      {"surfaces", Surfaces(extractor.Extract(scenario.terrain_mesh))},
                      {"robot", Robot(config_dir)}};
    std::cout << out.dump() << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "scene_json: " << e.what() << std::endl;
    return 2;
  }
}
