// Static world shapes as Bullet collision objects, shared by the Bullet physics backend and by tests
// that cross-check the 2-D lidar against btCollisionWorld::rayTest.
#ifndef MINIBOT3D_SIM_BULLET_WORLD_H_
#define MINIBOT3D_SIM_BULLET_WORLD_H_

#include <memory>
#include <vector>

#include <btBulletCollisionCommon.h>

#include "minibot3d_sim/world.h"

namespace minibot3d_sim {

// How static triangle meshes are given to Bullet. Convex-vs-triangle-mesh contacts cost Bullet a
// GJK run per overlapping triangle (~60 µs per step while the chassis leans on a 340-triangle mesh);
// a robot that stays on a flat floor only ever touches a mesh within its own height band, so there
// a mesh can be replaced by thin boxes along its cross-sections at `layers` heights in
// [z_min, z_max] (each box one layer tall): box contacts are cheap. layers = 0 keeps the triangles.
struct MeshBand {
  double z_min = 0.0;
  double z_max = 0.0;
  int layers = 0;
};

// Owns the Bullet shapes/objects made for a World. Each object's user index is the index of its
// Shape in World::shapes.
class BulletWorldObjects {
 public:
  // Creates one static collision object per world shape (box → btBoxShape, cylinder →
  // btCylinderShapeZ, sphere → btSphereShape, plane → btStaticPlaneShape, mesh →
  // btBvhTriangleMeshShape) and adds them to `collision_world` (not owned; must outlive this).
  // Meshes follow `band` (see MeshBand; default: kept as triangle meshes).
  BulletWorldObjects(const World& world, btCollisionWorld* collision_world,
                     const MeshBand& band = MeshBand());
  ~BulletWorldObjects();
  BulletWorldObjects(const BulletWorldObjects&) = delete;
  BulletWorldObjects& operator=(const BulletWorldObjects&) = delete;

 private:
  // A mesh as thin boxes along its cross-sections in the band (null when it has none there).
  std::unique_ptr<btCollisionShape> MeshBandBoxes(const Shape& mesh, const MeshBand& band);

  btCollisionWorld* collision_world_;
  std::vector<std::unique_ptr<btTriangleMesh>> meshes_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btCollisionObject>> objects_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_BULLET_WORLD_H_
