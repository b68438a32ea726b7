// Static world shapes as Bullet collision objects, shared by the Bullet physics backend and by tests
// that cross-check the 2-D lidar against btCollisionWorld::rayTest.
#ifndef MINIBOT3D_SIM_BULLET_WORLD_H_
#define MINIBOT3D_SIM_BULLET_WORLD_H_

#include <memory>
#include <vector>

#include <btBulletCollisionCommon.h>

#include "minibot3d_sim/world.h"

namespace minibot3d_sim {

// Owns the Bullet shapes/objects made for a World. Each object's user index is the index of its
// Shape in World::shapes.
class BulletWorldObjects {
 public:
  // Creates one static collision object per world shape (box → btBoxShape, cylinder →
  // btCylinderShapeZ, sphere → btSphereShape, plane → btStaticPlaneShape, mesh →
  // btBvhTriangleMeshShape) and adds them to `collision_world` (not owned; must outlive this).
  BulletWorldObjects(const World& world, btCollisionWorld* collision_world);
  ~BulletWorldObjects();
  BulletWorldObjects(const BulletWorldObjects&) = delete;
  BulletWorldObjects& operator=(const BulletWorldObjects&) = delete;

 private:
  btCollisionWorld* collision_world_;
  std::vector<std::unique_ptr<btTriangleMesh>> meshes_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btCollisionObject>> objects_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_BULLET_WORLD_H_
