// The scenario's terrain as static Bullet bodies: exact boxes, static triangle meshes.

#include "terrain_shapes.h"

#include <BulletCollision/BroadphaseCollision/btBroadphaseProxy.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>

#include <type_traits>

#include "bullet_eigen.h"
#include "rbcp/core/error.h"
#include "rbcp/core/pose.h"
#include "rbcp/core/triangle_mesh.h"
#include "urdf_multibody.h"

namespace rbcp::sim {
namespace {

/// Box collision margin [m]: Bullet rounds box edges with this radius (default 4 cm, which would
/// round stair nosings and plinth edges the planners treat as sharp).
constexpr double kBoxMargin = 0.001;

}  // namespace

std::vector<TerrainObject> BuildTerrain(const std::vector<TerrainElement>& terrain) {
  std::vector<TerrainObject> objects;
  objects.reserve(terrain.size());
  for (std::size_t e = 0; e < terrain.size(); ++e) {
    TerrainObject o;
    btTransform pose = btTransform::getIdentity();
    std::visit(
        [&](const auto& element) {
          using T = std::decay_t<decltype(element)>;
          if constexpr (std::is_same_v<T, TerrainBox>) {
            if (!(element.size.minCoeff() > 0.0) || !element.size.allFinite()) {
              throw InputError("terrain element " + std::to_string(e) + ": expected a box of positive size");
            }
            auto box = std::make_unique<btBoxShape>(ToBt(Eigen::Vector3d(0.5 * element.size)));
            box->setMargin(kBoxMargin);
            o.shape = std::move(box);
            pose = btTransform(ToBt(RotationFromRpy(element.rpy)), ToBt(element.position));
          } else {
            const TriangleMesh mesh = ElementMesh(element);  // world frame
            o.mesh = std::make_unique<btTriangleMesh>(/*use32bitIndices=*/true, /*use4componentVertices=*/false);
            for (const Eigen::Vector3d& v : mesh.vertices) o.mesh->findOrAddVertex(ToBt(v), /*removeDuplicateVertices=*/false);
            for (const auto& t : mesh.triangles) o.mesh->addTriangleIndices(t[0], t[1], t[2]);
            o.shape = std::make_unique<btBvhTriangleMeshShape>(o.mesh.get(), /*useQuantizedAabbCompression=*/true);
          }
        },
        terrain[e]);
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, o.shape.get(), btVector3(0, 0, 0));
    info.m_friction = 1.0;
    info.m_restitution = 0.0;
    info.m_rollingFriction = 0.0;
    info.m_spinningFriction = 0.0;
    o.body = std::make_unique<btRigidBody>(info);
    o.body->setWorldTransform(pose);
    o.body->setUserIndex(static_cast<int>(e));
    o.body->setUserIndex2(kTerrainObjectTag);
    objects.push_back(std::move(o));
  }
  return objects;
}

}  // namespace rbcp::sim
