#include "rbcp/collision/robot_self_collision.h"

#include <fcl/narrowphase/collision_result.h>

#include <atomic>
#include <cstdint>
#include <limits>

#include "fcl_shape.h"
#include "rbcp/core/error.h"

namespace rbcp {

using collision_detail::Aabb;
using collision_detail::FclShape;

namespace {

// Primitive groups: 0 the trunk, 1 + Index(leg) a leg.
constexpr std::size_t kNumGroups = kNumLegs + 1;

struct Scratch {
  // The placement (link poses, shape_poses, shape_boxes) is of `q` for the checker numbered
  // `owner` (0: none yet): a leg whose joints are unchanged keeps its link poses and shapes.
  std::vector<Eigen::Isometry3d> link_poses;
  std::vector<Eigen::Isometry3d> shape_poses;
  std::vector<Aabb> shape_boxes;
  // Whether the groups' bounds overlap.
  std::array<std::array<bool, kNumGroups>, kNumGroups> groups_overlap{};
  fcl::CollisionResultd result;
  JointVector q = JointVector::Zero();
  std::uint64_t owner = 0;
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

// Which pair blocks a query tests.
enum class PairSelection {
  kAll,       // every block
  kOfGroup,   // the blocks holding the group
  kGroupTrunk,  // the group against the trunk
};

}  // namespace

struct RobotSelfCollision::Impl {
  RobotModel robot;
  RobotCollisionModel model;
  bool measure_penetration = true;
  const std::uint64_t id = NextCheckerId();  // keys the per-thread placement

  std::vector<FclShape> shapes;     // model.Primitives() order
  std::vector<std::size_t> groups;  // each shape's group
  // The pairs in checking order, in blocks of one group pair (leg-trunk or leg-leg) so that a
  // block is skipped when the groups' bounds do not overlap.
  struct PairBlock {
    std::size_t group_a = 0, group_b = 0;
    std::size_t begin = 0, end = 0;  // range in pairs
  };
  std::vector<PrimitivePair> pairs;
  std::vector<PairBlock> blocks;

  Impl(const RobotModel& r, RobotCollisionModel m, bool measure)
      : robot(r), model(std::move(m)), measure_penetration(measure) {
    for (const CollisionPrimitive& p : model.Primitives()) {
      shapes.emplace_back(p);
      groups.push_back(p.leg ? 1 + static_cast<std::size_t>(Index(*p.leg)) : 0);
    }
    for (Leg leg : kAllLegs) {
      const std::size_t group = 1 + static_cast<std::size_t>(Index(leg));
      AddBlock(group, 0, model.LegTrunkPairs(leg));
      for (Leg other : kAllLegs) {
        if (Index(other) > Index(leg)) AddBlock(group, 1 + static_cast<std::size_t>(Index(other)), model.LegLegPairs(leg, other));
      }
    }
  }

  void AddBlock(std::size_t group_a, std::size_t group_b, const std::vector<PrimitivePair>& block) {
    if (block.empty()) return;
    blocks.push_back(PairBlock{group_a, group_b, pairs.size(), pairs.size() + block.size()});
    pairs.insert(pairs.end(), block.begin(), block.end());
  }

  // Places the shapes of the groups marked `changed` in the base frame from scratch.link_poses,
  // then the groups' bounds and which of them overlap.
  void PlaceShapes(Scratch& scratch, const std::array<bool, kNumGroups>& changed) const {
    scratch.shape_poses.resize(shapes.size());
    scratch.shape_boxes.resize(shapes.size());
    std::array<Aabb, kNumGroups> group_boxes;
    for (Aabb& g : group_boxes) {
      g.lo.setConstant(std::numeric_limits<double>::infinity());
      g.hi.setConstant(-std::numeric_limits<double>::infinity());
    }
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      const FclShape& s = shapes[i];
      const std::size_t group = groups[i];
      if (changed[group]) {
        scratch.shape_poses[i] = scratch.link_poses[static_cast<std::size_t>(s.link_index)] * s.pose_link;
        scratch.shape_boxes[i] = s.Bounds(scratch.shape_poses[i]);
      }
      Aabb& g = group_boxes[group];
      g.lo = g.lo.cwiseMin(scratch.shape_boxes[i].lo);
      g.hi = g.hi.cwiseMax(scratch.shape_boxes[i].hi);
    }
    for (std::size_t a = 0; a < kNumGroups; ++a) {
      for (std::size_t b = 0; b < kNumGroups; ++b) scratch.groups_overlap[a][b] = group_boxes[a].Overlaps(group_boxes[b]);
    }
  }

  // Places the shapes at q, again only for the legs whose joints differ from the thread's last
  // placement by this checker.
  void PlaceShapesAt(const JointVector& q, Scratch& scratch) const {
    std::array<bool, kNumGroups> changed;
    if (scratch.owner != id) {
      robot.LinkPoses(q, &scratch.link_poses);
      changed.fill(true);
      scratch.owner = id;
    } else {
      changed[0] = false;
      for (Leg leg : kAllLegs) {
        const Eigen::Vector3d q_leg = LegJoints(q, leg);
        const bool moved = q_leg != LegJoints(scratch.q, leg);
        changed[static_cast<std::size_t>(1 + Index(leg))] = moved;
        if (moved) robot.SetLegLinkPoses(leg, q_leg, &scratch.link_poses);
      }
    }
    scratch.q = q;
    PlaceShapes(scratch, changed);
  }

  static bool Selected(const PairBlock& block, PairSelection selection, std::size_t group) {
    switch (selection) {
      case PairSelection::kOfGroup:
        return block.group_a == group || block.group_b == group;
      case PairSelection::kGroupTrunk:
        return block.group_a == group && block.group_b == 0;
      case PairSelection::kAll:
      default:
        return true;
    }
  }

  CollisionReport Check(const JointVector& q, PairSelection selection, std::size_t group) const {
    RBCP_CHECK(q.allFinite(), "self-collision query with a non-finite joint vector");
    Scratch& scratch = ThreadScratch();
    PlaceShapesAt(q, scratch);
    CollisionReport report;
    for (const PairBlock& block : blocks) {
      if (!Selected(block, selection, group) || !scratch.groups_overlap[block.group_a][block.group_b]) continue;
      for (std::size_t k = block.begin; k < block.end; ++k) {
        const auto a = static_cast<std::size_t>(pairs[k].a), b = static_cast<std::size_t>(pairs[k].b);
        if (!collision_detail::ShapesTouch(shapes[a], scratch.shape_poses[a], scratch.shape_boxes[a], shapes[b],
                                           scratch.shape_poses[b], scratch.shape_boxes[b], scratch.result)) {
          continue;
        }
        report.collision = true;
        report.first_shape = shapes[a].name;
        report.obstacle = shapes[b].name;
        if (measure_penetration) {
          report.penetration = collision_detail::ShapesDepth(shapes[a], scratch.shape_poses[a], shapes[b],
                                                             scratch.shape_poses[b], scratch.result);
        }
        return report;
      }
    }
    return report;
  }
};

RobotSelfCollision::RobotSelfCollision(const RobotModel& robot, RobotCollisionModel model, bool measure_penetration)
    : impl_(std::make_unique<Impl>(robot, std::move(model), measure_penetration)) {}

RobotSelfCollision::RobotSelfCollision(const RobotModel& robot) : RobotSelfCollision(robot, RobotCollisionModel(robot)) {}

RobotSelfCollision::~RobotSelfCollision() = default;
RobotSelfCollision::RobotSelfCollision(RobotSelfCollision&&) noexcept = default;
RobotSelfCollision& RobotSelfCollision::operator=(RobotSelfCollision&&) noexcept = default;

CollisionReport RobotSelfCollision::Check(const JointVector& q) const { return impl_->Check(q, PairSelection::kAll, 0); }

CollisionReport RobotSelfCollision::Check(const JointVector& q, Leg leg) const {
  return impl_->Check(q, PairSelection::kOfGroup, 1 + static_cast<std::size_t>(Index(leg)));
}

CollisionReport RobotSelfCollision::CheckLegTrunk(const JointVector& q, Leg leg) const {
  return impl_->Check(q, PairSelection::kGroupTrunk, 1 + static_cast<std::size_t>(Index(leg)));
}

const RobotModel& RobotSelfCollision::Robot() const { return impl_->robot; }
const RobotCollisionModel& RobotSelfCollision::Model() const { return impl_->model; }

}  // namespace rbcp
