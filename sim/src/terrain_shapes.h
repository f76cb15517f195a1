#pragma once
/// The scenario's terrain as static Bullet bodies. Private to the simulator (Bullet types).
///
/// A TerrainBox becomes an exact btBoxShape (half extents, 1 mm margin so edges stay sharp) at its
/// centre, rotated by Rz(yaw) Ry(pitch) Rx(roll). A TerrainMeshFile becomes a static
/// btBvhTriangleMeshShape of its world-frame triangles (rbcp::ElementMesh: scale, pose applied).
/// Every terrain body is a btRigidBody of mass 0 (Bullet's static filter group, colliding with
/// everything but other static bodies) with friction 1 and restitution 0, so a contact's
/// combined friction is the robot collider's coefficient.

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletCollision/CollisionShapes/btTriangleMesh.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <memory>
#include <vector>

#include "rbcp/scenario/scenario.h"

namespace rbcp::sim {

struct TerrainObject {
  std::unique_ptr<btTriangleMesh> mesh;  ///< vertex storage of a mesh element
  std::unique_ptr<btCollisionShape> shape;
  std::unique_ptr<btRigidBody> body;
};

/// Builds one static body per element, in order (user index = element index). Throws InputError
/// for a mesh that cannot be read.
std::vector<TerrainObject> BuildTerrain(const std::vector<TerrainElement>& terrain);

}  // namespace rbcp::sim
