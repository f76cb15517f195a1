// Loading of the robot model: the URDF (through urdfdom, read here and nowhere else) and the
// planning parameters (strict YAML).

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <mutex>
#include <sstream>

#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
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

[[noreturn]] void FailAt(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

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

/// One URDF joint: the 12 leg joints must be revolute (or continuous), every other joint fixed.
RobotJoint ReadJoint(const urdf::Joint& joint, const std::string& path) {
  RobotJoint j;
  j.name = joint.name;
  j.parent_link = joint.parent_link_name;
  j.child_link = joint.child_link_name;
  j.origin = ToIsometry(joint.parent_to_joint_origin_transform);
  const auto fail = [&](const std::string& problem) { FailAt(path, "joint '" + joint.name + "': " + problem); };
  const bool movable = joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS;
  if (JointIndex(joint.name) < 0) {
    if (joint.type != urdf::Joint::FIXED) fail("unexpected movable joint (only the 12 leg joints may move)");
    return j;
  }
  if (!movable) fail("expected a revolute joint, got a " + JointTypeName(joint.type) + " joint");
  const Eigen::Vector3d axis(joint.axis.x, joint.axis.y, joint.axis.z);
  if (!(axis.norm() > 0.0) || !axis.allFinite()) fail("expected a non-zero axis, got " + Vec(axis));
  j.axis = axis.normalized();
  if (joint.type == urdf::Joint::CONTINUOUS) {
    j.type = RobotJoint::Type::kContinuous;
    j.lower_limit = -INFINITY;
    j.upper_limit = INFINITY;
    return j;
  }
  j.type = RobotJoint::Type::kRevolute;
  if (!joint.limits) fail("expected <limit> on a revolute joint");
  j.lower_limit = joint.limits->lower;
  j.upper_limit = joint.limits->upper;
  if (!(j.lower_limit < j.upper_limit)) {
    fail("expected lower < upper limit, got [" + Num(j.lower_limit) + ", " + Num(j.upper_limit) + "]");
  }
  return j;
}

/// Every joint of the URDF, breadth first from the root link "base", each link's child joints in
/// name order (so that nothing depends on the order of the URDF's elements).
std::vector<RobotJoint> ReadJoints(const urdf::ModelInterface& urdf, const std::string& path) {
  const urdf::LinkConstSharedPtr root = urdf.getRoot();
  if (!root || root->name != "base") FailAt(path, "expected root link 'base', got '" + (root ? root->name : "") + "'");
  for (int i = 0; i < kNumJoints; ++i) {
    if (!urdf.getJoint(JointName(i))) FailAt(path, "missing joint '" + JointName(i) + "'");
  }
  std::vector<RobotJoint> joints;
  std::deque<urdf::LinkConstSharedPtr> queue = {root};
  while (!queue.empty()) {
    const urdf::LinkConstSharedPtr link = queue.front();
    queue.pop_front();
    std::vector<urdf::JointSharedPtr> children = link->child_joints;
    std::sort(children.begin(), children.end(),
              [](const urdf::JointSharedPtr& a, const urdf::JointSharedPtr& b) { return a->name < b->name; });
    for (const urdf::JointSharedPtr& child : children) {
      joints.push_back(ReadJoint(*child, path));
      queue.push_back(urdf.getLink(child->child_link_name));
    }
  }
  return joints;
}

/// A link's name and inertial data. Every link needs an <inertial> with a positive, finite mass
/// and a positive definite inertia (see RobotModel::Load).
RobotLink ReadLinkInertia(const urdf::Link& link, const std::string& path) {
  const auto fail = [&](const std::string& problem) { FailAt(path, "link '" + link.name + "': " + problem); };
  if (!link.inertial) fail("missing <inertial> (every link needs a mass)");
  const urdf::Inertial& in = *link.inertial;
  if (!(in.mass > 0.0) || !std::isfinite(in.mass)) fail("expected a positive mass, got " + Num(in.mass));
  Eigen::Matrix3d inertia;
  inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia, Eigen::EigenvaluesOnly)
                                      .eigenvalues();
  if (!inertia.allFinite() || !(moments.minCoeff() > 0.0)) {
    fail("expected a positive definite inertia, got principal moments " + Vec(moments));
  }
  const Eigen::Isometry3d inertial_frame = ToIsometry(in.origin);
  RobotLink info;
  info.name = link.name;
  info.mass = in.mass;
  info.com = inertial_frame.translation();
  info.inertia = inertial_frame.linear() * inertia * inertial_frame.linear().transpose();
  return info;
}

/// A link's collision primitives in URDF order (link index and leg left to the caller).
std::vector<CollisionShape> ReadCollisionShapes(const urdf::Link& link, const std::string& path) {
  const auto fail = [&](const std::string& problem) { FailAt(path, "link '" + link.name + "': " + problem); };
  std::vector<CollisionShape> shapes;
  for (const urdf::CollisionSharedPtr& collision : link.collision_array) {
    if (!collision || !collision->geometry) continue;
    CollisionShape shape;
    shape.name = collision->name;
    shape.link = link.name;
    shape.pose_link = ToIsometry(collision->origin);
    const urdf::Geometry& g = *collision->geometry;
    switch (g.type) {
      case urdf::Geometry::BOX: {
        const auto& box = static_cast<const urdf::Box&>(g);
        shape.kind = CollisionShape::Kind::kBox;
        shape.box_size = Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z);
        if (!(shape.box_size.minCoeff() > 0.0)) fail("expected a box of positive size");
        break;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& cylinder = static_cast<const urdf::Cylinder&>(g);
        shape.kind = CollisionShape::Kind::kCylinder;
        shape.radius = cylinder.radius;
        shape.length = cylinder.length;
        if (!(shape.radius > 0.0 && shape.length > 0.0)) fail("expected a cylinder of positive radius and length");
        break;
      }
      case urdf::Geometry::SPHERE:
        shape.kind = CollisionShape::Kind::kSphere;
        shape.radius = static_cast<const urdf::Sphere&>(g).radius;
        if (!(shape.radius > 0.0)) fail("expected a sphere of positive radius");
        break;
      default:
        fail("unsupported collision geometry, expected box, cylinder or sphere");
    }
    shapes.push_back(std::move(shape));
  }
  return shapes;
}

const RobotJoint* FindJoint(const std::vector<RobotJoint>& joints, const std::string& name) {
  for (const RobotJoint& joint : joints) {
    if (joint.name == name) return &joint;
  }
  return nullptr;
}

/// The leg of body `body` of RobotModel's bodies (0 the trunk, 1 + 3 * leg + j the child of joint j).
std::optional<Leg> BodyLeg(int body) {
  if (body == 0) return std::nullopt;
  return kAllLegs[static_cast<std::size_t>((body - 1) / kJointsPerLeg)];
}

}  // namespace

/// The steps of RobotModel::Load, in the order Load takes them.
struct RobotModel::Loader {
  /// The name of the link that starts each body (the root link of the rigid group it moves).
  using BodyRoots = std::array<std::string, kNumBodies>;

  /// The leg joints' transform chains (each joint's parent link, axis and origin checked).
  static BodyRoots ReadLegChains(const std::string& path, RobotModel* m) {
    BodyRoots body_root;
    body_root[0] = "base";
    for (Leg leg : kAllLegs) {
      LegChain& chain = m->legs_[static_cast<std::size_t>(Index(leg))];
      std::string parent = body_root[0];
      for (int j = 0; j < kJointsPerLeg; ++j) {
        const std::string name = JointName(leg, j);
        const RobotJoint* joint = FindJoint(m->joints_, name);
        RBCP_CHECK(joint != nullptr, "ReadJoints found every leg joint");
        const auto fail = [&](const std::string& problem) { FailAt(path, "joint '" + name + "': " + problem); };
        if (joint->parent_link != parent) {
          fail("expected parent link '" + parent + "', got '" + joint->parent_link + "'");
        }
        const Eigen::Vector3d expected_axis = j == 0 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
        if ((joint->axis - expected_axis).norm() > 1e-9) {
          fail("expected axis " + Vec(expected_axis) + ", got " + Vec(joint->axis));
        }
        if ((joint->origin.linear() - Eigen::Matrix3d::Identity()).norm() > 1e-9) {
          fail("expected an origin without rotation, got rpy " + Vec(RpyFromRotation(joint->origin.linear())));
        }
        const std::size_t js = static_cast<std::size_t>(j);
        chain.origin_rotation[js] = joint->origin.linear();
        chain.origin_translation[js] = joint->origin.translation();
        chain.axis[js] = joint->axis;
        body_root[static_cast<std::size_t>(1 + kJointsPerLeg * Index(leg) + j)] = joint->child_link;
        parent = joint->child_link;
      }
    }
    return body_root;
  }

  /// Appends a link rigidly attached to `body` at body_to_link: its inertia, its collision shapes.
  static void AddLink(const urdf::Link& link, int body, const Eigen::Isometry3d& body_to_link,
                      const std::string& path, RobotModel* m) {
    const int link_index = static_cast<int>(m->links_.size());
    const std::size_t b = static_cast<std::size_t>(body);
    RobotLink info = ReadLinkInertia(link, path);
    info.leg = BodyLeg(body);
    m->body_mass_[b] += info.mass;
    m->body_com_[b] += info.mass * (body_to_link * info.com);
    m->total_mass_ += info.mass;
    for (CollisionShape& shape : ReadCollisionShapes(link, path)) {
      shape.link_index = link_index;
      shape.leg = info.leg;
      m->collision_shapes_.push_back(std::move(shape));
    }
    m->links_.push_back(std::move(info));
    m->placements_.push_back({body, body_to_link});
  }

  /// Every link on its body: the body's root link, then depth-first over the links fixed to it,
  /// children in name order. Sums the bodies' masses and centres of mass.
  static void PlaceLinks(const urdf::ModelInterface& urdf, const BodyRoots& body_root, const std::string& path,
                         RobotModel* m) {
    m->body_mass_.fill(0.0);
    m->body_com_.fill(Eigen::Vector3d::Zero());
    for (int body = 0; body < kNumBodies; ++body) {
      std::vector<std::pair<std::string, Eigen::Isometry3d>> stack = {
          {body_root[static_cast<std::size_t>(body)], Eigen::Isometry3d::Identity()}};
      while (!stack.empty()) {
        const auto [name, body_to_link] = stack.back();
        stack.pop_back();
        AddLink(*urdf.getLink(name), body, body_to_link, path, m);
        // Joints() lists a link's child joints in name order: push them last to first.
        for (auto joint = m->joints_.rbegin(); joint != m->joints_.rend(); ++joint) {
          if (joint->parent_link != name || joint->type != RobotJoint::Type::kFixed) continue;
          stack.emplace_back(joint->child_link, body_to_link * joint->origin);
        }
      }
    }
    RBCP_CHECK(m->links_.size() == urdf.links_.size(), "every URDF link belongs to one body");
    for (std::size_t body = 0; body < m->body_com_.size(); ++body) m->body_com_[body] /= m->body_mass_[body];
  }

  /// Planning joint bounds, per leg and joint (inside [-pi, pi], knees on their X side of zero).
  static void ReadJointBounds(const YamlMap& yaml, RobotModel* m) {
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
        m->q_lower_[kJointsPerLeg * Index(leg) + j] = b[0];
        m->q_upper_[kJointsPerLeg * Index(leg) + j] = b[1];
      }
      leg_bounds.RejectUnknownKeys();
    }
    bounds.RejectUnknownKeys();
  }

  static void ReadMargins(const YamlMap& yaml, RobotModel* m) {
    const YamlMap margins = yaml.Map("kinematic_margins");
    KinematicMargins& k = m->margins_;
    k.max_stance_hip_distance_m = margins.Double("max_stance_hip_distance");
    k.max_lift_off_hip_distance_m = margins.Double("max_lift_off_hip_distance");
    k.min_knee_bend_rad = margins.Double("min_knee_bend");
    if (!(k.max_stance_hip_distance_m > 0.0)) {
      margins.Fail("max_stance_hip_distance", "expected a positive distance, got " + Num(k.max_stance_hip_distance_m));
    }
    if (!(k.max_lift_off_hip_distance_m >= k.max_stance_hip_distance_m)) {
      margins.Fail("max_lift_off_hip_distance", "expected at least max_stance_hip_distance (" +
                                                    Num(k.max_stance_hip_distance_m) + "), got " +
                                                    Num(k.max_lift_off_hip_distance_m));
    }
    if (!(k.min_knee_bend_rad >= 0.0 && k.min_knee_bend_rad < 2.0)) {
      margins.Fail("min_knee_bend", "expected an angle in [0, 2) rad, got " + Num(k.min_knee_bend_rad));
    }
    margins.RejectUnknownKeys();
  }

  /// The planning parameters of the YAML file, `reference` its reference_configuration map.
  static void ReadParameters(const YamlMap& yaml, const YamlMap& reference, RobotModel* m) {
    for (Leg leg : kAllLegs) SetLegJoints(m->q_reference_, leg, reference.Vector3(std::string(LegName(leg))));
    reference.RejectUnknownKeys();

    m->nominal_base_height_ = yaml.Double("nominal_base_height");
    if (!(m->nominal_base_height_ > 0.0)) {
      yaml.Fail("nominal_base_height", "expected a positive height, got " + Num(m->nominal_base_height_));
    }
    ReadJointBounds(yaml, m);

    const YamlMap foot = yaml.Map("foot");
    m->foot_contact_offset_ = foot.Vector3("contact_offset");
    m->foot_radius_ = foot.Double("radius");
    if (!(m->foot_radius_ > 0.0)) foot.Fail("radius", "expected a positive radius, got " + Num(m->foot_radius_));
    foot.RejectUnknownKeys();

    auto positive = [&](const std::string& key) {
      const double v = yaml.Double(key);
      if (!(v > 0.0)) yaml.Fail(key, "expected a positive number, got " + Num(v));
      return v;
    };
    ReadMargins(yaml, m);
    m->torque_limit_ = positive("torque_limit");
    m->continuous_torque_limit_ = positive("continuous_torque_limit");
    if (m->continuous_torque_limit_ > m->torque_limit_) {
      yaml.Fail("continuous_torque_limit", "expected at most torque_limit (" + Num(m->torque_limit_) + "), got " +
                                               Num(m->continuous_torque_limit_));
    }
    m->joint_velocity_limit_ = positive("joint_velocity_limit");
    yaml.RejectUnknownKeys();
  }

  /// The foot contact point of a leg in its shank frame: the <LEG>_FOOT link, which must be fixed
  /// to the shank, plus the YAML's contact offset.
  static Eigen::Vector3d ContactInShank(Leg leg, const BodyRoots& body_root, const std::string& urdf_path,
                                        const RobotModel& m) {
    const std::string foot_link = std::string(LegName(leg)) + "_FOOT";
    const int foot_index = m.LinkIndex(foot_link);
    if (foot_index < 0) FailAt(urdf_path, "missing link '" + foot_link + "'");
    const LinkPlacement& placement = m.placements_[static_cast<std::size_t>(foot_index)];
    const int shank_body = 1 + kJointsPerLeg * Index(leg) + 2;
    if (placement.body != shank_body) {
      FailAt(urdf_path, "link '" + foot_link + "': expected to be rigidly attached to '" +
                            body_root[static_cast<std::size_t>(shank_body)] + "', the child of " + JointName(leg, 2));
    }
    return placement.body_to_link.translation() + m.foot_contact_offset_;
  }

  /// The analytic IK constants of a leg; its knee bounds must lie on the X branch.
  static void SetIkConstants(Leg leg, const BodyRoots& body_root, const std::string& urdf_path,
                             const std::string& yaml_path, RobotModel* m) {
    LegChain& chain = m->legs_[static_cast<std::size_t>(Index(leg))];
    chain.contact_in_shank = ContactInShank(leg, body_root, urdf_path, *m);
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
    const double kfe_lower = m->q_lower_[kJointsPerLeg * Index(leg) + 2];
    const double kfe_upper = m->q_upper_[kJointsPerLeg * Index(leg) + 2];
    const bool inside = chain.knee_branch < 0
                            ? (kfe_upper <= chain.knee_straight && kfe_lower >= chain.knee_straight - M_PI)
                            : (kfe_lower >= chain.knee_straight && kfe_upper <= chain.knee_straight + M_PI);
    if (!inside) {
      throw InputError(yaml_path + ": joint_bounds: " + std::string(LegName(leg)) +
                       ": 'KFE': expected bounds on the X side of the stretched knee (" + Num(chain.knee_straight) +
                       " rad) and short of the folded knee, got [" + Num(kfe_lower) + ", " + Num(kfe_upper) + "]");
    }
  }

  /// The reference configuration within the bounds; its foot positions.
  static void SetReferenceFeet(const YamlMap& reference, RobotModel* m) {
    for (Leg leg : kAllLegs) {
      const Eigen::Vector3d q_leg = LegJoints(m->q_reference_, leg);
      if (!m->WithinJointBounds(leg, q_leg)) {
        std::string reason;
        m->BoundsReason(leg, q_leg, &reason);
        reference.Fail(std::string(LegName(leg)), "expected a configuration within joint_bounds: " + reason);
      }
      m->reference_feet_[static_cast<std::size_t>(Index(leg))] = m->FootPosition(leg, q_leg);
    }
  }
};

std::string JointName(Leg leg, int j) {
  RBCP_CHECK(j >= 0 && j < kJointsPerLeg, "joint index within a leg");
  return std::string(LegName(leg)) + "_" + kJointSuffix[static_cast<std::size_t>(j)];
}

std::string JointName(int joint_index) {
  RBCP_CHECK(joint_index >= 0 && joint_index < kNumJoints, "joint index");
  return JointName(kAllLegs[static_cast<std::size_t>(joint_index / kJointsPerLeg)], joint_index % kJointsPerLeg);
}

int JointIndex(const std::string& joint_name) {
  for (int i = 0; i < kNumJoints; ++i) {
    if (JointName(i) == joint_name) return i;
  }
  return -1;
}

RobotModel RobotModel::LoadDefault(const std::string& config_dir) {
  return Load(config_dir + "/robots/anymal_b.urdf", config_dir + "/robots/anymal_b.yaml");
}

RobotModel RobotModel::Load(const std::string& urdf_path, const std::string& yaml_path) {
  RobotModel m;
  const urdf::ModelInterfaceSharedPtr urdf = ParseUrdfFile(urdf_path);
  m.joints_ = ReadJoints(*urdf, urdf_path);
  const Loader::BodyRoots body_root = Loader::ReadLegChains(urdf_path, &m);
  Loader::PlaceLinks(*urdf, body_root, urdf_path, &m);

  const YamlMap yaml = YamlMap::LoadFile(yaml_path);
  const YamlMap reference = yaml.Map("reference_configuration");
  Loader::ReadParameters(yaml, reference, &m);
  for (Leg leg : kAllLegs) Loader::SetIkConstants(leg, body_root, urdf_path, yaml_path, &m);
  Loader::SetReferenceFeet(reference, &m);
  return m;
}

}  // namespace rbcp
