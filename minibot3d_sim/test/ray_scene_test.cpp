// RayScene: every shape type hit where geometry says, exact curved surfaces, bodies that move only
// at Commit(), hit ids and names, tnear/tfar, and concurrent casts.
#include "minibot3d_sim/ray_scene.h"

#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include <embree3/rtcore.h>
#include <gtest/gtest.h>

namespace minibot3d_sim {
namespace {

Shape Box(const std::string& name, const Eigen::Vector3d& center, const Eigen::Vector3d& size) {
  Shape s;
  s.type = ShapeType::kBox;
  s.name = name;
  s.pose.translation() = center;
  s.size = size;
  return s;
}

Shape Cylinder(const std::string& name, const Eigen::Vector3d& center, double radius,
               double length) {
  Shape s;
  s.type = ShapeType::kCylinder;
  s.name = name;
  s.pose.translation() = center;
  s.size = Eigen::Vector3d(radius, radius, length);
  return s;
}

Shape Sphere(const std::string& name, const Eigen::Vector3d& center, double radius) {
  Shape s;
  s.type = ShapeType::kSphere;
  s.name = name;
  s.pose.translation() = center;
  s.size = Eigen::Vector3d(radius, radius, radius);
  return s;
}

Shape Floor() {
  Shape s;
  s.type = ShapeType::kPlane;
  s.name = "ground_plane::link::collision";
  s.normal = Eigen::Vector3d::UnitZ();
  s.size = Eigen::Vector3d(100, 100, 0);
  return s;
}

struct Hit {
  float t;
  int id;
  Eigen::Vector3f normal;
};

Hit Cast(const RayScene& scene, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
         float tnear = 0.0f, float tfar = std::numeric_limits<float>::infinity()) {
  Hit h;
  scene.Intersect(&o.x(), &o.y(), &o.z(), &d.x(), &d.y(), &d.z(), 1, tnear, tfar, &h.t, &h.id,
                  h.normal.data());
  return h;
}

constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(RaySceneTest, BoxFaceAndItsNormal) {
  World world;
  world.shapes.push_back(Box("wall", {2.5, 0, 0}, {1, 4, 2}));
  const RayScene scene(world);
  const Hit h = Cast(scene, {0, 0, 0}, {1, 0.3f, -0.2f});
  EXPECT_NEAR(h.t, 2.0f, 1e-6);  // x = t·1 = 2
  EXPECT_EQ(h.id, 0);
  EXPECT_NEAR(std::abs(h.normal.x()), 1.0f, 1e-6);
  // Through the diagonal of the face, where its two triangles meet: no crack.
  const Hit diag = Cast(scene, {0, 0, 0}, {1, 0, 0});
  EXPECT_NEAR(diag.t, 2.0f, 1e-6);
  const Hit miss = Cast(scene, {0, 0, 0}, {1, 1.01f, 0});  // past y = 2
  EXPECT_EQ(miss.t, kInf);
  EXPECT_EQ(miss.id, RayScene::kNoHit);
  EXPECT_EQ(miss.normal, Eigen::Vector3f::Zero());
}

TEST(RaySceneTest, CylinderIsExactOnTheSideAndTheCaps) {
  const double r = 0.5, d = 3.0;
  World world;
  world.shapes.push_back(Cylinder("pillar", {d, 0, 0}, r, 2.0));  // z in [-1, 1]
  const RayScene scene(world);
  // Horizontal rays at offset y: the side is met at x = d − √(r² − y²).
  for (const double y : {0.0, 0.2, 0.45, 0.4999}) {
    const Hit h = Cast(scene, {0, static_cast<float>(y), 0}, {1, 0, 0});
    EXPECT_NEAR(h.t, d - std::sqrt(r * r - y * y), 1e-5) << "y " << y;
    EXPECT_NEAR(h.normal.x(), -std::sqrt(r * r - y * y) / r, 1e-5);
    EXPECT_NEAR(h.normal.y(), y / r, 1e-5);
  }
  // Just outside the radius: a tessellated cylinder would be hit or missed at the wrong place.
  EXPECT_EQ(Cast(scene, {0, 0.5001f, 0}, {1, 0, 0}).id, RayScene::kNoHit);
  // Top cap from above, and the rim region just inside it.
  const Hit top = Cast(scene, {3.3f, 0.3f, 5}, {0, 0, -1});
  EXPECT_NEAR(top.t, 4.0f, 1e-6);
  EXPECT_NEAR(top.normal.z(), 1.0f, 1e-6);
  // Above the top (z = 1.5): missed.
  EXPECT_EQ(Cast(scene, {0, 0, 1.5f}, {1, 0, 0}).id, RayScene::kNoHit);
  // A tilted cylinder (axis along world x): the side seen from above at z = r.
  World tilted;
  tilted.shapes.push_back(Cylinder("log", {0, 0, 0}, r, 4.0));
  tilted.shapes.back().pose.linear() =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const RayScene tilted_scene(tilted);
  const Hit log = Cast(tilted_scene, {1.0f, 0.3f, 2}, {0, 0, -1});
  EXPECT_NEAR(log.t, 2.0 - std::sqrt(r * r - 0.3 * 0.3), 1e-5);
  EXPECT_EQ(Cast(tilted_scene, {2.1f, 0, 2}, {0, 0, -1}).id, RayScene::kNoHit);  // past the cap
}

TEST(RaySceneTest, SphereMeshAndPlane) {
  World world;
  world.shapes.push_back(Sphere("ball", {5, 0, 1}, 1.0));
  Shape tri;
  tri.type = ShapeType::kMesh;
  tri.name = "tri";
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->vertices = {{0, -1, 0}, {0, 1, 0}, {0, 0, 2}};
  mesh->triangles = {{0, 1, 2}};
  tri.mesh = mesh;
  tri.pose.translation() = Eigen::Vector3d(0, 5, 0);
  tri.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  world.shapes.push_back(tri);  // in the plane y = 5
  world.shapes.push_back(Floor());
  const RayScene scene(world);

  const Hit ball = Cast(scene, {0, 0, 1}, {1, 0, 0});
  EXPECT_NEAR(ball.t, 4.0f, 1e-6);
  EXPECT_EQ(ball.id, 0);
  // Off-centre: (x − 5)² + y² = 1 along (t, 0.1t, 1).
  const double a = 1.01, b = -10.0, c = 24.0;
  const Hit off = Cast(scene, {0, 0, 1}, {1, 0.1f, 0});
  EXPECT_NEAR(off.t, (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a), 1e-5);

  const Hit t_in = Cast(scene, {0, 0, 0.5f}, {0, 1, 0});
  EXPECT_NEAR(t_in.t, 5.0f, 1e-6);
  EXPECT_EQ(t_in.id, 1);
  EXPECT_NEAR(std::abs(t_in.normal.y()), 1.0f, 1e-6);
  const Hit t_out = Cast(scene, {0.9f, 0, 0.5f}, {0, 1, 0});  // beside the triangle
  EXPECT_NE(t_out.id, 1);

  // The floor seen from above at 45°: from height 2 it is met at t = 2.
  const Hit floor = Cast(scene, {0, -1, 2}, {-1, 0, -1});
  EXPECT_NEAR(floor.t, 2.0f, 1e-6);
  EXPECT_EQ(floor.id, 2);
  EXPECT_NEAR(floor.normal.z(), 1.0f, 1e-6);
  // ... and far away: the plane is infinite (its <size> only sizes Gazebo's visual).
  EXPECT_NEAR(Cast(scene, {0, -1, 2}, {-100, 0, -1}).t, 2.0f, 1e-5);
  EXPECT_EQ(scene.HitName(2), "ground_plane::link::collision");
}

TEST(RaySceneTest, NearAndFarLimits) {
  World world;
  world.shapes.push_back(Box("near", {1.5, 0, 0}, {1, 1, 1}));   // faces x = 1, 2
  world.shapes.push_back(Box("far", {4.5, 0, 0}, {1, 1, 1}));    // faces x = 4, 5
  const RayScene scene(world);
  EXPECT_EQ(Cast(scene, {0, 0, 0}, {1, 0, 0}, 0.0f, 0.9f).id, RayScene::kNoHit);
  const Hit inside = Cast(scene, {0, 0, 0}, {1, 0, 0}, 1.1f, 10.0f);  // the near box's back face
  EXPECT_NEAR(inside.t, 2.0f, 1e-6);
  EXPECT_EQ(inside.id, 0);
  const Hit past = Cast(scene, {0, 0, 0}, {1, 0, 0}, 2.1f, 10.0f);
  EXPECT_NEAR(past.t, 4.0f, 1e-6);
  EXPECT_EQ(past.id, 1);
  // Direction length sets the unit of t.
  EXPECT_NEAR(Cast(scene, {0, 0, 0}, {2, 0, 0}).t, 0.5f, 1e-6);
}

TEST(RaySceneTest, EmptyWorldHitsNothing) {
  const RayScene scene{World()};
  const Hit h = Cast(scene, {0, 0, 0}, {0, 0, -1});
  EXPECT_EQ(h.t, kInf);
  EXPECT_EQ(h.id, RayScene::kNoHit);
  EXPECT_EQ(scene.num_hit_ids(), 0);
}

TEST(RaySceneTest, ScenesShareADevice) {
  RTCDevice device = rtcNewDevice(nullptr);
  ASSERT_NE(device, nullptr);
  {
    World a, b;
    a.shapes.push_back(Box("near", {2.5, 0, 0}, {1, 1, 1}));
    b.shapes.push_back(Sphere("ball", {0, 3, 0}, 1.0));
    const RayScene scene_a(a, device);
    const RayScene scene_b(b, device);
    EXPECT_NEAR(Cast(scene_a, {0, 0, 0}, {1, 0, 0}).t, 2.0f, 1e-6);
    EXPECT_NEAR(Cast(scene_b, {0, 0, 0}, {0, 1, 0}).t, 2.0f, 1e-6);
    EXPECT_EQ(Cast(scene_a, {0, 0, 0}, {0, 1, 0}).id, RayScene::kNoHit);
  }
  rtcReleaseDevice(device);  // after the scenes, as documented
}

TEST(RaySceneTest, BodiesMoveAtCommitOnly) {
  World world;
  world.shapes.push_back(Box("wall", {10, 0, 0}, {1, 20, 4}));  // face x = 9.5
  RayScene scene(world);
  const int person = scene.AddBody(
      {Cylinder("legs", {0, 0, 0.5}, 0.2, 1.0), Sphere("head", {0, 0, 1.4}, 0.15)}, "person");
  EXPECT_EQ(person, 0);
  EXPECT_EQ(scene.num_hit_ids(), 3);
  EXPECT_EQ(scene.BodyHitId(person, 1), 2);
  EXPECT_EQ(scene.HitName(2), "person::head");
  const HitTarget head = scene.Target(2);
  EXPECT_EQ(head.body, person);
  EXPECT_EQ(head.shape, 1);

  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(4, 0, 0);
  scene.SetBodyPose(person, pose);
  // Not committed yet: the ray still reaches the wall.
  EXPECT_EQ(Cast(scene, {0, 0, 0.5f}, {1, 0, 0}).id, 0);
  scene.Commit();
  const Hit legs = Cast(scene, {0, 0, 0.5f}, {1, 0, 0});
  EXPECT_NEAR(legs.t, 3.8f, 1e-5);
  EXPECT_EQ(legs.id, scene.BodyHitId(person, 0));
  EXPECT_EQ(scene.Target(legs.id).body, person);
  const Hit face = Cast(scene, {0, 0, 1.4f}, {1, 0, 0});
  EXPECT_NEAR(face.t, 3.85f, 1e-5);
  EXPECT_EQ(face.id, scene.BodyHitId(person, 1));
  // Static shapes are still there, through the top-level scene.
  const Hit wall = Cast(scene, {0, 3, 0.5f}, {1, 0, 0});
  EXPECT_NEAR(wall.t, 9.5f, 1e-5);
  EXPECT_EQ(wall.id, 0);

  // Turn and move: the new pose only after Commit(); the normal comes out in the world frame.
  const int crate = scene.AddBody({Box("crate", {0, 0, 0}, {2, 0.5, 0.5})}, "crate");
  Eigen::Isometry3d crate_pose = Eigen::Isometry3d::Identity();
  crate_pose.translation() = Eigen::Vector3d(0, 3, 0);
  crate_pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  scene.SetBodyPose(crate, crate_pose);
  pose.translation() = Eigen::Vector3d(6, 0, 0);
  scene.SetBodyPose(person, pose);
  EXPECT_NEAR(Cast(scene, {0, 0, 0.5f}, {1, 0, 0}).t, 3.8f, 1e-5);
  EXPECT_EQ(Cast(scene, {0, 0, 0}, {0, 1, 0}).id, RayScene::kNoHit);
  scene.Commit();
  EXPECT_NEAR(Cast(scene, {0, 0, 0.5f}, {1, 0, 0}).t, 5.8f, 1e-5);
  // The crate's long side (2 m) now lies along y: seen from x = −3 along +x, its face at x = −0.25.
  const Hit side = Cast(scene, {-3, 3.9f, 0}, {1, 0, 0});
  EXPECT_NEAR(side.t, 2.75f, 1e-5);
  EXPECT_EQ(side.id, scene.BodyHitId(crate, 0));
  EXPECT_NEAR(std::abs(side.normal.x()), 1.0f, 1e-5);  // body-frame y turned to world x
  EXPECT_NEAR(Cast(scene, {0, 0, 0}, {0, 1, 0}).t, 2.0f, 1e-5);

  EXPECT_THROW(scene.SetBodyPose(7, pose), std::out_of_range);
  EXPECT_THROW(scene.AddBody({}, "nothing"), std::invalid_argument);
}

TEST(RaySceneTest, BatchesOfAnySizeAndConcurrentCasts) {
  World world;
  world.shapes.push_back(Box("wall", {3.5, 0, 0}, {1, 100, 100}));
  world.shapes.push_back(Cylinder("pillar", {2, 0.5, 0}, 0.3, 4));
  world.shapes.back().color = Eigen::Vector3f(1, 0, 0);
  const RayScene scene(world);
  EXPECT_EQ(scene.HitColor(1), Eigen::Vector3f(1, 0, 0));
  const int n = 37;  // two full packets and a partial one
  std::vector<float> dx(n), dy(n), dz(n);
  for (int i = 0; i < n; ++i) {
    dx[i] = 1.0f;
    dy[i] = -0.5f + i / static_cast<float>(n - 1);
    dz[i] = 0.1f;
  }
  const Eigen::Vector3f origin(0, 0, 0);
  std::vector<float> ox(n, 0.0f), oy(n, 0.0f), oz(n, 0.0f);
  std::vector<float> t1(n), t2(n);
  std::vector<int> id1(n), id2(n);
  scene.IntersectFrom(origin, dx.data(), dy.data(), dz.data(), n, 0.0f, 100.0f, t1.data(),
                      id1.data());
  scene.Intersect(ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), n, 0.0f,
                  100.0f, t2.data(), id2.data());
  int pillar = 0;
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(t1[i], t2[i]);
    EXPECT_EQ(id1[i], id2[i]);
    // One by one: the same answer as in a packet.
    const Hit h = Cast(scene, origin, {dx[i], dy[i], dz[i]}, 0.0f, 100.0f);
    EXPECT_NEAR(h.t, t1[i], 1e-6);
    EXPECT_EQ(h.id, id1[i]);
    if (id1[i] == 0) {
      EXPECT_NEAR(t1[i], 3.0f, 1e-6);
    } else {
      ++pillar;
    }
  }
  EXPECT_GT(pillar, 3);

  std::vector<std::vector<float>> per_thread(3, std::vector<float>(n));
  std::vector<std::vector<int>> per_thread_id(3, std::vector<int>(n));
  std::vector<std::thread> threads;
  for (int k = 0; k < 3; ++k) {
    threads.emplace_back([&, k] {
      for (int rep = 0; rep < 200; ++rep) {
        scene.IntersectFrom(origin, dx.data(), dy.data(), dz.data(), n, 0.0f, 100.0f,
                            per_thread[k].data(), per_thread_id[k].data());
      }
    });
  }
  for (std::thread& t : threads) t.join();
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(per_thread[k], t1);
    EXPECT_EQ(per_thread_id[k], id1);
  }
}

}  // namespace
}  // namespace minibot3d_sim
