#include "rbcp/collision/robot_terrain_collision.h"

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "fcl_shape.h"
#include "rbcp/core/error.h"
#include "terrain_grid.h"

namespace rbcp {

using collision_detail::Aabb;
using collision_detail::FclShape;
using collision_detail::GridTriangle;
using collision_detail::kSeparationSlack;
using collision_detail::TerrainGrid;

namespace {

constexpr char kTerrainName[] = "terrain";

// The narrow phase of the terrain test: FCL's primitive-triangle intersection (exact for spheres,
// GJK for boxes and cylinders; with a depth pointer it also measures the penetration depth).
const fcl::detail::GJKSolver_libccd<double>& Narrowphase() {
  static const fcl::detail::GJKSolver_libccd<double> solver;
  return solver;
}

std::string Text(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

// Exact test of the shape at pose T against one terrain triangle; with `depth`, also its
// penetration depth (FCL measures it only when the contact point and normal are requested too).
inline bool TouchesTriangle(const FclShape& s, const Eigen::Isometry3d& T, const GridTriangle& t, double* depth) {
  Eigen::Vector3d point, normal;
  Eigen::Vector3d* point_out = depth != nullptr ? &point : nullptr;
  Eigen::Vector3d* normal_out = depth != nullptr ? &normal : nullptr;
  const auto& [a, b, c] = t.corners;
  switch (s.kind) {
    case CollisionShape::Kind::kBox:
      return Narrowphase().shapeTriangleIntersect(static_cast<const fcl::Boxd&>(*s.geometry), T, a, b, c, point_out,
                                                  depth, normal_out);
    case CollisionShape::Kind::kCylinder:
      return Narrowphase().shapeTriangleIntersect(static_cast<const fcl::Cylinderd&>(*s.geometry), T, a, b, c,
                                                  point_out, depth, normal_out);
    case CollisionShape::Kind::kSphere:
    default:
      return Narrowphase().shapeTriangleIntersect(static_cast<const fcl::Sphered&>(*s.geometry), T, a, b, c,
                                                  point_out, depth, normal_out);
  }
}

// A cheap sufficient test that a shape does not touch a terrain triangle (whose own normal the
// caller has tested): the line from the shape's centre to the triangle's centroid, the box face
// normals, the cylinder axis as separating axes.
inline bool SeparatedFromTriangle(const FclShape& s, const Eigen::Isometry3d& T, const GridTriangle& t) {
  const Eigen::Vector3d& p = t.corners[0];
  const Eigen::Vector3d& q = t.corners[1];
  const Eigen::Vector3d& r = t.corners[2];
  const auto apart = [&](const Eigen::Vector3d& n) {
    const double c = n.dot(T.translation());
    const double lo = std::min({n.dot(p), n.dot(q), n.dot(r)});
    const double hi = std::max({n.dot(p), n.dot(q), n.dot(r)});
    const double half = s.Support(T, n);
    return c - half > hi + kSeparationSlack || c + half < lo - kSeparationSlack;
  };
  const Eigen::Vector3d d = (p + q + r) / 3.0 - T.translation();
  const double length = d.norm();
  if (length > 1e-12 && apart(d / length)) return true;
  std::array<Eigen::Vector3d, 3> axes;
  for (int k = s.Axes(T, axes) - 1; k >= 0; --k) {
    if (apart(axes[static_cast<std::size_t>(k)])) return true;
  }
  return false;
}

// Per-thread link poses: queries stay const, thread-safe and allocation-free once warm.
std::vector<Eigen::Isometry3d>& ThreadLinkPoses() {
  static thread_local std::vector<Eigen::Isometry3d> link_poses;
  return link_poses;
}

}  // namespace

struct RobotTerrainCollision::Impl {
  CollisionOptions options;
  RobotSelfCollision self;  // the robot, its collision model and the self-collision test
  // Link poses in the base frame at the reference configuration (the trunk's never change).
  std::vector<Eigen::Isometry3d> reference_link_poses;
  std::unique_ptr<TerrainGrid> grid;

  // The model's primitives in RobotCollisionModel::Primitives() order, then the stance variants.
  std::vector<FclShape> shapes;
  // For each shape, the shape whose penetration depth is reported for it: itself, except for
  // the shrunk stance foot, which reports the depth of the full foot sphere.
  std::vector<int> depth_shape;
  // Shape lists, hip to foot for a leg: the model's (trunk, swing) and a stance leg's, with the
  // stance foot and adapter.
  std::vector<int> trunk;
  std::array<std::vector<int>, kNumLegs> swing;
  std::array<std::vector<int>, kNumLegs> stance;

  Impl(const RobotModel& robot, const CollisionOptions& o)
      : options(o),
        self(robot, RobotCollisionModel(robot, CollisionMargins{o.thigh_margin, o.trunk_margin}),
             o.measure_penetration) {}

  const RobotModel& Robot() const { return self.Robot(); }
  const RobotCollisionModel& Model() const { return self.Model(); }
  // A leg's shapes, hip to foot: those of a swing leg, or of a stance leg.
  const std::vector<int>& LegShapes(Leg leg, bool in_contact) const {
    const auto l = static_cast<std::size_t>(Index(leg));
    return in_contact ? stance[l] : swing[l];
  }

  void BuildShapes();
  void AddStanceShapes(Leg leg);

  // Visits the terrain triangles that shape s at `pose` may touch (broad phase: grid cells,
  // triangle bounds, the triangle's plane against the shape's extent along its normal) until
  // visit returns true.
  template <typename Visit>
  bool AnyTriangleTouching(const FclShape& s, const Eigen::Isometry3d& pose, const Aabb& box, Visit&& visit) const {
    return grid->AnyTriangleNear(box, [&](const GridTriangle& t) {
      if (std::abs(t.normal.dot(pose.translation()) - t.offset) > s.Support(pose, t.normal)) return false;
      return visit(t);
    });
  }

  // Deepest penetration of the shape over the terrain triangles it touches.
  double TerrainDepth(const FclShape& s, const Eigen::Isometry3d& link_W) const {
    const Eigen::Isometry3d pose = link_W * s.pose_link;
    double deepest = 0.0;
    AnyTriangleTouching(s, pose, s.Bounds(pose), [&](const GridTriangle& t) {
      double depth = 0.0;
      // The magnitude is the depth (FCL's solvers differ in sign conventions).
      if (TouchesTriangle(s, pose, t, &depth)) deepest = std::max(deepest, std::abs(depth));
      return false;
    });
    return deepest;
  }

  // Tests shape i placed by its link pose in the world; fills `report` on collision.
  bool ShapeHitsTerrain(int i, const Eigen::Isometry3d& link_W, CollisionReport* report) const {
    const FclShape& s = shapes[static_cast<std::size_t>(i)];
    const Eigen::Isometry3d pose = link_W * s.pose_link;
    const Aabb box = s.Bounds(pose);
    if (!box.Overlaps(grid->Bounds())) return false;
    if (box.lo.z() > grid->MaxHeightOver(box)) return false;
    double depth = 0.0;
    if (AnyTriangleTouching(s, pose, box, [&](const GridTriangle& t) {
          return !SeparatedFromTriangle(s, pose, t) && TouchesTriangle(s, pose, t, nullptr);
        })) {
      if (options.measure_penetration) {
        depth = TerrainDepth(shapes[static_cast<std::size_t>(depth_shape[static_cast<std::size_t>(i)])], link_W);
      }
    } else if (!grid->Bounds().Contains(box) || !grid->Inside(pose.translation(), &depth)) {
      return false;
    }
    report->collision = true;
    report->first_shape = s.name;
    report->obstacle = kTerrainName;
    report->penetration = depth;
    return true;
  }

  // Tests the shapes of `list` in order; link_poses are the link poses in the base frame.
  bool ListHitsTerrain(const std::vector<int>& list, const Eigen::Isometry3d& base_W,
                       const std::vector<Eigen::Isometry3d>& link_poses, CollisionReport* report) const {
    for (int i : list) {
      const FclShape& s = shapes[static_cast<std::size_t>(i)];
      const Eigen::Isometry3d link_W = base_W * link_poses[static_cast<std::size_t>(s.link_index)];
      if (ShapeHitsTerrain(i, link_W, report)) return true;
    }
    return false;
  }
};

void RobotTerrainCollision::Impl::BuildShapes() {
  reference_link_poses = Robot().LinkPoses(Robot().ReferenceConfiguration());
  for (const CollisionPrimitive& p : Model().Primitives()) {
    depth_shape.push_back(static_cast<int>(shapes.size()));
    shapes.emplace_back(p);
  }
  trunk = Model().Trunk();
  for (Leg leg : kAllLegs) {
    swing[static_cast<std::size_t>(Index(leg))] = Model().LegPrimitives(leg);
    AddStanceShapes(leg);
  }
}

// The stance variants of a leg's foot and adapter tube (see the header), and the leg's stance list.
void RobotTerrainCollision::Impl::AddStanceShapes(Leg leg) {
  const auto& links = Robot().Links();
  const std::string foot_link = std::string(LegName(leg)) + "_FOOT";
  const std::string adapter_link = std::string(LegName(leg)) + "_ADAPTER";
  int foot = -1;
  int adapter = -1;
  for (int i : Model().LegPrimitives(leg)) {
    const FclShape& s = shapes[static_cast<std::size_t>(i)];
    const std::string& link = links[static_cast<std::size_t>(s.link_index)].name;
    if (link == foot_link && s.kind == CollisionShape::Kind::kSphere && foot < 0) foot = i;
    if (link == adapter_link && s.kind == CollisionShape::Kind::kCylinder && adapter < 0) adapter = i;
  }
  if (foot < 0) throw InputError("robot collision model: expected a sphere on link '" + foot_link + "', got none");
  if (adapter < 0) {
    throw InputError("robot collision model: expected a cylinder on link '" + adapter_link + "', got none");
  }
  const FclShape& foot_shape = shapes[static_cast<std::size_t>(foot)];
  const FclShape& adapter_shape = shapes[static_cast<std::size_t>(adapter)];
  if (!(options.foot_tolerance >= 0.0 && options.foot_tolerance < foot_shape.radius)) {
    throw InputError("collision options: 'foot_tolerance': expected a depth in [0, " + Text(foot_shape.radius) +
                     ") m (the foot radius), got " + Text(options.foot_tolerance));
  }
  if (!(options.adapter_exclusion >= 0.0 && options.adapter_exclusion < 2.0 * adapter_shape.half_length)) {
    throw InputError("collision options: 'adapter_exclusion': expected a length in [0, " +
                     Text(2.0 * adapter_shape.half_length) + ") m (the adapter tube), got " +
                     Text(options.adapter_exclusion));
  }

  // Stance foot: the same sphere shrunk by the tolerance; its depth is reported for the full one.
  FclShape stance_foot = foot_shape;
  stance_foot.radius = foot_shape.radius - options.foot_tolerance;
  stance_foot.MakeGeometry();

  // Stance adapter: the tube shortened at the end nearer to the foot sphere's centre (the foot
  // and adapter links ride on the same body, so their relative pose is fixed).
  FclShape stance_adapter = adapter_shape;
  const Eigen::Isometry3d foot_in_adapter_link =
      reference_link_poses[static_cast<std::size_t>(adapter_shape.link_index)].inverse() *
      reference_link_poses[static_cast<std::size_t>(foot_shape.link_index)] * foot_shape.pose_link;
  const Eigen::Vector3d foot_in_tube = adapter_shape.pose_link.inverse() * foot_in_adapter_link.translation();
  const double toward_foot = foot_in_tube.z() < 0.0 ? -1.0 : 1.0;
  stance_adapter.half_length = adapter_shape.half_length - 0.5 * options.adapter_exclusion;
  stance_adapter.pose_link =
      adapter_shape.pose_link * Eigen::Translation3d(0.0, 0.0, -toward_foot * 0.5 * options.adapter_exclusion);
  stance_adapter.MakeGeometry();

  std::vector<int>& list = stance[static_cast<std::size_t>(Index(leg))];
  for (int i : Model().LegPrimitives(leg)) {
    if (i != foot && i != adapter) {
      list.push_back(i);
      continue;
    }
    const int variant = static_cast<int>(shapes.size());
    list.push_back(variant);
    depth_shape.push_back(i == foot ? foot : variant);
    shapes.push_back(i == foot ? std::move(stance_foot) : std::move(stance_adapter));
  }
}

RobotTerrainCollision::RobotTerrainCollision(const RobotModel& robot, const TriangleMesh& terrain,
                                             const CollisionOptions& options) {
  const std::string problem = ValidateMesh(terrain);
  if (!problem.empty()) throw InputError("robot-terrain collision: expected a valid terrain mesh, got: " + problem);
  if (!(options.trunk_margin >= 0.0 && options.trunk_margin < 0.1)) {
    throw InputError("collision options: 'trunk_margin': expected a clearance in [0, 0.1) m, got " +
                     Text(options.trunk_margin));
  }
  if (!(options.thigh_margin >= 0.0 && options.thigh_margin < 0.1)) {
    throw InputError("collision options: 'thigh_margin': expected a clearance in [0, 0.1) m, got " +
                     Text(options.thigh_margin));
  }
  impl_ = std::make_unique<Impl>(robot, options);
  impl_->BuildShapes();
  impl_->grid = std::make_unique<TerrainGrid>(terrain);
}

RobotTerrainCollision::~RobotTerrainCollision() = default;
RobotTerrainCollision::RobotTerrainCollision(RobotTerrainCollision&&) noexcept = default;
RobotTerrainCollision& RobotTerrainCollision::operator=(RobotTerrainCollision&&) noexcept = default;

CollisionReport RobotTerrainCollision::CheckRobot(const Eigen::Isometry3d& base_W, const JointVector& q,
                                                  const std::array<bool, kNumLegs>& feet_in_contact) const {
  RBCP_CHECK(q.allFinite() && base_W.matrix().allFinite(), "collision query with a non-finite pose or joint vector");
  const Impl& m = *impl_;
  std::vector<Eigen::Isometry3d>& link_poses = ThreadLinkPoses();
  m.Robot().LinkPoses(q, &link_poses);
  CollisionReport report;
  if (m.ListHitsTerrain(m.trunk, base_W, link_poses, &report)) return report;
  for (Leg leg : kAllLegs) {
    if (m.ListHitsTerrain(m.LegShapes(leg, feet_in_contact[static_cast<std::size_t>(Index(leg))]), base_W, link_poses,
                          &report)) {
      return report;
    }
  }
  return report;
}

CollisionReport RobotTerrainCollision::CheckLeg(Leg leg, const Eigen::Isometry3d& base_W, const Eigen::Vector3d& q_leg,
                                                bool foot_in_contact) const {
  RBCP_CHECK(q_leg.allFinite() && base_W.matrix().allFinite(), "collision query with a non-finite pose or joint vector");
  const Impl& m = *impl_;
  std::vector<Eigen::Isometry3d>& link_poses = ThreadLinkPoses();
  // Only the leg's own links are placed: its shapes ride on nothing else.
  if (link_poses.size() != m.reference_link_poses.size()) link_poses = m.reference_link_poses;
  m.Robot().SetLegLinkPoses(leg, q_leg, &link_poses);
  CollisionReport report;
  m.ListHitsTerrain(m.LegShapes(leg, foot_in_contact), base_W, link_poses, &report);
  return report;
}

CollisionReport RobotTerrainCollision::CheckTrunk(const Eigen::Isometry3d& base_W) const {
  RBCP_CHECK(base_W.matrix().allFinite(), "collision query with a non-finite pose");
  const Impl& m = *impl_;
  CollisionReport report;
  m.ListHitsTerrain(m.trunk, base_W, m.reference_link_poses, &report);
  return report;
}

CollisionReport RobotTerrainCollision::CheckSelf(const JointVector& q) const { return impl_->self.Check(q); }

CollisionReport RobotTerrainCollision::CheckSelf(const JointVector& q, Leg leg) const {
  return impl_->self.Check(q, leg);
}

bool RobotTerrainCollision::InsideTerrain(const Eigen::Vector3d& p_W) const { return impl_->grid->Inside(p_W); }

std::vector<std::pair<std::string, std::string>> RobotTerrainCollision::SelfCollisionExclusions() const {
  const RobotCollisionModel& model = impl_->Model();
  std::vector<std::pair<std::string, std::string>> names;
  for (const PrimitivePair& p : model.ReferenceOverlaps()) {
    names.emplace_back(model.Primitives()[static_cast<std::size_t>(p.a)].name,
                       model.Primitives()[static_cast<std::size_t>(p.b)].name);
  }
  return names;
}

const CollisionOptions& RobotTerrainCollision::Options() const { return impl_->options; }

}  // namespace rbcp
