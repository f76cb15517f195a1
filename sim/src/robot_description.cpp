// The simulated robot's bodies from the URDF (urdfdom): merged fixed links, principal inertias.

#include "robot_description.h"

#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "rbcp/core/error.h"

namespace rbcp::sim {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

Eigen::Isometry3d ToIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return T;
}

/// The leg of a "<LEG>_FOOT" link name, nullopt for any other name.
std::optional<Leg> FootLeg(const std::string& link) {
  constexpr std::string_view kSuffix = "_FOOT";
  if (link.size() != 2 + kSuffix.size() || link.compare(2, kSuffix.size(), kSuffix) != 0) return std::nullopt;
  return LegFromName(std::string_view(link).substr(0, 2));
}

/// Mass properties of the links merged into one body, in the body frame.
struct MassAccumulator {
  struct Part {
    double mass;
    Eigen::Vector3d com;
    Eigen::Matrix3d inertia;  // about the part's own CoM, body axes
  };
  std::vector<Part> parts;
};

class Builder {
 public:
  Builder(std::string path, urdf::ModelInterfaceSharedPtr model) : path_(std::move(path)), model_(std::move(model)) {
    d_.bodies.resize(RobotDescription::kNumBodies);
    mass_.resize(RobotDescription::kNumBodies);
    defined_.assign(RobotDescription::kNumBodies, false);
  }

  RobotDescription Build() {
    const urdf::LinkConstSharedPtr root = model_->getRoot();
    if (!root || root->name != "base") Fail("expected root link 'base', got '" + (root ? root->name : "") + "'");
    RobotBody& base = d_.bodies[RobotDescription::kBase];
    base.name = root->name;
    base.joint = RobotBody::Joint::kFloating;
    defined_[RobotDescription::kBase] = true;
    Visit(root, RobotDescription::kBase, Eigen::Isometry3d::Identity());

    for (int i = 0; i < kNumJoints; ++i) {
      if (!defined_[static_cast<std::size_t>(RobotDescription::JointBody(i))]) Fail("missing joint '" + JointName(i) + "'");
    }
    for (Leg leg : kAllLegs) {
      const int b = RobotDescription::FootBody(leg);
      const std::string foot = std::string(LegName(leg)) + "_FOOT";
      if (!defined_[static_cast<std::size_t>(b)]) Fail("missing link '" + foot + "' (fixed to the shank)");
      const int shank = RobotDescription::JointBody(kJointsPerLeg * Index(leg) + 2);
      if (d_.bodies[static_cast<std::size_t>(b)].parent != shank) {
        Fail("link '" + foot + "': expected to be rigidly attached to the child of " + JointName(leg, 2));
      }
    }
    for (int b = 0; b < RobotDescription::kNumBodies; ++b) Finish(b);
    return std::move(d_);
  }

 private:
  [[noreturn]] void Fail(const std::string& problem) const { throw InputError(path_ + ": " + problem); }

  /// Adds `link` (placed at body_to_link in the body frame) to body `b`, then its subtree.
  void Visit(const urdf::LinkConstSharedPtr& link, int b, const Eigen::Isometry3d& body_to_link) {
    RobotBody& body = d_.bodies[static_cast<std::size_t>(b)];
    body.links.push_back(link->name);
    if (link->inertial) {
      const urdf::Inertial& in = *link->inertial;
      if (!std::isfinite(in.mass) || in.mass < 0.0) {
        Fail("link '" + link->name + "': expected a non-negative mass, got " + Num(in.mass));
      }
      const Eigen::Isometry3d inertial = body_to_link * ToIsometry(in.origin);
      Eigen::Matrix3d inertia;
      inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      mass_[static_cast<std::size_t>(b)].parts.push_back(
          {in.mass, inertial.translation(), inertial.linear() * inertia * inertial.linear().transpose()});
    }
    for (const urdf::CollisionSharedPtr& collision : link->collision_array) {
      if (!collision || !collision->geometry) continue;
      BodyShape shape;
      shape.link = link->name;
      shape.name = collision->name;
      shape.pose_body = body_to_link * ToIsometry(collision->origin);
      const urdf::Geometry& g = *collision->geometry;
      switch (g.type) {
        case urdf::Geometry::BOX: {
          const auto& box = static_cast<const urdf::Box&>(g);
          shape.kind = CollisionShape::Kind::kBox;
          shape.box_size = Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z);
          if (!(shape.box_size.minCoeff() > 0.0)) Fail("link '" + link->name + "': expected a box of positive size");
          break;
        }
        case urdf::Geometry::CYLINDER: {
          const auto& cylinder = static_cast<const urdf::Cylinder&>(g);
          shape.kind = CollisionShape::Kind::kCylinder;
          shape.radius = cylinder.radius;
          shape.length = cylinder.length;
          if (!(shape.radius > 0.0 && shape.length > 0.0)) {
            Fail("link '" + link->name + "': expected a cylinder of positive radius and length");
          }
          break;
        }
        case urdf::Geometry::SPHERE:
          shape.kind = CollisionShape::Kind::kSphere;
          shape.radius = static_cast<const urdf::Sphere&>(g).radius;
          if (!(shape.radius > 0.0)) Fail("link '" + link->name + "': expected a sphere of positive radius");
          break;
        default:
          Fail("link '" + link->name + "': unsupported collision geometry, expected box, cylinder or sphere");
      }
      body.shapes.push_back(std::move(shape));
    }

    // Children in name order, so that the build does not depend on the URDF's element order.
    std::vector<urdf::JointSharedPtr> children = link->child_joints;
    std::sort(children.begin(), children.end(),
              [](const urdf::JointSharedPtr& a, const urdf::JointSharedPtr& c) { return a->name < c->name; });
    for (const urdf::JointSharedPtr& joint : children) {
      const urdf::LinkConstSharedPtr child = model_->getLink(joint->child_link_name);
      if (!child) Fail("joint '" + joint->name + "': missing child link '" + joint->child_link_name + "'");
      const Eigen::Isometry3d body_to_joint = body_to_link * ToIsometry(joint->parent_to_joint_origin_transform);
      if (joint->type == urdf::Joint::FIXED) {
        if (const std::optional<Leg> leg = FootLeg(child->name)) {
          const int f = RobotDescription::FootBody(*leg);
          RobotBody& foot = Define(f, child->name);
          foot.joint = RobotBody::Joint::kFixed;
          foot.joint_name = joint->name;
          foot.parent = b;
          foot.leg = leg;
          foot.is_foot = true;
          foot.parent_to_body = body_to_joint;
          Visit(child, f, Eigen::Isometry3d::Identity());
        } else {
          Visit(child, b, body_to_joint);  // merged into this body
        }
        continue;
      }
      if (joint->type != urdf::Joint::REVOLUTE && joint->type != urdf::Joint::CONTINUOUS) {
        Fail("joint '" + joint->name + "': unexpected movable joint (only the 12 revolute leg joints may move)");
      }
      int index = -1;
      for (int i = 0; i < kNumJoints; ++i) {
        if (JointName(i) == joint->name) index = i;
      }
      if (index < 0) Fail("joint '" + joint->name + "': unexpected movable joint (only the 12 leg joints may move)");
      const int expected_parent = index % kJointsPerLeg == 0 ? RobotDescription::kBase : RobotDescription::JointBody(index - 1);
      if (b != expected_parent) {
        Fail("joint '" + joint->name + "': expected parent link '" + d_.bodies[static_cast<std::size_t>(expected_parent)].name +
             "' (or a link fixed to it), got '" + link->name + "'");
      }
      const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
      if (!(axis.norm() > 0.0) || !axis.allFinite()) Fail("joint '" + joint->name + "': expected a non-zero axis");
      const int c = RobotDescription::JointBody(index);
      RobotBody& body_c = Define(c, child->name);
      body_c.joint = RobotBody::Joint::kRevolute;
      body_c.joint_name = joint->name;
      body_c.parent = b;
      body_c.leg = kAllLegs[static_cast<std::size_t>(index / kJointsPerLeg)];
      body_c.parent_to_body = body_to_joint;
      body_c.axis = axis.normalized();
      if (joint->type == urdf::Joint::REVOLUTE) {
        if (!joint->limits) Fail("joint '" + joint->name + "': expected <limit> on a revolute joint");
        body_c.lower_limit = joint->limits->lower;
        body_c.upper_limit = joint->limits->upper;
        if (!(body_c.lower_limit < body_c.upper_limit)) {
          Fail("joint '" + joint->name + "': expected lower < upper limit, got [" + Num(body_c.lower_limit) + ", " +
               Num(body_c.upper_limit) + "]");
        }
      } else {
        body_c.lower_limit = -INFINITY;
        body_c.upper_limit = INFINITY;
      }
      Visit(child, c, Eigen::Isometry3d::Identity());
    }
  }

  RobotBody& Define(int b, const std::string& name) {
    if (defined_[static_cast<std::size_t>(b)]) Fail("link '" + name + "': defined twice");
    defined_[static_cast<std::size_t>(b)] = true;
    RobotBody& body = d_.bodies[static_cast<std::size_t>(b)];
    body.name = name;
    return body;
  }

  /// Combined mass, centre of mass and inertia of the merged links; principal axes.
  void Finish(int b) {
    RobotBody& body = d_.bodies[static_cast<std::size_t>(b)];
    const auto& parts = mass_[static_cast<std::size_t>(b)].parts;
    double mass = 0.0;
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    for (const auto& p : parts) {
      mass += p.mass;
      weighted += p.mass * p.com;
    }
    if (!(mass > 0.0)) Fail("link '" + body.name + "': expected a positive mass for the body it starts, got " + Num(mass));
    const Eigen::Vector3d com = weighted / mass;
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    for (const auto& p : parts) {
      const Eigen::Vector3d d = p.com - com;  // parallel-axis theorem
      inertia += p.inertia + p.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
    }
    inertia = 0.5 * (inertia + inertia.transpose());
    body.mass = mass;
    body.inertia_body = inertia;
    Eigen::Matrix3d axes;
    PrincipalAxes(inertia, &axes, &body.principal_inertia);
    if (!(body.principal_inertia.minCoeff() > 0.0)) {
      Fail("link '" + body.name + "': expected a positive definite inertia, got principal moments (" +
           Num(body.principal_inertia.x()) + " " + Num(body.principal_inertia.y()) + " " + Num(body.principal_inertia.z()) + ")");
    }
    body.inertial_frame = Eigen::Isometry3d::Identity();
    body.inertial_frame.linear() = axes;
    body.inertial_frame.translation() = com;
    d_.total_mass += mass;
  }

  std::string path_;
  urdf::ModelInterfaceSharedPtr model_;
  RobotDescription d_;
  std::vector<MassAccumulator> mass_;
  std::vector<bool> defined_;
};

}  // namespace

void PrincipalAxes(const Eigen::Matrix3d& inertia, Eigen::Matrix3d* rotation, Eigen::Vector3d* principal) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(inertia);
  const Eigen::Matrix3d& v = solver.eigenvectors();
  const Eigen::Vector3d& lambda = solver.eigenvalues();
  // Match eigenvectors to coordinate axes: the permutation with the largest |diagonal| sum.
  std::array<int, 3> perm = {0, 1, 2};
  std::array<int, 3> best = perm;
  double best_score = -1.0;
  do {
    const double score = std::abs(v(0, perm[0])) + std::abs(v(1, perm[1])) + std::abs(v(2, perm[2]));
    if (score > best_score) {
      best_score = score;
      best = perm;
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  for (int i = 0; i < 3; ++i) {
    const int k = best[static_cast<std::size_t>(i)];
    rotation->col(i) = v(i, k) < 0.0 ? Eigen::Vector3d(-v.col(k)) : Eigen::Vector3d(v.col(k));
    (*principal)(i) = lambda(k);
  }
  if (rotation->determinant() < 0.0) {
    // Only possible when an axis is far from every coordinate axis: flip the least aligned one.
    int worst = 0;
    for (int i = 1; i < 3; ++i) {
      if (std::abs((*rotation)(i, i)) < std::abs((*rotation)(worst, worst))) worst = i;
    }
    rotation->col(worst) = -rotation->col(worst);
  }
}

RobotDescription RobotDescription::FromUrdf(const std::string& urdf_path) {
  if (!std::ifstream(urdf_path)) throw InputError(urdf_path + ": cannot open file");
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDFFile(urdf_path);
  } catch (const std::exception& e) {
    throw InputError(urdf_path + ": invalid URDF: " + e.what());
  }
  if (!model) throw InputError(urdf_path + ": invalid URDF");
  return Builder(urdf_path, model).Build();
}

}  // namespace rbcp::sim
