// The simulated robot's bodies from the robot model: merged fixed links, principal inertias.

#include "robot_description.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>

#include "rbcp/core/error.h"

namespace rbcp::sim {
namespace {

/// The leg of a "<LEG>_FOOT" link name, nullopt for any other name.
std::optional<Leg> FootLeg(const std::string& link) {
  constexpr std::string_view kSuffix = "_FOOT";
  if (link.size() != 2 + kSuffix.size() || link.compare(2, kSuffix.size(), kSuffix) != 0) return std::nullopt;
  return LegFromName(std::string_view(link).substr(0, 2));
}

/// Mass properties of one link merged into a body, in the body frame.
struct MassPart {
  double mass;
  Eigen::Vector3d com;
  Eigen::Matrix3d inertia;  // about the part's own CoM, body axes
};

/// Walks the model's link tree from the base, a link's child joints in name order: a movable or
/// foot joint starts a body, any other fixed joint merges its child into the current body.
class Builder {
 public:
  explicit Builder(const RobotModel& model) : model_(model) {
    d_.bodies.resize(RobotDescription::kNumBodies);
    parts_.resize(RobotDescription::kNumBodies);
  }

  RobotDescription Build() {
    RobotBody& base = d_.bodies[RobotDescription::kBase];
    base.name = model_.Links().front().name;
    base.joint = RobotBody::Joint::kFloating;
    Visit(0, RobotDescription::kBase, Eigen::Isometry3d::Identity());
    for (const RobotBody& body : d_.bodies) RBCP_CHECK(!body.name.empty(), "the model has every leg joint and foot");
    for (Leg leg : kAllLegs) {
      const int shank = RobotDescription::JointBody(kJointsPerLeg * Index(leg) + 2);
      RBCP_CHECK(d_.bodies[static_cast<std::size_t>(RobotDescription::FootBody(leg))].parent == shank,
                 "the model has each foot fixed to its shank");
    }
    for (int b = 0; b < RobotDescription::kNumBodies; ++b) Finish(b);
    return std::move(d_);
  }

 private:
  /// Adds link `link` (placed at body_to_link in the frame of body `b`) to that body, then its subtree.
  void Visit(int link, int b, const Eigen::Isometry3d& body_to_link) {
    AddLink(link, b, body_to_link);
    const std::string& name = model_.Links()[static_cast<std::size_t>(link)].name;
    for (const RobotJoint& joint : model_.Joints()) {
      if (joint.parent_link != name) continue;
      const int child = model_.LinkIndex(joint.child_link);
      const Eigen::Isometry3d body_to_joint = body_to_link * joint.origin;
      if (joint.type != RobotJoint::Type::kFixed) {
        Visit(child, AddJointBody(joint, b, body_to_joint), Eigen::Isometry3d::Identity());
      } else if (const std::optional<Leg> leg = FootLeg(joint.child_link)) {
        Visit(child, AddFootBody(joint, *leg, b, body_to_joint), Eigen::Isometry3d::Identity());
      } else {
        Visit(child, b, body_to_joint);  // merged into this body
      }
    }
  }

  /// The link's name, mass properties and collision primitives added to body `b`.
  void AddLink(int link, int b, const Eigen::Isometry3d& body_to_link) {
    RobotBody& body = d_.bodies[static_cast<std::size_t>(b)];
    const RobotLink& l = model_.Links()[static_cast<std::size_t>(link)];
    body.links.push_back(l.name);
    const Eigen::Matrix3d& rotation = body_to_link.linear();
    parts_[static_cast<std::size_t>(b)].push_back(
        {l.mass, body_to_link * l.com, rotation * l.inertia * rotation.transpose()});
    for (const CollisionShape& shape : model_.CollisionShapes()) {
      if (shape.link_index == link) body.shapes.push_back({shape, body_to_link * shape.pose_link});
    }
  }

  /// The body a leg joint moves (its child link and the links fixed to it); returns its index.
  int AddJointBody(const RobotJoint& joint, int parent, const Eigen::Isometry3d& parent_to_body) {
    const int index = JointIndex(joint.name);
    RBCP_CHECK(index >= 0, "only the leg joints of the model move");
    const int c = RobotDescription::JointBody(index);
    RobotBody& body = Define(c, joint, parent, parent_to_body);
    body.joint = RobotBody::Joint::kRevolute;
    body.leg = kAllLegs[static_cast<std::size_t>(index / kJointsPerLeg)];
    body.axis = joint.axis;
    body.lower_limit = joint.lower_limit;
    body.upper_limit = joint.upper_limit;
    return c;
  }

  /// The body of a foot link, fixed to its parent body; returns its index.
  int AddFootBody(const RobotJoint& joint, Leg leg, int parent, const Eigen::Isometry3d& parent_to_body) {
    const int f = RobotDescription::FootBody(leg);
    RobotBody& foot = Define(f, joint, parent, parent_to_body);
    foot.joint = RobotBody::Joint::kFixed;
    foot.leg = leg;
    foot.is_foot = true;
    return f;
  }

  RobotBody& Define(int b, const RobotJoint& joint, int parent, const Eigen::Isometry3d& parent_to_body) {
    RobotBody& body = d_.bodies[static_cast<std::size_t>(b)];
    RBCP_CHECK(body.name.empty(), "link '" + joint.child_link + "' starts one body");
    body.name = joint.child_link;
    body.joint_name = joint.name;
    body.parent = parent;
    body.parent_to_body = parent_to_body;
    return body;
  }

  /// Combined mass, centre of mass and inertia of the merged links; principal axes.
  void Finish(int b) {
    RobotBody& body = d_.bodies[static_cast<std::size_t>(b)];
    const std::vector<MassPart>& parts = parts_[static_cast<std::size_t>(b)];
    double mass = 0.0;
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    for (const MassPart& p : parts) {
      mass += p.mass;
      weighted += p.mass * p.com;
    }
    RBCP_CHECK(mass > 0.0, "every link of the model has a positive mass");
    const Eigen::Vector3d com = weighted / mass;
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    for (const MassPart& p : parts) {
      const Eigen::Vector3d d = p.com - com;  // parallel-axis theorem
      inertia += p.inertia + p.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
    }
    inertia = 0.5 * (inertia + inertia.transpose());
    body.mass = mass;
    body.inertia_body = inertia;
    Eigen::Matrix3d axes;
    PrincipalAxes(inertia, &axes, &body.principal_inertia);
    RBCP_CHECK(body.principal_inertia.minCoeff() > 0.0, "every link of the model has a positive definite inertia");
    body.inertial_frame = Eigen::Isometry3d::Identity();
    body.inertial_frame.linear() = axes;
    body.inertial_frame.translation() = com;
    d_.total_mass += mass;
  }

  const RobotModel& model_;
  RobotDescription d_;
  std::vector<std::vector<MassPart>> parts_;  ///< per body
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

RobotDescription RobotDescription::FromModel(const RobotModel& model) { return Builder(model).Build(); }

}  // namespace rbcp::sim
