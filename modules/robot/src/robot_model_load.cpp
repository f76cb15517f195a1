// Loading of the robot model: URDF (through urdfdom) and planning parameters (strict YAML).

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/robot/robot_model.h"

namespace rbcp {
namespace {

constexpr std::array<const char*, kJointsPerLeg> kJointSuffix = {"HAA", "HFE", "KFE"};

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

std::string Vec(const Eigen::Vector3d& v) { return "(" + Num(v.x()) + " " + Num(v.y()) + " " + Num(v.z()) + ")"; }

Eigen::Isometry3d ToIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return T;
}

/// Collects the error messages urdfdom reports through console_bridge while parsing.
class ErrorCapture : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) Add(text);
  }
  void Add(const std::string& text) {
    if (!text_.empty()) text_ += "; ";
    text_ += text;
  }
  const std::string& Text() const { return text_; }

 private:
  std::string text_;
};

urdf::ModelInterfaceSharedPtr ParseUrdfFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  std::stringstream xml;
  xml << in.rdbuf();

  urdf::ModelInterfaceSharedPtr model;
  std::string errors;
  {
    // console_bridge's output handler is process-wide: serialize parses that redirect it.
    static std::mutex mutex;
    std::lock_guard<std::mutex> lock(mutex);
    ErrorCapture capture;
    console_bridge::useOutputHandler(&capture);
    try {
      model = urdf::parseURDF(xml.str());
    } catch (const std::exception& e) {
      capture.Add(e.what());
      model.reset();
    }
    console_bridge::restorePreviousOutputHandler();
    errors = capture.Text();
  }
  if (!model) throw InputError(path + ": invalid URDF" + (errors.empty() ? "" : ": " + errors));
  return model;
}

std::string JointTypeName(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE:
      return "revolute";
    case urdf::Joint::CONTINUOUS:
      return "continuous";
    case urdf::Joint::PRISMATIC:
      return "prismatic";
    case urdf::Joint::FLOATING:
      return "floating";
    case urdf::Joint::PLANAR:
      return "planar";
    case urdf::Joint::FIXED:
      return "fixed";
    default:
      return "unknown";
  }
}

[[noreturn]] void FailAt(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

}  // namespace

std::string JointName(Leg leg, int j) {
  RBCP_CHECK(j >= 0 && j < kJointsPerLeg, "joint index within a leg");
  return std::string(LegName(leg)) + "_" + kJointSuffix[static_cast<std::size_t>(j)];
}

std::string JointName(int joint_index) {
  RBCP_CHECK(joint_index >= 0 && joint_index < kNumJoints, "joint index");
  return JointName(kAllLegs[static_cast<std::size_t>(joint_index / kJointsPerLeg)], joint_index % kJointsPerLeg);
}

RobotModel RobotModel::LoadDefault(const std::string& config_dir) {
  return Load(config_dir + "/robots/anymal_b.urdf", config_dir + "/robots/anymal_b.yaml");
}

RobotModel RobotModel::Load(const std::string& urdf_path, const std::string& yaml_path) {
  RobotModel m;
  const urdf::ModelInterfaceSharedPtr urdf = ParseUrdfFile(urdf_path);

  // ---- Kinematic tree: base plus three revolute joints per leg -----------------------------------
  const urdf::LinkConstSharedPtr root = urdf->getRoot();
  if (!root || root->name != "base")
    FailAt(urdf_path, "expected root link 'base', got '" + (root ? root->name : "") + "'");

  std::map<std::string, int> body_of_root_link = {{root->name, 0}};
  std::set<std::string> leg_joint_names;
  for (Leg leg : kAllLegs) {
    LegChain& chain = m.legs_[static_cast<std::size_t>(Index(leg))];
    std::string parent = root->name;
    for (int j = 0; j < kJointsPerLeg; ++j) {
      const std::string name = JointName(leg, j);
      const urdf::JointConstSharedPtr joint = urdf->getJoint(name);
      if (!joint) FailAt(urdf_path, "missing joint '" + name + "'");
      leg_joint_names.insert(name);
      if (joint->type != urdf::Joint::REVOLUTE && joint->type != urdf::Joint::CONTINUOUS) {
        FailAt(urdf_path,
               "joint '" + name + "': expected a revolute joint, got a " + JointTypeName(joint->type) + " joint");
      }
      if (joint->parent_link_name != parent) {
        FailAt(urdf_path,
               "joint '" + name + "': expected parent link '" + parent + "', got '" + joint->parent_link_name + "'");
      }
      const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
      const Eigen::Vector3d expected_axis = j == 0 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
      if (!(axis.norm() > 0.0) || (axis.normalized() - expected_axis).norm() > 1e-9) {
        FailAt(urdf_path, "joint '" + name + "': expected axis " + Vec(expected_axis) + ", got " + Vec(axis));
      }
      const Eigen::Isometry3d origin = ToIsometry(joint->parent_to_joint_origin_transform);
      if ((origin.linear() - Eigen::Matrix3d::Identity()).norm() > 1e-9) {
        double r = 0.0, p = 0.0, y = 0.0;
        joint->parent_to_joint_origin_transform.rotation.getRPY(r, p, y);
        FailAt(urdf_path, "joint '" + name + "': expected an origin without rotation, got rpy " + Vec({r, p, y}));
      }
      chain.origin_rotation[static_cast<std::size_t>(j)] = origin.linear();
      chain.origin_translation[static_cast<std::size_t>(j)] = origin.translation();
      chain.axis[static_cast<std::size_t>(j)] = axis.normalized();
      body_of_root_link[joint->child_link_name] = 1 + kJointsPerLeg * Index(leg) + j;
      parent = joint->child_link_name;
    }
  }
  for (const auto& [name, joint] : urdf->joints_) {
    if (joint->type != urdf::Joint::FIXED && !leg_joint_names.count(name)) {
      FailAt(urdf_path, "joint '" + name + "': unexpected movable joint (only the 12 leg joints may move)");
    }
  }

  // ---- Links: placement on their body, inertia, collision shapes --------------------------------
  std::vector<std::string> body_root(kNumBodies);
  for (const auto& [name, body] : body_of_root_link) body_root[static_cast<std::size_t>(body)] = name;
  m.body_mass_.fill(0.0);
  m.body_com_.fill(Eigen::Vector3d::Zero());
  for (int body = 0; body < kNumBodies; ++body) {
    const std::optional<Leg> leg =
        body == 0 ? std::nullopt : std::optional<Leg>(kAllLegs[static_cast<std::size_t>((body - 1) / kJointsPerLeg)]);
    // Depth-first over the links rigidly attached to this body, children in name order.
    std::vector<std::pair<urdf::LinkConstSharedPtr, Eigen::Isometry3d>> stack = {
        {urdf->getLink(body_root[static_cast<std::size_t>(body)]), Eigen::Isometry3d::Identity()}};
    while (!stack.empty()) {
      const auto [link, body_to_link] = stack.back();
      stack.pop_back();
      const int link_index = static_cast<int>(m.links_.size());
      RobotLink info;
      info.name = link->name;
      info.leg = leg;
      if (!link->inertial) FailAt(urdf_path, "link '" + link->name + "': missing <inertial> (every link needs a mass)");
      const urdf::Inertial& in = *link->inertial;
      if (!(in.mass > 0.0) || !std::isfinite(in.mass)) {
        FailAt(urdf_path, "link '" + link->name + "': expected a positive mass, got " + Num(in.mass));
      }
      const Eigen::Isometry3d inertial_frame = ToIsometry(in.origin);
      Eigen::Matrix3d inertia;
      inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      info.mass = in.mass;
      info.com = inertial_frame.translation();
      info.inertia = inertial_frame.linear() * inertia * inertial_frame.linear().transpose();
      m.body_mass_[static_cast<std::size_t>(body)] += in.mass;
      m.body_com_[static_cast<std::size_t>(body)] += in.mass * (body_to_link * info.com);
      m.total_mass_ += in.mass;

      for (const urdf::CollisionSharedPtr& collision : link->collision_array) {
        if (!collision || !collision->geometry) continue;
        CollisionShape shape;
        shape.name = collision->name;
        shape.link = link->name;
        shape.link_index = link_index;
        shape.leg = leg;
        shape.pose_link = ToIsometry(collision->origin);
        const urdf::Geometry& g = *collision->geometry;
        switch (g.type) {
          case urdf::Geometry::BOX: {
            const auto& box = static_cast<const urdf::Box&>(g);
            shape.kind = CollisionShape::Kind::kBox;
            shape.box_size = Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z);
            break;
          }
          case urdf::Geometry::CYLINDER: {
            const auto& cylinder = static_cast<const urdf::Cylinder&>(g);
            shape.kind = CollisionShape::Kind::kCylinder;
            shape.radius = cylinder.radius;
            shape.length = cylinder.length;
            break;
          }
          case urdf::Geometry::SPHERE:
            shape.kind = CollisionShape::Kind::kSphere;
            shape.radius = static_cast<const urdf::Sphere&>(g).radius;
            break;
          default:
            FailAt(urdf_path,
                   "link '" + link->name + "': unsupported collision geometry, expected box, cylinder or sphere");
        }
        m.collision_shapes_.push_back(std::move(shape));
      }

      m.links_.push_back(std::move(info));
      m.placements_.push_back({body, body_to_link});

      std::vector<urdf::JointSharedPtr> children = link->child_joints;
      std::sort(children.begin(), children.end(),
                [](const urdf::JointSharedPtr& a, const urdf::JointSharedPtr& b) { return a->name > b->name; });
      for (const urdf::JointSharedPtr& child : children) {
        if (child->type != urdf::Joint::FIXED) continue;  // starts another body
        stack.emplace_back(urdf->getLink(child->child_link_name),
                           body_to_link * ToIsometry(child->parent_to_joint_origin_transform));
      }
    }
  }
  RBCP_CHECK(m.links_.size() == urdf->links_.size(), "every URDF link belongs to one body");
  for (int body = 0; body < kNumBodies; ++body) {
    m.body_com_[static_cast<std::size_t>(body)] /= m.body_mass_[static_cast<std::size_t>(body)];
  }

  // ---- Planning parameters ----------------------------------------------------------------------
  const YamlMap yaml = YamlMap::LoadFile(yaml_path);
  const YamlMap reference = yaml.Map("reference_configuration");
  for (Leg leg : kAllLegs) SetLegJoints(m.q_reference_, leg, reference.Vector3(std::string(LegName(leg))));
  reference.RejectUnknownKeys();

  m.nominal_base_height_ = yaml.Double("nominal_base_height");
  if (!(m.nominal_base_height_ > 0.0)) {
    yaml.Fail("nominal_base_height", "expected a positive height, got " + Num(m.nominal_base_height_));
  }

  const YamlMap bounds = yaml.Map("joint_bounds");
  for (Leg leg : kAllLegs) {
    const YamlMap leg_bounds = bounds.Map(std::string(LegName(leg)));
    for (int j = 0; j < kJointsPerLeg; ++j) {
      const std::string key = kJointSuffix[static_cast<std::size_t>(j)];
      const Eigen::Vector2d b = leg_bounds.Vector2(key);
      const std::string got = "[" + Num(b[0]) + ", " + Num(b[1]) + "]";
      if (!(b[0] < b[1])) leg_bounds.Fail(key, "expected lower < upper, got " + got);
      if (b[0] < -M_PI || b[1] > M_PI) leg_bounds.Fail(key, "expected bounds within [-pi, pi], got " + got);
      if (j == 2 && ForeSign(leg) > 0 && b[1] > 0.0) {
        leg_bounds.Fail(key, "expected a fore knee upper bound <= 0 (X configuration), got " + got);
      }
      if (j == 2 && ForeSign(leg) < 0 && b[0] < 0.0) {
        leg_bounds.Fail(key, "expected a hind knee lower bound >= 0 (X configuration), got " + got);
      }
      m.q_lower_[kJointsPerLeg * Index(leg) + j] = b[0];
      m.q_upper_[kJointsPerLeg * Index(leg) + j] = b[1];
    }
    leg_bounds.RejectUnknownKeys();
  }
  bounds.RejectUnknownKeys();

  const YamlMap foot = yaml.Map("foot");
  m.foot_contact_offset_ = foot.Vector3("contact_offset");
  m.foot_radius_ = foot.Double("radius");
  if (!(m.foot_radius_ > 0.0)) foot.Fail("radius", "expected a positive radius, got " + Num(m.foot_radius_));
  foot.RejectUnknownKeys();

  auto positive = [&](const std::string& key) {
    const double v = yaml.Double(key);
    if (!(v > 0.0)) yaml.Fail(key, "expected a positive number, got " + Num(v));
    return v;
  };
  const YamlMap margins = yaml.Map("kinematic_margins");
  m.margins_.max_stance_hip_distance_m = margins.Double("max_stance_hip_distance");
  m.margins_.max_lift_off_hip_distance_m = margins.Double("max_lift_off_hip_distance");
  m.margins_.min_knee_bend_rad = margins.Double("min_knee_bend");
  if (!(m.margins_.max_stance_hip_distance_m > 0.0)) {
    margins.Fail("max_stance_hip_distance", "expected a positive distance, got " + Num(m.margins_.max_stance_hip_distance_m));
  }
  if (!(m.margins_.max_lift_off_hip_distance_m >= m.margins_.max_stance_hip_distance_m)) {
    margins.Fail("max_lift_off_hip_distance", "expected at least max_stance_hip_distance (" +
                                                  Num(m.margins_.max_stance_hip_distance_m) + "), got " +
                                                  Num(m.margins_.max_lift_off_hip_distance_m));
  }
  if (!(m.margins_.min_knee_bend_rad >= 0.0 && m.margins_.min_knee_bend_rad < 2.0)) {
    margins.Fail("min_knee_bend", "expected an angle in [0, 2) rad, got " + Num(m.margins_.min_knee_bend_rad));
  }
  margins.RejectUnknownKeys();
  m.torque_limit_ = positive("torque_limit");
  m.continuous_torque_limit_ = positive("continuous_torque_limit");
  if (m.continuous_torque_limit_ > m.torque_limit_) {
    yaml.Fail("continuous_torque_limit",
              "expected at most torque_limit (" + Num(m.torque_limit_) + "), got " + Num(m.continuous_torque_limit_));
  }
  m.joint_velocity_limit_ = positive("joint_velocity_limit");
  yaml.RejectUnknownKeys();

  // ---- Foot contact points and analytic IK constants ----------------------------------------------
  for (Leg leg : kAllLegs) {
    LegChain& chain = m.legs_[static_cast<std::size_t>(Index(leg))];
    const std::string foot_link = std::string(LegName(leg)) + "_FOOT";
    const int foot_index = m.LinkIndex(foot_link);
    if (foot_index < 0) FailAt(urdf_path, "missing link '" + foot_link + "'");
    const LinkPlacement& placement = m.placements_[static_cast<std::size_t>(foot_index)];
    const int shank_body = 1 + kJointsPerLeg * Index(leg) + 2;
    if (placement.body != shank_body) {
      FailAt(urdf_path, "link '" + foot_link + "': expected to be rigidly attached to '" +
                            body_root[static_cast<std::size_t>(shank_body)] + "', the child of " + JointName(leg, 2));
    }
    chain.contact_in_shank = placement.body_to_link.translation() + m.foot_contact_offset_;

    const Eigen::Vector3d& hfe = chain.origin_translation[1];
    const Eigen::Vector3d& kfe = chain.origin_translation[2];
    chain.hip = chain.origin_translation[0];
    chain.lateral = hfe.y() + kfe.y() + chain.contact_in_shank.y();
    chain.hfe_xz = Eigen::Vector2d(hfe.x(), hfe.z());
    chain.thigh_xz = Eigen::Vector2d(kfe.x(), kfe.z());
    chain.shank_xz = Eigen::Vector2d(chain.contact_in_shank.x(), chain.contact_in_shank.z());
    chain.thigh_length = chain.thigh_xz.norm();
    chain.shank_length = chain.shank_xz.norm();
    if (!(chain.thigh_length > 0.0) || !(chain.shank_length > 0.0)) {
      FailAt(urdf_path,
             std::string(LegName(leg)) + ": expected a thigh and a shank of non-zero length in the sagittal plane");
    }
    const Eigen::Vector2d& a = chain.thigh_xz;
    const Eigen::Vector2d& b = chain.shank_xz;
    chain.knee_straight = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    chain.knee_branch = -ForeSign(leg);

    // The X branch covers KFE in [straight - pi, straight] (fore) or [straight, straight + pi]
    // (hind); the bounds must lie inside it for the analytic solution to see every valid pose.
    const double kfe_lower = m.q_lower_[kJointsPerLeg * Index(leg) + 2];
    const double kfe_upper = m.q_upper_[kJointsPerLeg * Index(leg) + 2];
    const bool inside = chain.knee_branch < 0
                            ? (kfe_upper <= chain.knee_straight && kfe_lower >= chain.knee_straight - M_PI)
                            : (kfe_lower >= chain.knee_straight && kfe_upper <= chain.knee_straight + M_PI);
    if (!inside) {
      throw InputError(yaml_path + ": joint_bounds: " + std::string(LegName(leg)) +
                       ": 'KFE': expected bounds on the X side of the stretched knee (" + Num(chain.knee_straight) +
                       " rad) and short of the folded knee, got [" + Num(kfe_lower) + ", " + Num(kfe_upper) + "]");
    }
  }

  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d q_leg = LegJoints(m.q_reference_, leg);
    if (!m.WithinJointBounds(leg, q_leg)) {
      std::string reason;
      m.BoundsReason(leg, q_leg, &reason);
      reference.Fail(std::string(LegName(leg)), "expected a configuration within joint_bounds: " + reason);
    }
    m.reference_feet_[static_cast<std::size_t>(Index(leg))] = m.FootPosition(leg, q_leg);
  }
  return m;
}

}  // namespace rbcp
