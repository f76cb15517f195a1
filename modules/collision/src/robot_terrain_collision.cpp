#include "rbcp/collision/robot_terrain_collision.h"

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "rbcp/core/error.h"
#include "terrain_grid.h"

namespace rbcp {

using collision_detail::Aabb;
using collision_detail::GridTriangle;
using collision_detail::TerrainGrid;

namespace {

constexpr char kTerrainName[] = "terrain";
// libccd: faster than FCL's own GJK on these primitive tests, and it measures depth only on request.
constexpr fcl::GJKSolverType kSolver = fcl::GST_LIBCCD;

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

// One collision primitive placed on a link.
struct Shape {
  std::string name;
  int link_index = -1;
  int leg = -1;  // Index(Leg), -1 for the trunk
  bool on_hip = false;
  CollisionShape::Kind kind = CollisionShape::Kind::kBox;
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // box
  double radius = 0.0;                                     // cylinder, sphere
  double half_length = 0.0;                                // cylinder
  Eigen::Isometry3d pose_link = Eigen::Isometry3d::Identity();
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  // Index of the shape whose penetration depth is reported for this one: itself, except for the
  // shrunk stance foot, which reports the depth of the full foot sphere.
  int report_index = -1;

  void MakeGeometry() {
    switch (kind) {
      case CollisionShape::Kind::kBox:
        geometry = std::make_shared<fcl::Boxd>(2.0 * half_extents);
        break;
      case CollisionShape::Kind::kCylinder:
        geometry = std::make_shared<fcl::Cylinderd>(radius, 2.0 * half_length);
        break;
      case CollisionShape::Kind::kSphere:
        geometry = std::make_shared<fcl::Sphered>(radius);
        break;
    }
  }

  // Half the shape's extent along the unit direction n at pose T.
  double Support(const Eigen::Isometry3d& T, const Eigen::Vector3d& n) const {
    switch (kind) {
      case CollisionShape::Kind::kBox:
        return (T.linear().transpose() * n).cwiseAbs().dot(half_extents);
      case CollisionShape::Kind::kCylinder: {
        const double c = std::abs(n.dot(T.linear().col(2)));
        return c * half_length + radius * std::sqrt(std::max(0.0, 1.0 - c * c));
      }
      case CollisionShape::Kind::kSphere:
      default:
        return radius;
    }
  }

  // Exact test of the shape at pose T against one terrain triangle; with `depth`, also its
  // penetration depth (FCL measures it only when the contact point and normal are requested too).
  bool TouchesTriangle(const Eigen::Isometry3d& T, const GridTriangle& t, double* depth) const {
    Eigen::Vector3d point, normal;
    Eigen::Vector3d* point_out = depth != nullptr ? &point : nullptr;
    Eigen::Vector3d* normal_out = depth != nullptr ? &normal : nullptr;
    const auto& [a, b, c] = t.corners;
    switch (kind) {
      case CollisionShape::Kind::kBox:
        return Narrowphase().shapeTriangleIntersect(static_cast<const fcl::Boxd&>(*geometry), T, a, b, c, point_out,
                                                    depth, normal_out);
      case CollisionShape::Kind::kCylinder:
        return Narrowphase().shapeTriangleIntersect(static_cast<const fcl::Cylinderd&>(*geometry), T, a, b, c,
                                                    point_out, depth, normal_out);
      case CollisionShape::Kind::kSphere:
      default:
        return Narrowphase().shapeTriangleIntersect(static_cast<const fcl::Sphered&>(*geometry), T, a, b, c,
                                                    point_out, depth, normal_out);
    }
  }

  // Directions along which the shape has faces or an axis at pose T: a box's three face normals,
  // a cylinder's axis, none for a sphere. Returns how many of axes[] it filled.
  int Axes(const Eigen::Isometry3d& T, std::array<Eigen::Vector3d, 3>& axes) const {
    switch (kind) {
      case CollisionShape::Kind::kBox:
        for (int i = 0; i < 3; ++i) axes[static_cast<std::size_t>(i)] = T.linear().col(i);
        return 3;
      case CollisionShape::Kind::kCylinder:
        axes[0] = T.linear().col(2);
        return 1;
      case CollisionShape::Kind::kSphere:
      default:
        return 0;
    }
  }

  // Axis-aligned bounds of the shape at pose T.
  Aabb Bounds(const Eigen::Isometry3d& T) const {
    const Eigen::Vector3d c = T.translation();
    Eigen::Vector3d e;
    switch (kind) {
      case CollisionShape::Kind::kBox:
        e = T.linear().cwiseAbs() * half_extents;
        break;
      case CollisionShape::Kind::kCylinder: {
        const Eigen::Vector3d axis = T.linear().col(2);
        for (int i = 0; i < 3; ++i) {
          e[i] = std::abs(axis[i]) * half_length + radius * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i]));
        }
        break;
      }
      case CollisionShape::Kind::kSphere:
      default:
        e.setConstant(radius);
        break;
    }
    return Aabb{c - e, c + e};
  }
};

// Gap [m] by which a separating axis must part two convex sets before the GJK test is skipped:
// touching and nearly touching pairs are left to GJK and its own tolerance, so the pre-test never
// changes a verdict.
constexpr double kSeparationSlack = 1e-5;

// True when the unit axis n separates the shapes a (at Ta) and b (at Tb) by more than the slack.
bool ApartAlong(const Eigen::Vector3d& n, const Shape& a, const Eigen::Isometry3d& Ta, const Shape& b,
                const Eigen::Isometry3d& Tb) {
  return std::abs(n.dot(Tb.translation() - Ta.translation())) > a.Support(Ta, n) + b.Support(Tb, n) + kSeparationSlack;
}

// A cheap sufficient test that two placed shapes do not touch: the line through their centres,
// the box face normals and the cylinder axes as separating axes (exact shapes, no tolerance).
bool Separated(const Shape& a, const Eigen::Isometry3d& Ta, const Shape& b, const Eigen::Isometry3d& Tb) {
  const Eigen::Vector3d d = Tb.translation() - Ta.translation();
  const double length = d.norm();
  if (length > 1e-12 && ApartAlong(d / length, a, Ta, b, Tb)) return true;
  std::array<Eigen::Vector3d, 3> axes;
  for (int k = a.Axes(Ta, axes) - 1; k >= 0; --k) {
    if (ApartAlong(axes[static_cast<std::size_t>(k)], a, Ta, b, Tb)) return true;
  }
  for (int k = b.Axes(Tb, axes) - 1; k >= 0; --k) {
    if (ApartAlong(axes[static_cast<std::size_t>(k)], a, Ta, b, Tb)) return true;
  }
  return false;
}

// The same for a shape against a terrain triangle (whose own normal the caller has tested): the
// line from the shape's centre to the triangle's centroid, the box face normals, the cylinder axis.
bool SeparatedFromTriangle(const Shape& s, const Eigen::Isometry3d& T, const GridTriangle& t) {
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

struct Scratch {
  std::vector<Eigen::Isometry3d> link_poses;
  std::vector<Eigen::Isometry3d> shape_poses;
  std::vector<Aabb> shape_boxes;
  // Self-collision groups: 0 the trunk, 1 + Index(leg) a leg; whether their bounds overlap.
  std::array<std::array<bool, kNumLegs + 1>, kNumLegs + 1> groups_overlap{};
  fcl::CollisionResultd result;
  // The self-collision placement (link poses, shape_poses, shape_boxes) is of `self_q` for the
  // checker numbered `self_owner` (0: none yet): a leg whose joints are unchanged keeps its link
  // poses and shapes (a swing moves one leg).
  std::vector<Eigen::Isometry3d> self_link_poses;
  JointVector self_q = JointVector::Zero();
  std::uint64_t self_owner = 0;
};

// Numbers the checkers for the per-thread placement above (never reused, unlike addresses).
std::uint64_t NextCheckerId() {
  static std::atomic<std::uint64_t> next{1};
  return next++;
}

// Per-thread scratch space: queries stay const, thread-safe and allocation-free once warm.
Scratch& ThreadScratch() {
  static thread_local Scratch scratch;
  return scratch;
}

}  // namespace

struct RobotTerrainCollision::Impl {
  RobotModel robot;
  CollisionOptions options;
  // Link poses in the base frame at the reference configuration (the trunk's never change).
  std::vector<Eigen::Isometry3d> reference_link_poses;
  std::unique_ptr<TerrainGrid> grid;

  // The robot's primitives in RobotModel::CollisionShapes() order, then the stance variants.
  std::vector<Shape> shapes;
  std::size_t num_robot_shapes = 0;
  std::vector<int> trunk;                           // shape indices of the trunk
  std::array<std::vector<int>, kNumLegs> swing;     // a leg's shapes, hip to foot
  std::array<std::vector<int>, kNumLegs> stance;    // the same with the stance foot and adapter
  // Self-collision pairs (leg shape first), in checking order, in blocks of one group pair
  // (leg-trunk or leg-leg) so that a block is skipped when the groups' bounds do not overlap.
  struct PairBlock {
    std::size_t group_a = 0, group_b = 0;  // 0 the trunk, 1 + Index(leg) a leg
    std::size_t begin = 0, end = 0;        // range in self_pairs
  };
  std::vector<std::pair<int, int>> self_pairs;
  std::vector<PairBlock> self_blocks;
  std::vector<std::pair<std::string, std::string>> self_exclusions;

  explicit Impl(const RobotModel& r) : robot(r) {}

  const std::uint64_t id = NextCheckerId();  // keys the per-thread self-collision placement

  void BuildShapes();
  void BuildSelfPairs();

  fcl::CollisionRequestd FirstHitRequest() const {
    fcl::CollisionRequestd request(1, false);
    request.gjk_solver_type = kSolver;
    return request;
  }

  // Visits the terrain triangles that shape s at `pose` may touch (broad phase: grid cells,
  // triangle bounds, the triangle's plane against the shape's extent along its normal) until
  // visit returns true.
  template <typename Visit>
  bool AnyTriangleTouching(const Shape& s, const Eigen::Isometry3d& pose, const Aabb& box, Visit&& visit) const {
    return grid->AnyTriangleNear(box, [&](const GridTriangle& t) {
      if (std::abs(t.normal.dot(pose.translation()) - t.offset) > s.Support(pose, t.normal)) return false;
      return visit(t);
    });
  }

  // Deepest penetration of the shape over the terrain triangles it touches.
  double TerrainDepth(const Shape& s, const Eigen::Isometry3d& link_W) const {
    const Eigen::Isometry3d pose = link_W * s.pose_link;
    double deepest = 0.0;
    AnyTriangleTouching(s, pose, s.Bounds(pose), [&](const GridTriangle& t) {
      double depth = 0.0;
      // The magnitude is the depth (FCL's solvers differ in sign conventions).
      if (s.TouchesTriangle(pose, t, &depth)) deepest = std::max(deepest, std::abs(depth));
      return false;
    });
    return deepest;
  }

  // Tests one shape placed by its link pose in the world; fills `report` on collision.
  bool ShapeHitsTerrain(const Shape& s, const Eigen::Isometry3d& link_W, CollisionReport* report) const {
    const Eigen::Isometry3d pose = link_W * s.pose_link;
    const Aabb box = s.Bounds(pose);
    if (!box.Overlaps(grid->Bounds())) return false;
    if (box.lo.z() > grid->MaxHeightOver(box)) return false;
    double depth = 0.0;
    if (AnyTriangleTouching(s, pose, box, [&](const GridTriangle& t) {
          return !SeparatedFromTriangle(s, pose, t) && s.TouchesTriangle(pose, t, nullptr);
        })) {
      if (options.measure_penetration) depth = TerrainDepth(shapes[static_cast<std::size_t>(s.report_index)], link_W);
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
      const Shape& s = shapes[static_cast<std::size_t>(i)];
      const Eigen::Isometry3d link_W = base_W * link_poses[static_cast<std::size_t>(s.link_index)];
      if (ShapeHitsTerrain(s, link_W, report)) return true;
    }
    return false;
  }

  // Places the robot shapes of the groups marked `changed` (0 the trunk, 1 + Index(leg) a leg) in
  // the base frame from scratch.self_link_poses for the self-collision test, then the groups'
  // bounds and which of them overlap.
  void PlaceRobotShapes(Scratch& scratch, const std::array<bool, kNumLegs + 1>& changed) const {
    scratch.shape_poses.resize(num_robot_shapes);
    scratch.shape_boxes.resize(num_robot_shapes);
    std::array<Aabb, kNumLegs + 1> group_boxes;
    for (Aabb& g : group_boxes) {
      g.lo.setConstant(std::numeric_limits<double>::infinity());
      g.hi.setConstant(-std::numeric_limits<double>::infinity());
    }
    for (std::size_t i = 0; i < num_robot_shapes; ++i) {
      const Shape& s = shapes[i];
      const std::size_t group = static_cast<std::size_t>(s.leg + 1);
      if (changed[group]) {
        scratch.shape_poses[i] = scratch.self_link_poses[static_cast<std::size_t>(s.link_index)] * s.pose_link;
        scratch.shape_boxes[i] = s.Bounds(scratch.shape_poses[i]);
      }
      Aabb& g = group_boxes[group];
      g.lo = g.lo.cwiseMin(scratch.shape_boxes[i].lo);
      g.hi = g.hi.cwiseMax(scratch.shape_boxes[i].hi);
    }
    for (std::size_t a = 0; a < group_boxes.size(); ++a) {
      for (std::size_t b = 0; b < group_boxes.size(); ++b) scratch.groups_overlap[a][b] = group_boxes[a].Overlaps(group_boxes[b]);
    }
  }

  // Places the robot's shapes at q for the self-collision test, again only for the legs whose
  // joints differ from the thread's last placement by this checker.
  void PlaceRobotShapesAt(const JointVector& q, Scratch& scratch) const {
    std::array<bool, kNumLegs + 1> changed;
    if (scratch.self_owner != id) {
      robot.LinkPoses(q, &scratch.self_link_poses);
      changed.fill(true);
      scratch.self_owner = id;
    } else {
      changed[0] = false;
      for (Leg leg : kAllLegs) {
        const Eigen::Vector3d q_leg = LegJoints(q, leg);
        const bool moved = q_leg != LegJoints(scratch.self_q, leg);
        changed[static_cast<std::size_t>(1 + Index(leg))] = moved;
        if (moved) robot.SetLegLinkPoses(leg, q_leg, &scratch.self_link_poses);
      }
    }
    scratch.self_q = q;
    PlaceRobotShapes(scratch, changed);
  }

  bool PairCollides(int a, int b, Scratch& scratch) const {
    const std::size_t ia = static_cast<std::size_t>(a), ib = static_cast<std::size_t>(b);
    if (!scratch.shape_boxes[ia].Overlaps(scratch.shape_boxes[ib])) return false;
    if (Separated(shapes[ia], scratch.shape_poses[ia], shapes[ib], scratch.shape_poses[ib])) return false;
    scratch.result.clear();
    return fcl::collide(shapes[ia].geometry.get(), scratch.shape_poses[ia], shapes[ib].geometry.get(),
                        scratch.shape_poses[ib], FirstHitRequest(), scratch.result) > 0;
  }

  double PairDepth(int a, int b, Scratch& scratch) const {
    const std::size_t ia = static_cast<std::size_t>(a), ib = static_cast<std::size_t>(b);
    fcl::CollisionRequestd request(1, true);
    request.gjk_solver_type = kSolver;
    scratch.result.clear();
    fcl::collide(shapes[ia].geometry.get(), scratch.shape_poses[ia], shapes[ib].geometry.get(), scratch.shape_poses[ib],
                 request, scratch.result);
    return scratch.result.numContacts() > 0 ? std::abs(scratch.result.getContact(0).penetration_depth) : 0.0;
  }

  // Self-collision over the pair blocks, or only those of one group (1 + Index(leg)) when
  // group >= 0.
  CollisionReport Self(const JointVector& q, int group) const {
    RBCP_CHECK(q.allFinite(), "self-collision query with a non-finite joint vector");
    Scratch& scratch = ThreadScratch();
    PlaceRobotShapesAt(q, scratch);
    CollisionReport report;
    for (const PairBlock& block : self_blocks) {
      if (group >= 0 && block.group_a != static_cast<std::size_t>(group) && block.group_b != static_cast<std::size_t>(group)) {
        continue;
      }
      if (!scratch.groups_overlap[block.group_a][block.group_b]) continue;
      for (std::size_t k = block.begin; k < block.end; ++k) {
        const auto [a, b] = self_pairs[k];
        if (!PairCollides(a, b, scratch)) continue;
        report.collision = true;
        report.first_shape = shapes[static_cast<std::size_t>(a)].name;
        report.obstacle = shapes[static_cast<std::size_t>(b)].name;
        if (options.measure_penetration) report.penetration = PairDepth(a, b, scratch);
        return report;
      }
    }
    return report;
  }
};

void RobotTerrainCollision::Impl::BuildShapes() {
  const auto& robot_shapes = robot.CollisionShapes();
  const auto& links = robot.Links();
  // The foot and adapter links ride on the same body, so their relative pose is fixed.
  reference_link_poses = robot.LinkPoses(robot.ReferenceConfiguration());
  const std::vector<Eigen::Isometry3d>& ref_poses = reference_link_poses;
  for (const CollisionShape& c : robot_shapes) {
    Shape s;
    s.name = c.name.empty() ? c.link : c.name;
    s.link_index = c.link_index;
    s.leg = c.leg ? Index(*c.leg) : -1;
    s.on_hip = c.leg && links[static_cast<std::size_t>(c.link_index)].name == std::string(LegName(*c.leg)) + "_HIP";
    s.kind = c.kind;
    s.half_extents = 0.5 * c.box_size;
    s.radius = c.radius;
    s.half_length = 0.5 * c.length;
    if (c.leg && links[static_cast<std::size_t>(c.link_index)].name == std::string(LegName(*c.leg)) + "_THIGH") {
      s.half_extents.array() += options.thigh_margin;
      s.radius += options.thigh_margin;
      s.half_length += options.thigh_margin;
    }
    if (!c.leg) {
      s.half_extents.array() += options.trunk_margin;
      s.radius += options.trunk_margin;
      s.half_length += options.trunk_margin;
    }
    s.pose_link = c.pose_link;
    s.MakeGeometry();
    s.report_index = static_cast<int>(shapes.size());
    shapes.push_back(std::move(s));
  }
  num_robot_shapes = shapes.size();

  for (Leg leg : kAllLegs) {
    const std::size_t l = static_cast<std::size_t>(Index(leg));
    const std::string foot_link = std::string(LegName(leg)) + "_FOOT";
    const std::string adapter_link = std::string(LegName(leg)) + "_ADAPTER";
    int foot = -1;
    int adapter = -1;
    for (std::size_t i = 0; i < num_robot_shapes; ++i) {
      const CollisionShape& c = robot_shapes[i];
      if (c.link == foot_link && c.kind == CollisionShape::Kind::kSphere && foot < 0) foot = static_cast<int>(i);
      if (c.link == adapter_link && c.kind == CollisionShape::Kind::kCylinder && adapter < 0) adapter = static_cast<int>(i);
    }
    if (foot < 0) throw InputError("robot collision model: expected a sphere on link '" + foot_link + "', got none");
    if (adapter < 0) {
      throw InputError("robot collision model: expected a cylinder on link '" + adapter_link + "', got none");
    }
    const Shape& foot_shape = shapes[static_cast<std::size_t>(foot)];
    const Shape& adapter_shape = shapes[static_cast<std::size_t>(adapter)];
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
    Shape stance_foot = foot_shape;
    stance_foot.radius = foot_shape.radius - options.foot_tolerance;
    stance_foot.MakeGeometry();
    stance_foot.report_index = foot;

    // Stance adapter: the tube shortened at the end nearer to the foot sphere's centre.
    Shape stance_adapter = adapter_shape;
    const Eigen::Isometry3d foot_in_adapter_link =
        ref_poses[static_cast<std::size_t>(adapter_shape.link_index)].inverse() *
        ref_poses[static_cast<std::size_t>(foot_shape.link_index)] * foot_shape.pose_link;
    const Eigen::Vector3d foot_in_tube = adapter_shape.pose_link.inverse() * foot_in_adapter_link.translation();
    const double toward_foot = foot_in_tube.z() < 0.0 ? -1.0 : 1.0;
    stance_adapter.half_length = adapter_shape.half_length - 0.5 * options.adapter_exclusion;
    stance_adapter.pose_link =
        adapter_shape.pose_link * Eigen::Translation3d(0.0, 0.0, -toward_foot * 0.5 * options.adapter_exclusion);
    stance_adapter.MakeGeometry();

    for (std::size_t i = 0; i < num_robot_shapes; ++i) {
      if (shapes[i].leg != Index(leg)) continue;
      swing[l].push_back(static_cast<int>(i));
      if (static_cast<int>(i) == foot) {
        stance[l].push_back(static_cast<int>(shapes.size()));
        shapes.push_back(stance_foot);
      } else if (static_cast<int>(i) == adapter) {
        stance[l].push_back(static_cast<int>(shapes.size()));
        stance_adapter.report_index = static_cast<int>(shapes.size());
        shapes.push_back(stance_adapter);
      } else {
        stance[l].push_back(static_cast<int>(i));
      }
    }
  }
  for (std::size_t i = 0; i < num_robot_shapes; ++i) {
    if (shapes[i].leg < 0) trunk.push_back(static_cast<int>(i));
  }
}

void RobotTerrainCollision::Impl::BuildSelfPairs() {
  Scratch scratch;
  PlaceRobotShapesAt(robot.ReferenceConfiguration(), scratch);
  const auto add_block = [&](std::size_t group_a, std::size_t group_b, std::size_t begin) {
    if (self_pairs.size() > begin) self_blocks.push_back(PairBlock{group_a, group_b, begin, self_pairs.size()});
  };
  for (Leg leg : kAllLegs) {
    const std::size_t l = static_cast<std::size_t>(Index(leg));
    std::size_t begin = self_pairs.size();
    for (int a : swing[l]) {
      const Shape& sa = shapes[static_cast<std::size_t>(a)];
      if (sa.on_hip) continue;
      for (int b : trunk) {
        if (PairCollides(a, b, scratch)) {
          self_exclusions.emplace_back(sa.name, shapes[static_cast<std::size_t>(b)].name);
        } else {
          self_pairs.emplace_back(a, b);
        }
      }
    }
    add_block(1 + l, 0, begin);
    for (std::size_t other = l + 1; other < static_cast<std::size_t>(kNumLegs); ++other) {
      begin = self_pairs.size();
      for (int a : swing[l]) {
        for (int b : swing[other]) self_pairs.emplace_back(a, b);
      }
      add_block(1 + l, 1 + other, begin);
    }
  }
}

RobotTerrainCollision::RobotTerrainCollision(const RobotModel& robot, const TriangleMesh& terrain,
                                             const CollisionOptions& options)
    : impl_(std::make_unique<Impl>(robot)) {
  const std::string problem = ValidateMesh(terrain);
  if (!problem.empty()) throw InputError("robot-terrain collision: expected a valid terrain mesh, got: " + problem);
  Impl& m = *impl_;
  m.options = options;
  if (!(options.trunk_margin >= 0.0 && options.trunk_margin < 0.1)) {
    throw InputError("collision options: 'trunk_margin': expected a clearance in [0, 0.1) m, got " +
                     Text(options.trunk_margin));
  }
  if (!(options.thigh_margin >= 0.0 && options.thigh_margin < 0.1)) {
    throw InputError("collision options: 'thigh_margin': expected a clearance in [0, 0.1) m, got " +
                     Text(options.thigh_margin));
  }
  m.BuildShapes();
  m.BuildSelfPairs();
  m.grid = std::make_unique<TerrainGrid>(terrain);
}

RobotTerrainCollision::~RobotTerrainCollision() = default;
RobotTerrainCollision::RobotTerrainCollision(RobotTerrainCollision&&) noexcept = default;
RobotTerrainCollision& RobotTerrainCollision::operator=(RobotTerrainCollision&&) noexcept = default;

CollisionReport RobotTerrainCollision::CheckRobot(const Eigen::Isometry3d& base_W, const JointVector& q,
                                                  const std::array<bool, kNumLegs>& feet_in_contact) const {
  RBCP_CHECK(q.allFinite() && base_W.matrix().allFinite(), "collision query with a non-finite pose or joint vector");
  const Impl& m = *impl_;
  Scratch& scratch = ThreadScratch();
  m.robot.LinkPoses(q, &scratch.link_poses);
  CollisionReport report;
  if (m.ListHitsTerrain(m.trunk, base_W, scratch.link_poses, &report)) return report;
  for (Leg leg : kAllLegs) {
    const std::size_t l = static_cast<std::size_t>(Index(leg));
    if (m.ListHitsTerrain(feet_in_contact[l] ? m.stance[l] : m.swing[l], base_W, scratch.link_poses, &report)) {
      return report;
    }
  }
  return report;
}

CollisionReport RobotTerrainCollision::CheckLeg(Leg leg, const Eigen::Isometry3d& base_W, const Eigen::Vector3d& q_leg,
                                                bool foot_in_contact) const {
  RBCP_CHECK(q_leg.allFinite() && base_W.matrix().allFinite(), "collision query with a non-finite pose or joint vector");
  const Impl& m = *impl_;
  Scratch& scratch = ThreadScratch();
  // Only the leg's own links are placed: its shapes ride on nothing else.
  if (scratch.link_poses.size() != m.reference_link_poses.size()) scratch.link_poses = m.reference_link_poses;
  m.robot.SetLegLinkPoses(leg, q_leg, &scratch.link_poses);
  const std::size_t l = static_cast<std::size_t>(Index(leg));
  CollisionReport report;
  m.ListHitsTerrain(foot_in_contact ? m.stance[l] : m.swing[l], base_W, scratch.link_poses, &report);
  return report;
}

CollisionReport RobotTerrainCollision::CheckTrunk(const Eigen::Isometry3d& base_W) const {
  RBCP_CHECK(base_W.matrix().allFinite(), "collision query with a non-finite pose");
  const Impl& m = *impl_;
  CollisionReport report;
  m.ListHitsTerrain(m.trunk, base_W, m.reference_link_poses, &report);
  return report;
}

CollisionReport RobotTerrainCollision::CheckSelf(const JointVector& q) const { return impl_->Self(q, -1); }

CollisionReport RobotTerrainCollision::CheckSelf(const JointVector& q, Leg leg) const {
  return impl_->Self(q, 1 + Index(leg));
}

bool RobotTerrainCollision::InsideTerrain(const Eigen::Vector3d& p_W) const { return impl_->grid->Inside(p_W); }

std::vector<std::pair<std::string, std::string>> RobotTerrainCollision::SelfCollisionExclusions() const {
  return impl_->self_exclusions;
}

const CollisionOptions& RobotTerrainCollision::Options() const { return impl_->options; }

}  // namespace rbcp
