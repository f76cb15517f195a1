// BulletWorld: ANYmal B as a btMultiBody on static terrain, fixed-step integration, measured state.

#include "rbcp/sim/bullet_world.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bullet_eigen.h"
#include "rbcp/core/error.h"
#include "robot_description.h"
#include "terrain_shapes.h"
#include "urdf_multibody.h"

namespace rbcp::sim {
namespace {

// ---- Contact solver parameters ------------------------------------------------------------------
// btMultiBody contacts are velocity constraints: a penetration d is removed by adding erp2 * d / dt
// to the separating velocity target (multibodies get no split impulse), and points still apart by
// a gap g let the bodies approach by at most g within the step (speculative contacts, up to the
// colliders' 4 mm breaking threshold), so an impact does not sink a foot into the ground. With the
// solver converged a standing foot penetrates by well under a micrometre, so erp2 only acts after
// an impact; 0.02 removes that (at most ~1 mm after a 30 cm drop) with a time constant of
// dt / erp2 = 42 ms at 1/1200 s, the same as pybullet's 0.08 at 1/240 s. Stiffer values (0.1 and
// more) make the feet chatter after hard landings and while sliding.
constexpr double kContactErp = 0.02;
// Warm starting with the previous step's impulses: Bullet's default factor.
constexpr double kWarmStartingFactor = 0.85;
// Generalized velocity clamp of the btMultiBody [m/s, rad/s], as a multiple of the joint speed
// bound (and at least 50): a numerical safety net only.
double MaxCoordinateVelocity(double joint_velocity_limit_radps) { return std::max(50.0, 4.0 * joint_velocity_limit_radps); }

/// Result callback recording the deepest overlap of one shape pair.
struct OverlapCallback : btCollisionWorld::ContactResultCallback {
  double min_distance = std::numeric_limits<double>::infinity();
  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int, const btCollisionObjectWrapper*,
                           int, int) override {
    min_distance = std::min(min_distance, static_cast<double>(cp.getDistance()));
    return 0;
  }
};

/// The collision dispatcher, with robot-robot manifolds processed by the solver only where the
/// shapes touch (distance <= 0): Bullet otherwise turns every point within the breaking threshold
/// into speculative constraint rows, and the trunk and thighs sit a few millimetres apart in any
/// stance, which would double the solver's work for contacts that never happen. Robot-terrain
/// manifolds keep their speculative points (an approaching foot is stopped at the surface).
class Dispatcher : public btCollisionDispatcher {
 public:
  using btCollisionDispatcher::btCollisionDispatcher;
  btPersistentManifold* getNewManifold(const btCollisionObject* b0, const btCollisionObject* b1) override {
    btPersistentManifold* manifold = btCollisionDispatcher::getNewManifold(b0, b1);
    if (b0->getUserIndex2() == kRobotColliderTag && b1->getUserIndex2() == kRobotColliderTag) {
      manifold->setContactProcessingThreshold(0.0);
    }
    return manifold;
  }
};

/// A manifold point that is a contact of the last step: the shapes overlap or the solver pushed.
bool IsActive(const btManifoldPoint& p) { return p.getDistance() <= 0.0 || p.getAppliedImpulse() > 0.0; }

/// Distance along a unit ray (box frame) from `o` to the first face of a box of half extents `h`
/// centred at the origin, within [0, max]; 0 from inside the box, +infinity when missed. The
/// slab test, exact for Bullet's btBoxShape (its margin lies inside the half extents).
double RayBoxDistance(const btVector3& o, const btVector3& d, const btVector3& h, double max) {
  double t0 = 0.0;
  double t1 = max;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-300) {
      if (std::abs(o[i]) > h[i]) return std::numeric_limits<double>::infinity();
      continue;
    }
    const double inv = 1.0 / d[i];
    double ta = (-h[i] - o[i]) * inv;
    double tb = (h[i] - o[i]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0;
}

/// The closest triangle a ray crosses (both faces), as a fraction of the ray.
struct ClosestTriangleHit : btTriangleRaycastCallback {
  ClosestTriangleHit(const btVector3& from, const btVector3& to) : btTriangleRaycastCallback(from, to, 0) {}
  btScalar reportHit(const btVector3& /*normal*/, btScalar fraction, int /*part*/, int /*triangle*/) override {
    return fraction;  // later triangles must be closer than this one
  }
};

}  // namespace

struct BulletWorld::Impl {
  PhysicsConfig config;
  RobotDescription description;
  JointVector q_reference = JointVector::Zero();
  double torque_limit_Nm = 0.0;             ///< the robot's continuous torque limit
  double joint_velocity_limit_radps = 0.0;  ///< the robot's joint speed limit

  std::unique_ptr<btDefaultCollisionConfiguration> collision_configuration;
  std::unique_ptr<Dispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<btMultiBodyConstraintSolver> solver;
  std::unique_ptr<btMultiBodyDynamicsWorld> world;
  MultiBodyRobot robot;
  std::vector<TerrainObject> terrain;
  bool robot_in_world = false;

  Eigen::Isometry3d base_com_from_link = Eigen::Isometry3d::Identity();  ///< base link frame in the base CoM frame
  JointVector command = JointVector::Zero();  ///< saturated command, held
  JointVector applied = JointVector::Zero();  ///< applied in the last step
  Eigen::Vector3d base_force_W = Eigen::Vector3d::Zero();  ///< external force on the base, held
  long long steps = 0;
  btAlignedObjectArray<btQuaternion> scratch_rotations;
  btAlignedObjectArray<btVector3> scratch_origins;

  ~Impl() {
    if (!world) return;
    for (auto it = terrain.rbegin(); it != terrain.rend(); ++it) world->removeRigidBody(it->body.get());
    if (robot_in_world) robot.RemoveFrom(world.get());
  }

  btMultiBody& Mb() const { return *robot.multibody; }

  void Place(const Eigen::Vector3d& p, const Eigen::Quaterniond& orientation, const JointVector& q) {
    Eigen::Isometry3d base_W = Eigen::Isometry3d::Identity();
    base_W.linear() = orientation.normalized().toRotationMatrix();
    base_W.translation() = p;
    btMultiBody& mb = Mb();
    mb.setBaseWorldTransform(ToBt(Eigen::Isometry3d(base_W * base_com_from_link.inverse())));
    mb.clearVelocities();
    for (int i = 0; i < kNumJoints; ++i) mb.setJointPos(i, q[i]);
    mb.clearForcesAndTorques();
    mb.clearConstraintForces();
    mb.forwardKinematics(scratch_rotations, scratch_origins);
    mb.updateCollisionObjectWorldTransforms(scratch_rotations, scratch_origins);
    // Forget contacts: drop the cached collision algorithms and manifolds of every robot pair.
    for (const auto& collider : robot.colliders) {
      if (collider && collider->getBroadphaseHandle()) {
        world->getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(collider->getBroadphaseHandle(),
                                                                                dispatcher.get());
      }
    }
    command.setZero();
    applied.setZero();
    steps = 0;
  }

  /// Primitive pairs on different bodies that Bullet would test and that overlap in the
  /// reference configuration (e.g. a thigh's upper protector around the HAA actuator): they
  /// overlap by construction, so they are not self-collisions. Same rule as the planners'
  /// self-collision check.
  void ExcludeOverlapsByConstruction() {
    Place(Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity(), q_reference);
    const int num_bodies = static_cast<int>(robot.colliders.size());
    for (int a = 0; a < num_bodies; ++a) {
      for (int b = a + 1; b < num_bodies; ++b) {
        const auto& ca = robot.colliders[static_cast<std::size_t>(a)];
        const auto& cb = robot.colliders[static_cast<std::size_t>(b)];
        if (!ca || !cb || !ca->checkCollideWithOverride(cb.get())) continue;
        for (int ia : robot.body_shapes[static_cast<std::size_t>(a)]) {
          for (int ib : robot.body_shapes[static_cast<std::size_t>(b)]) {
            btCollisionObject oa, ob;
            const auto* compound_a = robot.compounds[static_cast<std::size_t>(a)].get();
            const auto* compound_b = robot.compounds[static_cast<std::size_t>(b)].get();
            const int child_a = robot.shapes[static_cast<std::size_t>(ia)].child;
            const int child_b = robot.shapes[static_cast<std::size_t>(ib)].child;
            oa.setCollisionShape(const_cast<btCollisionShape*>(compound_a->getChildShape(child_a)));
            ob.setCollisionShape(const_cast<btCollisionShape*>(compound_b->getChildShape(child_b)));
            oa.setWorldTransform(ca->getWorldTransform() * compound_a->getChildTransform(child_a));
            ob.setWorldTransform(cb->getWorldTransform() * compound_b->getChildTransform(child_b));
            OverlapCallback overlap;
            world->contactPairTest(&oa, &ob, overlap);
            if (overlap.min_distance < 0.0) robot.filter->Exclude(ia, ib);
          }
        }
      }
    }
  }

  enum class Side { kOther, kRobot, kTerrain };
  Side Classify(const btCollisionObject* o) const {
    switch (o->getUserIndex2()) {
      case kRobotColliderTag:
        return Side::kRobot;
      case kTerrainObjectTag:
        return Side::kTerrain;
      default:
        return Side::kOther;
    }
  }

  std::string LinkOf(int body, int child) const {
    const int id = robot.ShapeId(body, child);
    return id >= 0 ? robot.shapes[static_cast<std::size_t>(id)].link
                   : description.bodies[static_cast<std::size_t>(body)].name;
  }

  /// Calls f(robot body, robot is body 0 of the manifold, point) for every active robot-terrain point.
  template <typename F>
  void ForEachTerrainContact(F&& f) const {
    const int n = dispatcher->getNumManifolds();
    for (int m = 0; m < n; ++m) {
      const btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
      const Side s0 = Classify(manifold->getBody0());
      const Side s1 = Classify(manifold->getBody1());
      bool robot_is_0;
      if (s0 == Side::kRobot && s1 == Side::kTerrain) {
        robot_is_0 = true;
      } else if (s1 == Side::kRobot && s0 == Side::kTerrain) {
        robot_is_0 = false;
      } else {
        continue;
      }
      const int body = (robot_is_0 ? manifold->getBody0() : manifold->getBody1())->getUserIndex();
      for (int p = 0; p < manifold->getNumContacts(); ++p) {
        const btManifoldPoint& pt = manifold->getContactPoint(p);
        if (IsActive(pt)) f(body, robot_is_0, pt);
      }
    }
  }
};

BulletWorld::BulletWorld(const RobotModel& robot, const std::vector<TerrainElement>& terrain,
                         const PhysicsConfig& config)
    : impl_(std::make_unique<Impl>()) {
  config.Validate();
  Impl& m = *impl_;
  m.config = config;
  m.description = RobotDescription::FromModel(robot);
  m.q_reference = robot.ReferenceConfiguration();
  m.torque_limit_Nm = robot.ContinuousTorqueLimit();
  m.joint_velocity_limit_radps = robot.JointVelocityLimit();
  m.base_com_from_link = m.description.bodies[RobotDescription::kBase].inertial_frame.inverse();

  m.collision_configuration = std::make_unique<btDefaultCollisionConfiguration>();
  m.dispatcher = std::make_unique<Dispatcher>(m.collision_configuration.get());
  m.broadphase = std::make_unique<btDbvtBroadphase>();
  m.solver = std::make_unique<btMultiBodyConstraintSolver>();
  m.world = std::make_unique<btMultiBodyDynamicsWorld>(m.dispatcher.get(), m.broadphase.get(), m.solver.get(),
                                                       m.collision_configuration.get());
  m.world->setGravity(btVector3(0, 0, -config.gravity_mps2));
  btContactSolverInfo& info = m.world->getSolverInfo();
  info.m_numIterations = config.solver_iterations;
  info.m_erp2 = kContactErp;
  info.m_globalCfm = 0.0;
  info.m_linearSlop = 0.0;
  info.m_warmstartingFactor = kWarmStartingFactor;
  info.m_restitution = 0.0;
  // Two friction directions per contact point (the multibody world's default), solved as a
  // pyramid: Bullet's implicit cone friction lets quadruped feet creep on slopes.
  info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS | SOLVER_DISABLE_IMPLICIT_CONE_FRICTION;
  info.m_solverMode &= ~SOLVER_RANDMIZE_ORDER;  // deterministic order
  info.m_timeStep = config.time_step_s;

  InstallSelfCollisionCallbacks();
  m.robot = MultiBodyRobot::Build(m.description, config.friction, MaxCoordinateVelocity(m.joint_velocity_limit_radps));
  m.robot.AddTo(m.world.get());
  m.robot_in_world = true;
  m.ExcludeOverlapsByConstruction();

  m.terrain = BuildTerrain(terrain);
  for (TerrainObject& o : m.terrain) m.world->addRigidBody(o.body.get());  // static: StaticFilter group

  m.Place(Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity(), m.q_reference);
}

BulletWorld::~BulletWorld() = default;

void BulletWorld::ResetRobot(const Eigen::Vector3d& base_position_W, const Eigen::Quaterniond& base_orientation_W,
                             const JointVector& q) {
  if (!base_position_W.allFinite() || !base_orientation_W.coeffs().allFinite() || !(base_orientation_W.norm() > 0.0) ||
      !q.allFinite()) {
    throw InputError("BulletWorld::ResetRobot: expected a finite base pose and joint vector, got non-finite values");
  }
  impl_->Place(base_position_W, base_orientation_W, q);
}

JointVector BulletWorld::SetJointTorques(const JointVector& tau_command) {
  Impl& m = *impl_;
  JointVector next = JointVector::Zero();
  for (int i = 0; i < kNumJoints; ++i) {
    if (!std::isfinite(tau_command[i])) {
      throw InputError("BulletWorld::SetJointTorques: '" + JointName(i) + "': expected a finite torque, got " +
                       std::to_string(tau_command[i]));
    }
    m.command[i] = std::clamp(tau_command[i], -m.torque_limit_Nm, m.torque_limit_Nm);
    next[i] = ActuatorTorque(m.command[i], m.Mb().getJointVel(i), m.torque_limit_Nm,
                             m.joint_velocity_limit_radps);
  }
  return next;
}

void BulletWorld::Step() {
  Impl& m = *impl_;
  btMultiBody& mb = m.Mb();
  // The speed bound is re-evaluated every step: the command is held over several steps.
  // Bullet clears joint torques after each stepSimulation and addJointTorque accumulates, so
  // each torque is added exactly once per step.
  for (int i = 0; i < kNumJoints; ++i) {
    m.applied[i] = ActuatorTorque(m.command[i], mb.getJointVel(i), m.torque_limit_Nm,
                                  m.joint_velocity_limit_radps);
    mb.addJointTorque(i, m.applied[i]);
  }
  // Like joint torques, external forces are cleared after every step.
  if (!m.base_force_W.isZero()) mb.addBaseForce(ToBt(m.base_force_W));
  // maxSubSteps = 0: one step of exactly time_step_s (no accumulation, no interpolation).
  m.world->stepSimulation(m.config.time_step_s, 0, m.config.time_step_s);
  ++m.steps;
}

void BulletWorld::SetTerrain(const std::vector<TerrainElement>& terrain) {
  Impl& m = *impl_;
  std::vector<TerrainObject> next = BuildTerrain(terrain);  // throws before anything changes
  for (auto it = m.terrain.rbegin(); it != m.terrain.rend(); ++it) m.world->removeRigidBody(it->body.get());
  m.terrain = std::move(next);
  for (TerrainObject& o : m.terrain) m.world->addRigidBody(o.body.get());
}

void BulletWorld::SetBaseForce(const Eigen::Vector3d& force_W) {
  if (!force_W.allFinite()) throw InputError("BulletWorld::SetBaseForce: expected a finite force");
  impl_->base_force_W = force_W;
}

double BulletWorld::Time() const { return static_cast<double>(impl_->steps) * impl_->config.time_step_s; }

RobotState BulletWorld::State() const {
  const Impl& m = *impl_;
  const btMultiBody& mb = m.Mb();
  RobotState s;
  s.t = Time();
  const Eigen::Isometry3d com_W = ToEigen(mb.getBaseWorldTransform());
  const Eigen::Isometry3d base_W = com_W * m.base_com_from_link;
  s.base_position_W = base_W.translation();
  s.base_orientation_W = Eigen::Quaterniond(base_W.linear()).normalized();
  const Eigen::Vector3d omega_W = ToEigen(mb.getBaseOmega());
  s.base_linear_velocity_W = ToEigen(mb.getBaseVel()) + omega_W.cross(base_W.translation() - com_W.translation());
  s.base_angular_velocity_B = base_W.linear().transpose() * omega_W;
  for (int i = 0; i < kNumJoints; ++i) {
    s.q[i] = mb.getJointPos(i);
    s.qd[i] = mb.getJointVel(i);
  }
  s.tau = m.applied;

  const double dt = m.config.time_step_s;
  m.ForEachTerrainContact([&](int body, bool robot_is_0, const btManifoldPoint& pt) {
    const RobotBody& b = m.description.bodies[static_cast<std::size_t>(body)];
    if (!b.is_foot) return;
    const std::size_t l = static_cast<std::size_t>(Index(*b.leg));
    s.foot_contact[l] = true;
    // Impulses act along +normal / +friction directions on the manifold's body 0.
    const btVector3 impulse = pt.m_normalWorldOnB * pt.getAppliedImpulse() +
                              pt.m_lateralFrictionDir1 * pt.m_appliedImpulseLateral1 +
                              pt.m_lateralFrictionDir2 * pt.m_appliedImpulseLateral2;
    s.foot_force_W[l] += (robot_is_0 ? 1.0 : -1.0) * ToEigen(impulse) / dt;
  });
  return s;
}

std::array<Eigen::Vector3d, kNumLegs> BulletWorld::FootCentersW() const {
  std::array<Eigen::Vector3d, kNumLegs> centers;
  const auto frames = FootFramesW();
  for (std::size_t i = 0; i < frames.size(); ++i) centers[i] = frames[i].translation();
  return centers;
}

std::array<Eigen::Isometry3d, kNumLegs> BulletWorld::FootFramesW() const {
  const Impl& m = *impl_;
  std::array<Eigen::Isometry3d, kNumLegs> frames;
  for (Leg leg : kAllLegs) {
    const int b = RobotDescription::FootBody(leg);
    const auto& collider = m.robot.colliders[static_cast<std::size_t>(b)];
    const btCompoundShape& compound = *m.robot.compounds[static_cast<std::size_t>(b)];
    int sphere = -1;
    for (int c = 0; c < compound.getNumChildShapes(); ++c) {
      if (compound.getChildShape(c)->getShapeType() == SPHERE_SHAPE_PROXYTYPE) sphere = c;
    }
    RBCP_CHECK(sphere >= 0, "every foot body has a sphere");
    const btTransform& body = collider->getWorldTransform();
    Eigen::Isometry3d& frame = frames[static_cast<std::size_t>(Index(leg))];
    frame = ToEigen(body);
    frame.translation() = ToEigen(body * compound.getChildTransform(sphere).getOrigin());
  }
  return frames;
}

std::vector<TerrainContact> BulletWorld::TerrainContacts() const {
  const Impl& m = *impl_;
  std::vector<TerrainContact> contacts;
  const double dt = m.config.time_step_s;
  m.ForEachTerrainContact([&](int body, bool robot_is_0, const btManifoldPoint& pt) {
    const RobotBody& b = m.description.bodies[static_cast<std::size_t>(body)];
    TerrainContact c;
    c.link = m.LinkOf(body, robot_is_0 ? pt.m_index0 : pt.m_index1);
    c.leg = b.leg;
    c.is_foot = b.is_foot;
    c.position_W = ToEigen(robot_is_0 ? pt.getPositionWorldOnA() : pt.getPositionWorldOnB());
    c.normal_W = (robot_is_0 ? 1.0 : -1.0) * ToEigen(pt.m_normalWorldOnB);
    c.normal_force_N = pt.getAppliedImpulse() / dt;
    c.penetration_m = -pt.getDistance();
    contacts.push_back(std::move(c));
  });
  return contacts;
}

std::vector<std::pair<std::string, std::string>> BulletWorld::SelfContacts() const {
  const Impl& m = *impl_;
  std::vector<std::pair<std::string, std::string>> pairs;
  const int n = m.dispatcher->getNumManifolds();
  for (int k = 0; k < n; ++k) {
    const btPersistentManifold* manifold = m.dispatcher->getManifoldByIndexInternal(k);
    if (m.Classify(manifold->getBody0()) != Impl::Side::kRobot || m.Classify(manifold->getBody1()) != Impl::Side::kRobot) {
      continue;
    }
    const int b0 = manifold->getBody0()->getUserIndex();
    const int b1 = manifold->getBody1()->getUserIndex();
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      const btManifoldPoint& pt = manifold->getContactPoint(p);
      if (!IsActive(pt)) continue;
      std::pair<std::string, std::string> pair(m.LinkOf(b0, pt.m_index0), m.LinkOf(b1, pt.m_index1));
      if (std::find(pairs.begin(), pairs.end(), pair) == pairs.end()) pairs.push_back(std::move(pair));
    }
  }
  return pairs;
}

void BulletWorld::CastTerrainRays(const Eigen::Vector3d& origin_W, const std::vector<Eigen::Vector3d>& directions_W,
                                  double max_range_m, std::vector<double>* distances) const {
  const Impl& m = *impl_;
  constexpr double kNone = std::numeric_limits<double>::infinity();
  distances->assign(directions_W.size(), kNone);
  const btVector3 origin = ToBt(origin_W);
  // Each terrain body by its own shape, no broadphase: a box by the exact slab test, a mesh by its
  // bounding volume hierarchy. On the DARPA rubble boxes this is 13 times faster than
  // btCollisionWorld::rayTest filtered for the terrain, and 10% faster on the paper's mesh.
  // The terrain bodies within reach: their axis-aligned boxes come within max_range_m.
  struct Candidate {
    btTransform from_world;           ///< world to object frame
    const btBoxShape* box = nullptr;  ///< an exact box, or
    const btBvhTriangleMeshShape* mesh = nullptr;
  };
  std::vector<Candidate> candidates;
  for (const TerrainObject& o : m.terrain) {
    btVector3 lo, hi;
    const btTransform& pose = o.body->getWorldTransform();
    o.shape->getAabb(pose, lo, hi);
    const btVector3 nearest(std::clamp(origin.x(), lo.x(), hi.x()), std::clamp(origin.y(), lo.y(), hi.y()),
                            std::clamp(origin.z(), lo.z(), hi.z()));
    if ((nearest - origin).length() > max_range_m) continue;
    Candidate c;
    c.from_world = pose.inverse();
    if (o.shape->getShapeType() == BOX_SHAPE_PROXYTYPE) {
      c.box = static_cast<const btBoxShape*>(o.shape.get());
    } else {
      RBCP_CHECK(o.shape->getShapeType() == TRIANGLE_MESH_SHAPE_PROXYTYPE, "terrain shapes are boxes and meshes");
      c.mesh = static_cast<const btBvhTriangleMeshShape*>(o.shape.get());
    }
    candidates.push_back(c);
  }
  for (std::size_t k = 0; k < directions_W.size(); ++k) {
    const btVector3 d = ToBt(directions_W[k]);
    double best = max_range_m;
    bool hit = false;
    for (const Candidate& c : candidates) {
      const btVector3 o = c.from_world * origin;
      const btVector3 dir = c.from_world.getBasis() * d;
      if (c.box) {
        const double t = RayBoxDistance(o, dir, c.box->getHalfExtentsWithMargin(), best);
        if (t <= best) {
          best = t;
          hit = true;
        }
      } else {
        ClosestTriangleHit cb(o, o + dir * best);
        const_cast<btBvhTriangleMeshShape*>(c.mesh)->performRaycast(&cb, cb.m_from, cb.m_to);
        if (cb.m_hitFraction < 1.0) {
          best *= cb.m_hitFraction;
          hit = true;
        }
      }
    }
    if (hit) (*distances)[k] = best;
  }
}

double BulletWorld::RobotMass() const {
  const btMultiBody& mb = impl_->Mb();
  double mass = mb.getBaseMass();
  for (int i = 0; i < mb.getNumLinks(); ++i) mass += mb.getLinkMass(i);
  return mass;
}

const PhysicsConfig& BulletWorld::Config() const { return impl_->config; }

}  // namespace rbcp::sim
