#pragma once
/// The robot description turned into a Bullet btMultiBody with one collider per body.
/// Private to the simulator (includes Bullet headers).
///
/// Frames: Bullet places every btMultiBody link (and the base) at its centre of mass with its
/// principal axes, the RobotBody's inertial_frame. The joint geometry is handed to setupRevolute
/// / setupFixed in those frames, as Bullet's own URDF importer does: the rotation from the parent's
/// inertial frame to this body's at zero joint position, the joint axis in this body's inertial
/// frame, the joint origin relative to the parent's centre of mass (parent inertial axes) and the
/// centre of mass relative to the joint origin (this body's inertial axes). A positive joint
/// position turns the child about the URDF axis by the right-hand rule, as in the URDF.
///
/// Collision: every body has a btCompoundShape whose children are its URDF primitives, placed
/// relative to the inertial frame. Every child shape carries a ShapeTag (its user pointer), so
/// contact points (compound child indices) map back to URDF links, and self-collision pairs can
/// be excluded per primitive pair (SelfCollisionFilter).

#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "robot_description.h"

namespace rbcp::sim {

class SelfCollisionFilter;

/// Attached to every robot primitive (btCollisionShape user pointer).
struct ShapeTag {
  const SelfCollisionFilter* filter = nullptr;
  int id = -1;  ///< index into MultiBodyRobot::shapes
};

/// Primitive pairs of one robot that never collide with each other (pairs that overlap by
/// construction). Read from Bullet's compound-compound narrow phase through a stateless global
/// callback, so it must not change while a world steps.
class SelfCollisionFilter {
 public:
  void Exclude(int a, int b) { pairs_.insert(Key(a, b)); }
  bool Excluded(int a, int b) const { return pairs_.count(Key(a, b)) > 0; }
  std::size_t Size() const { return pairs_.size(); }

 private:
  static std::pair<int, int> Key(int a, int b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); }
  std::set<std::pair<int, int>> pairs_;
};

/// Installs the child-pair callbacks of Bullet's compound collision algorithms that consult the
/// shapes' SelfCollisionFilter (idempotent; pairs of untagged shapes always collide).
void InstallSelfCollisionCallbacks();

/// A body's compound collider with a fixed contact breaking threshold. Bullet derives the
/// threshold from the shape's size (2 % of its bounding radius: 1.5 mm for a foot), and it is
/// also the distance up to which the narrow phase reports (speculative) points, so it bounds how
/// fast a foot may approach the ground without sinking into it for a step.
class RobotCompoundShape : public btCompoundShape {
 public:
  /// [m]: points persist and are generated up to this distance; 4 mm = one 1/1200 s step at 4.8 m/s.
  static constexpr double kContactBreakingThreshold = 0.004;
  explicit RobotCompoundShape(int initial_child_capacity) : btCompoundShape(true, initial_child_capacity) {}
  btScalar getContactBreakingThreshold(btScalar) const override { return kContactBreakingThreshold; }
};

/// Tags in btCollisionObject::getUserIndex2() of the simulator's collision objects.
inline constexpr int kRobotColliderTag = 1;
inline constexpr int kTerrainObjectTag = 2;

struct MultiBodyRobot {
  struct Shape {
    int body = -1;   ///< RobotDescription body index
    int child = -1;  ///< child index in the body's compound shape
    std::string link;
    std::string name;
  };

  std::unique_ptr<btMultiBody> multibody;
  /// Per body (RobotDescription order); body b is Bullet link b - 1, body 0 the base.
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<RobotCompoundShape>> compounds;
  std::vector<std::unique_ptr<btCollisionShape>> primitives;  ///< shape id order
  std::vector<ShapeTag> tags;                                 ///< shape id order
  std::vector<Shape> shapes;                                  ///< shape id order
  std::vector<std::vector<int>> body_shapes;                  ///< [body][child] -> shape id
  std::vector<std::unique_ptr<btMultiBodyJointLimitConstraint>> limits;
  std::unique_ptr<SelfCollisionFilter> filter;

  /// Builds the multibody and its colliders (not yet in a world). Robot colliders get the
  /// friction coefficient `friction`, restitution 0; foot colliders a friction anchor.
  static MultiBodyRobot Build(const RobotDescription& d, double friction, double max_coordinate_velocity);

  /// Adds the multibody, its colliders (DefaultFilter group, AllFilter mask: they touch static
  /// terrain and each other) and its joint limit constraints to the world.
  void AddTo(btMultiBodyDynamicsWorld* world);
  void RemoveFrom(btMultiBodyDynamicsWorld* world);

  /// Shape id of a contact point's compound child on a robot collider, or -1.
  int ShapeId(int body, int child) const;
};

}  // namespace rbcp::sim
