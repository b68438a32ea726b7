#include "minibot3d_sim/bullet_world.h"

#include <algorithm>
#include <cmath>

#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {
namespace {

// Bullet rounds convex shapes by their collision margin (0.04 m by default, kept inside boxes and
// cylinders but still rounding their edges). A few millimetres keep wall corners sharp for contacts
// and ray tests while leaving GJK/EPA enough room to be robust.
constexpr btScalar kStaticMargin = 0.002;

btTransform ToBullet(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d r = pose.rotation();
  const Eigen::Vector3d t = pose.translation();
  return btTransform(btMatrix3x3(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0),
                                 r(2, 1), r(2, 2)),
                     btVector3(t.x(), t.y(), t.z()));
}

}  // namespace

BulletWorldObjects::BulletWorldObjects(const World& world, btCollisionWorld* collision_world,
                                       const MeshBand& band)
    : collision_world_(collision_world) {
  for (std::size_t i = 0; i < world.shapes.size(); ++i) {
    const Shape& s = world.shapes[i];
    std::unique_ptr<btCollisionShape> shape;
    switch (s.type) {
      case ShapeType::kBox: {
        const btVector3 half(s.size.x() / 2, s.size.y() / 2, s.size.z() / 2);
        shape = std::make_unique<btBoxShape>(half);
        // btBoxShape keeps its margin inside the extents; it must stay below the half extents.
        shape->setMargin(std::min(kStaticMargin, half[half.minAxis()] * btScalar(0.5)));
        break;
      }
      case ShapeType::kCylinder: {
        const btVector3 half(s.size.x(), s.size.x(), s.size.z() / 2);
        shape = std::make_unique<btCylinderShapeZ>(half);
        shape->setMargin(std::min(kStaticMargin, half[half.minAxis()] * btScalar(0.5)));
        break;
      }
      case ShapeType::kSphere:
        // A sphere's margin is its radius: nothing to tune.
        shape = std::make_unique<btSphereShape>(s.size.x());
        break;
      case ShapeType::kPlane: {
        const Eigen::Vector3d n = s.normal.normalized();
        shape = std::make_unique<btStaticPlaneShape>(btVector3(n.x(), n.y(), n.z()), 0.0);
        break;
      }
      case ShapeType::kMesh: {
        if (!s.mesh || s.mesh->triangles.empty()) continue;  // nothing to collide with
        if (band.layers > 0 && band.z_max > band.z_min) {
          shape = MeshBandBoxes(s, band);
          if (!shape) continue;  // the mesh does not reach the band
          break;
        }
        auto mesh = std::make_unique<btTriangleMesh>(/*use32bitIndices=*/true,
                                                     /*use4componentVertices=*/false);
        const auto& v = s.mesh->vertices;
        mesh->preallocateVertices(static_cast<int>(s.mesh->triangles.size() * 3));
        for (const auto& tri : s.mesh->triangles) {
          if (tri[0] >= v.size() || tri[1] >= v.size() || tri[2] >= v.size()) continue;
          const Eigen::Vector3f& a = v[tri[0]];
          const Eigen::Vector3f& b = v[tri[1]];
          const Eigen::Vector3f& c = v[tri[2]];
          mesh->addTriangle(btVector3(a.x(), a.y(), a.z()), btVector3(b.x(), b.y(), b.z()),
                            btVector3(c.x(), c.y(), c.z()), /*removeDuplicateVertices=*/false);
        }
        if (mesh->getNumTriangles() == 0) continue;
        shape = std::make_unique<btBvhTriangleMeshShape>(mesh.get(),
                                                         /*useQuantizedAabbCompression=*/true);
        meshes_.push_back(std::move(mesh));
        break;
      }
    }
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(shape.get());
    // Band boxes of a mesh are already in the world frame.
    const bool in_world_frame = shape->getShapeType() == COMPOUND_SHAPE_PROXYTYPE;
    object->setWorldTransform(in_world_frame ? btTransform::getIdentity() : ToBullet(s.pose));
    object->setCollisionFlags(object->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
    object->setUserIndex(static_cast<int>(i));
    // Asleep, a static object is skipped when a dynamics world refreshes AABBs and activation each
    // step (an awake one has its AABB recomputed and re-inserted into the broadphase every step);
    // collision detection against active bodies and ray tests still see it.
    object->setActivationState(ISLAND_SLEEPING);
    collision_world_->addCollisionObject(object.get(), btBroadphaseProxy::StaticFilter,
                                         btBroadphaseProxy::AllFilter ^
                                             btBroadphaseProxy::StaticFilter);
    shapes_.push_back(std::move(shape));
    objects_.push_back(std::move(object));
  }
}

std::unique_ptr<btCollisionShape> BulletWorldObjects::MeshBandBoxes(const Shape& mesh,
                                                                   const MeshBand& band) {
  constexpr double kThickness = 0.01;  // m: the boxes are walls along the cross-section
  World alone;
  alone.shapes.push_back(mesh);
  auto compound = std::make_unique<btCompoundShape>();
  const double layer = (band.z_max - band.z_min) / band.layers;
  for (int l = 0; l < band.layers; ++l) {
    const double z = band.z_min + (l + 0.5) * layer;
    const WorldSlice cut(alone, z);
    for (const Segment2& seg : cut.segments()) {
      const Eigen::Vector2d d = seg.b - seg.a;
      const double length = d.norm();
      if (length < 1e-6) continue;
      // Lengthened by the thickness so that neighbouring boxes close the corners between them.
      auto box = std::make_unique<btBoxShape>(
          btVector3((length + kThickness) / 2, kThickness / 2, layer / 2));
      box->setMargin(std::min<btScalar>(kStaticMargin, kThickness / 4));
      const Eigen::Vector2d mid = 0.5 * (seg.a + seg.b);
      btTransform t(btQuaternion(btVector3(0, 0, 1), std::atan2(d.y(), d.x())),
                    btVector3(mid.x(), mid.y(), z));
      compound->addChildShape(t, box.get());
      shapes_.push_back(std::move(box));
    }
  }
  if (compound->getNumChildShapes() == 0) return nullptr;
  return compound;
}

BulletWorldObjects::~BulletWorldObjects() {
  for (auto& object : objects_) collision_world_->removeCollisionObject(object.get());
}

}  // namespace minibot3d_sim
