// The robot description as a Bullet btMultiBody: links in principal inertial frames, compound
// colliders of the robot's collision primitives, joint limit constraints.

#include "urdf_multibody.h"

#include <BulletCollision/CollisionDispatch/btCompoundCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCompoundCompoundCollisionAlgorithm.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include <cmath>

#include "bullet_eigen.h"
#include "rbcp/core/error.h"

namespace rbcp::sim {
namespace {

/// Collision margin of boxes and cylinders [m]. Bullet keeps the outer extents exact and rounds
/// edges and corners with this radius; its default (4 cm) would round a 7 cm shank box into a
/// near-capsule. 1 mm keeps the shapes true while leaving GJK a margin to work with. Spheres use
/// their radius as the margin (exact).
constexpr double kShapeMargin = 0.001;

/// Both primitives collide unless they are robot primitives of the same filter that excludes them.
bool ChildPairCollides(const btCollisionShape* a, const btCollisionShape* b) {
  const auto* ta = static_cast<const ShapeTag*>(a->getUserPointer());
  const auto* tb = static_cast<const ShapeTag*>(b->getUserPointer());
  if (ta == nullptr || tb == nullptr || ta->filter == nullptr || ta->filter != tb->filter) return true;
  return !ta->filter->Excluded(ta->id, tb->id);
}

std::unique_ptr<btCollisionShape> MakePrimitive(const CollisionShape& s) {
  std::unique_ptr<btCollisionShape> shape;
  switch (s.kind) {
    case CollisionShape::Kind::kBox:
      shape = std::make_unique<btBoxShape>(ToBt(Eigen::Vector3d(0.5 * s.box_size)));
      break;
    case CollisionShape::Kind::kCylinder:
      // URDF cylinders lie along their frame's z: btCylinderShapeZ, half extents (r, r, L/2).
      shape = std::make_unique<btCylinderShapeZ>(btVector3(s.radius, s.radius, 0.5 * s.length));
      break;
    case CollisionShape::Kind::kSphere:
      return std::make_unique<btSphereShape>(s.radius);
  }
  shape->setMargin(kShapeMargin);
  return shape;
}

/// The joints of bodies 1.. on the multibody's links, in the inertial frames (urdf_multibody.h).
void SetupJoints(const RobotDescription& d, btMultiBody& mb) {
  const int num_bodies = static_cast<int>(d.bodies.size());
  for (int b = 1; b < num_bodies; ++b) {
    const RobotBody& body = d.bodies[static_cast<std::size_t>(b)];
    RBCP_CHECK(body.parent >= 0 && body.parent < b, "every body's parent comes before it");
    const RobotBody& parent = d.bodies[static_cast<std::size_t>(body.parent)];
    // The joint frame in the parent's inertial frame, and this body's frame in its inertial frame.
    const Eigen::Isometry3d joint_in_parent_com = parent.inertial_frame.inverse() * body.parent_to_body;
    const Eigen::Isometry3d body_in_com = body.inertial_frame.inverse();
    const Eigen::Matrix3d rot_parent_to_this = body_in_com.linear() * joint_in_parent_com.linear().transpose();
    const btVector3 parent_com_to_pivot = ToBt(Eigen::Vector3d(joint_in_parent_com.translation()));
    const btVector3 pivot_to_com = ToBt(Eigen::Vector3d(-body_in_com.translation()));
    const btVector3 inertia = ToBt(body.principal_inertia);
    if (body.joint == RobotBody::Joint::kRevolute) {
      const Eigen::Vector3d axis = body_in_com.linear() * body.axis;
      mb.setupRevolute(b - 1, body.mass, inertia, body.parent - 1, ToBtQuaternion(rot_parent_to_this), ToBt(axis),
                       parent_com_to_pivot, pivot_to_com, /*disableParentCollision=*/true);
    } else {
      RBCP_CHECK(body.joint == RobotBody::Joint::kFixed, "bodies after the base hang on revolute or fixed joints");
      mb.setupFixed(b - 1, body.mass, inertia, body.parent - 1, ToBtQuaternion(rot_parent_to_this), parent_com_to_pivot,
                    pivot_to_com);
    }
  }
}

/// Body b's collider: a compound of its primitives (each tagged with its index into r.shapes),
/// installed on the multibody's base or link.
void AddCollider(const RobotDescription& d, int b, double friction, MultiBodyRobot& r) {
  btMultiBody& mb = *r.multibody;
  const RobotBody& body = d.bodies[static_cast<std::size_t>(b)];
  auto compound = std::make_unique<RobotCompoundShape>(static_cast<int>(body.shapes.size()));
  const Eigen::Isometry3d com_from_body = body.inertial_frame.inverse();
  for (const BodyShape& s : body.shapes) {
    const int id = static_cast<int>(r.shapes.size());
    std::unique_ptr<btCollisionShape> primitive = MakePrimitive(s.primitive);
    r.tags[static_cast<std::size_t>(id)] = ShapeTag{r.filter.get(), id};
    primitive->setUserPointer(&r.tags[static_cast<std::size_t>(id)]);
    r.body_shapes[static_cast<std::size_t>(b)].push_back(id);
    r.shapes.push_back(MultiBodyRobot::Shape{b, compound->getNumChildShapes(), s.primitive.link, s.primitive.name});
    compound->addChildShape(ToBt(com_from_body * s.pose_body), primitive.get());
    r.primitives.push_back(std::move(primitive));
  }
  auto collider = std::make_unique<btMultiBodyLinkCollider>(&mb, b - 1);
  collider->setCollisionShape(compound.get());
  // Combined friction is the product of the two colliders' coefficients; terrain uses 1.
  collider->setFriction(friction);
  collider->setRestitution(0.0);
  collider->setRollingFriction(0.0);
  collider->setSpinningFriction(0.0);
  collider->setUserIndex(b);
  collider->setUserIndex2(kRobotColliderTag);
  if (body.is_foot) {
    // Keeps a foot's contact point (and its friction) in place while the friction cone holds,
    // instead of replacing it by each new closest point: less drift of a standing foot.
    collider->setCollisionFlags(collider->getCollisionFlags() | btCollisionObject::CF_HAS_FRICTION_ANCHOR);
  }
  if (b == 0) {
    mb.setBaseCollider(collider.get());
  } else {
    mb.getLink(b - 1).m_collider = collider.get();
  }
  r.colliders[static_cast<std::size_t>(b)] = std::move(collider);
  r.compounds[static_cast<std::size_t>(b)] = std::move(compound);
}

}  // namespace

void InstallSelfCollisionCallbacks() {
  gCompoundCompoundChildShapePairCallback = &ChildPairCollides;
  gCompoundChildShapePairCallback = &ChildPairCollides;
}

MultiBodyRobot MultiBodyRobot::Build(const RobotDescription& d, double friction, double max_coordinate_velocity) {
  MultiBodyRobot r;
  const int num_bodies = static_cast<int>(d.bodies.size());
  const RobotBody& base = d.bodies[0];
  RBCP_CHECK(base.joint == RobotBody::Joint::kFloating, "body 0 is the floating base");
  r.multibody = std::make_unique<btMultiBody>(num_bodies - 1, base.mass, ToBt(base.principal_inertia),
                                              /*fixedBase=*/false, /*canSleep=*/false);
  btMultiBody& mb = *r.multibody;
  SetupJoints(d, mb);
  mb.finalizeMultiDof();
  // No artificial damping: the URDF's joint damping and friction are zero and Bullet's default link
  // damping (0.04) would act as an unmodelled drag on every link.
  mb.setLinearDamping(0.0);
  mb.setAngularDamping(0.0);
  // Bullet clamps every generalized velocity (base and joints) at this bound after each step; it is
  // a numerical safety net far above anything the robot reaches, not an actuator model.
  mb.setMaxCoordinateVelocity(max_coordinate_velocity);
  mb.setHasSelfCollision(true);
  mb.setUseGyroTerm(true);

  // Collision shapes and colliders.
  r.filter = std::make_unique<SelfCollisionFilter>();
  std::size_t num_shapes = 0;
  for (const RobotBody& body : d.bodies) num_shapes += body.shapes.size();
  r.tags.resize(num_shapes);  // fixed size: the shapes point at its elements
  r.body_shapes.resize(static_cast<std::size_t>(num_bodies));
  r.colliders.resize(static_cast<std::size_t>(num_bodies));
  r.compounds.resize(static_cast<std::size_t>(num_bodies));
  for (int b = 0; b < num_bodies; ++b) {
    if (!d.bodies[static_cast<std::size_t>(b)].shapes.empty()) AddCollider(d, b, friction, r);
  }

  // Joint limits of the revolute joints that have them.
  for (int b = 1; b < num_bodies; ++b) {
    const RobotBody& body = d.bodies[static_cast<std::size_t>(b)];
    if (body.joint != RobotBody::Joint::kRevolute) continue;
    if (!std::isfinite(body.lower_limit) || !std::isfinite(body.upper_limit)) continue;  // continuous joint
    r.limits.push_back(std::make_unique<btMultiBodyJointLimitConstraint>(&mb, b - 1, body.lower_limit, body.upper_limit));
  }
  return r;
}

void MultiBodyRobot::AddTo(btMultiBodyDynamicsWorld* world) {
  world->addMultiBody(multibody.get());
  for (const auto& collider : colliders) {
    if (collider) world->addCollisionObject(collider.get(), btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
  }
  for (const auto& limit : limits) world->addMultiBodyConstraint(limit.get());
}

void MultiBodyRobot::RemoveFrom(btMultiBodyDynamicsWorld* world) {
  for (auto it = limits.rbegin(); it != limits.rend(); ++it) world->removeMultiBodyConstraint(it->get());
  for (auto it = colliders.rbegin(); it != colliders.rend(); ++it) {
    if (*it) world->removeCollisionObject(it->get());
  }
  world->removeMultiBody(multibody.get());
}

int MultiBodyRobot::ShapeId(int body, int child) const {
  if (body < 0 || body >= static_cast<int>(body_shapes.size())) return -1;
  const auto& ids = body_shapes[static_cast<std::size_t>(body)];
  if (child < 0 || child >= static_cast<int>(ids.size())) return -1;
  return ids[static_cast<std::size_t>(child)];
}

}  // namespace rbcp::sim
