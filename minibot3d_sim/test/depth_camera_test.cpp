// DepthCamera against depths worked out by hand: z-depth of a box face, an upright cylinder, a
// sphere, a mesh triangle and a tilted view of the floor; image orientation, clipping, bodies,
// colour, intrinsics, the point cloud, spec errors, and identical frames for any thread count.
#include "minibot3d_sim/depth_camera.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "minibot3d_sim/world_loader.h"

namespace minibot3d_sim {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

Shape Box(const Eigen::Vector3d& center, const Eigen::Vector3d& size,
          const std::string& name = "box") {
  Shape s;
  s.type = ShapeType::kBox;
  s.name = name;
  s.pose.translation() = center;
  s.size = size;
  return s;
}

DepthCameraSpec Spec(int w, int h, double hfov) {
  DepthCameraSpec spec;
  spec.width = w;
  spec.height = h;
  spec.horizontal_fov = hfov;
  spec.near_clip = 0.05;
  spec.far_clip = 10.0;
  spec.threads = 1;
  return spec;
}

// Gazebo camera frame at `position`, turned by yaw (about z) then pitch (about the new y; positive
// looks down).
Eigen::Isometry3d CameraPose(const Eigen::Vector3d& position, double yaw = 0.0,
                             double pitch = 0.0) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = position;
  pose.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                      .toRotationMatrix();
  return pose;
}

float Depth(const DepthFrame& f, int u, int v) { return f.depth[v * f.width + u]; }
int Id(const DepthFrame& f, int u, int v) { return f.hit_id[v * f.width + u]; }

TEST(DepthCameraTest, BoxFaceReadsItsDistanceAtEveryPixel) {
  World world;
  world.shapes.push_back(Box({2.5, 0, 0}, {1, 40, 40}));  // face at x = 2
  const RayScene scene(world);
  DepthCamera camera(Spec(64, 48, 1.2));
  DepthFrame frame;
  camera.Render(scene, CameraPose({0, 0, 0}), &frame);
  ASSERT_EQ(frame.depth.size(), 64u * 48u);
  for (int v = 0; v < 48; ++v) {
    for (int u = 0; u < 64; ++u) {
      // z-depth, not ray length: the whole face is 2 m away along the optical axis.
      ASSERT_NEAR(Depth(frame, u, v), 2.0f, 1e-5) << u << "," << v;
      ASSERT_EQ(Id(frame, u, v), 0);
    }
  }
}

TEST(DepthCameraTest, UprightCylinderByHand) {
  // Radius R at distance D on the optical axis, 4 m tall (z in [-2, 2]).
  const double r = 0.5, d = 3.0;
  World world;
  Shape cyl;
  cyl.type = ShapeType::kCylinder;
  cyl.name = "pillar";
  cyl.pose.translation() = Eigen::Vector3d(d, 0, 0);
  cyl.size = Eigen::Vector3d(r, r, 4.0);
  world.shapes.push_back(cyl);
  const RayScene scene(world);
  const int w = 101, h = 51;  // odd: the centre pixel looks exactly along the axis
  DepthCamera camera(Spec(w, h, 1.0));
  DepthFrame frame;
  camera.Render(scene, CameraPose({0, 0, 0}), &frame);
  EXPECT_NEAR(Depth(frame, 50, 25), d - r, 1e-5);

  // Pixel u looks at the horizontal angle α = atan(−(u − 50)/f) (left of the axis for u < 50).
  // Its ray (x, y) = t·(1, tan α) meets (x − D)² + y² = R² at
  //   t = (D − √(D² − (1 + tan²α)(D² − R²))) / (1 + tan²α),
  // and t is the z-depth. A vertical offset does not change it (the cylinder is upright).
  const double f = camera.focal_length();
  int hits = 0;
  for (int u = 0; u < w; ++u) {
    const double tan_a = -(u - 0.5 * (w - 1)) / f;
    const double k = 1.0 + tan_a * tan_a;
    const double disc = d * d - k * (d * d - r * r);
    for (const int v : {0, 10, 25, 40, 50}) {
      if (disc < 0.0) {
        EXPECT_EQ(Depth(frame, u, v), kInf) << "u " << u;
        EXPECT_EQ(Id(frame, u, v), RayScene::kNoHit);
      } else {
        EXPECT_NEAR(Depth(frame, u, v), (d - std::sqrt(disc)) / k, 1e-4)
            << "u " << u << " v " << v << " alpha " << std::atan(tan_a);
        ++hits;
      }
    }
  }
  EXPECT_GT(hits, 5 * 20);
}

TEST(DepthCameraTest, FloorSeenFromAboveAtATilt) {
  World world;
  Shape floor;
  floor.type = ShapeType::kPlane;
  floor.normal = Eigen::Vector3d::UnitZ();
  world.shapes.push_back(floor);
  const RayScene scene(world);
  const int w = 41, h = 31;
  const double pitch = M_PI / 6, height = 1.0;
  DepthCamera camera(Spec(w, h, 1.0));
  DepthFrame frame;
  camera.Render(scene, CameraPose({0.3, -0.2, height}, 0.7, pitch), &frame);
  // The optical axis meets the floor at ray length height / sin(pitch) = 2.
  EXPECT_NEAR(Depth(frame, 20, 15), 2.0f, 1e-5);
  // Pixel (u, v): camera-frame ray (1, a, b) with b = −(v − 15)/f; its world z component is
  // −sin(pitch) + b·cos(pitch) (yaw does not change it), so z-depth = height / −that.
  const double f = camera.focal_length();
  for (int v = 0; v < h; ++v) {
    const double b = -(v - 0.5 * (h - 1)) / f;
    const double dz = -std::sin(pitch) + b * std::cos(pitch);
    const double expected = dz < 0.0 ? height / -dz : kInf;
    for (int u = 0; u < w; u += 5) {
      if (std::isfinite(expected) && expected <= 10.0) {
        EXPECT_NEAR(Depth(frame, u, v), expected, 1e-4 * expected) << u << "," << v;
      } else if (expected > 10.001) {
        EXPECT_EQ(Depth(frame, u, v), kInf) << u << "," << v;
      }
    }
    // Nearer at the bottom of the image, where the camera looks down more.
    if (v > 0 && std::isfinite(Depth(frame, 20, v - 1))) {
      EXPECT_LT(Depth(frame, 20, v), Depth(frame, 20, v - 1));
    }
  }
}

TEST(DepthCameraTest, SphereAndMeshTriangleAndImageOrientation) {
  World world;
  Shape ball;
  ball.type = ShapeType::kSphere;
  ball.name = "ball";
  ball.pose.translation() = Eigen::Vector3d(4, 0, 0);
  ball.size = Eigen::Vector3d(1, 1, 1);
  world.shapes.push_back(ball);
  // A triangle in the plane x = 2, left of the axis (+y) and above it (+z).
  Shape tri;
  tri.type = ShapeType::kMesh;
  tri.name = "tri";
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->vertices = {{2, 0.3f, 0.3f}, {2, 0.9f, 0.3f}, {2, 0.6f, 0.8f}};
  mesh->triangles = {{0, 1, 2}};
  tri.mesh = mesh;
  world.shapes.push_back(tri);
  const RayScene scene(world);
  const int w = 81, h = 61;
  DepthCamera camera(Spec(w, h, 1.2));
  DepthFrame frame;
  camera.Render(scene, CameraPose({0, 0, 0}), &frame);
  EXPECT_NEAR(Depth(frame, 40, 30), 3.0f, 1e-5);  // D − r
  EXPECT_EQ(Id(frame, 40, 30), 0);

  // The pixel whose ray goes through the centroid (2, y, z): u = 40 − (y/2)·f, v = 30 − (z/2)·f.
  const double f = camera.focal_length();
  const double y = (0.3 + 0.9 + 0.6) / 3.0, z = (0.3 + 0.3 + 0.8) / 3.0;
  const int u = static_cast<int>(std::lround(40 - y / 2.0 * f));
  const int v = static_cast<int>(std::lround(30 - z / 2.0 * f));
  EXPECT_LT(u, w / 2);  // +y (left) is on the left of the image
  EXPECT_LT(v, h / 2);  // +z (up) is at the top
  EXPECT_EQ(Id(frame, u, v), 1);
  EXPECT_NEAR(Depth(frame, u, v), 2.0f, 1e-5);
  // Nothing of it on the right or bottom half.
  for (int vv = 0; vv < h; ++vv) {
    for (int uu = 0; uu < w; ++uu) {
      if (Id(frame, uu, vv) == 1) {
        EXPECT_LT(uu, w / 2);
        EXPECT_LT(vv, h / 2);
      }
    }
  }
}

TEST(DepthCameraTest, BodyIsSeenAfterCommitOnly) {
  World world;
  world.shapes.push_back(Box({5, 0, 0}, {1, 40, 40}, "wall"));  // face x = 4.5
  RayScene scene(world);
  const int crate = scene.AddBody({Box({0, 0, 0}, {0.5, 0.5, 0.5}, "crate")}, "crate");
  DepthCamera camera(Spec(33, 25, 1.0));
  DepthFrame frame;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(2.25, 0, 0);  // near face x = 2
  scene.SetBodyPose(crate, pose);
  camera.Render(scene, CameraPose({0, 0, 0}), &frame);
  EXPECT_NEAR(Depth(frame, 16, 12), 4.5f, 1e-5);
  scene.Commit();
  camera.Render(scene, CameraPose({0, 0, 0}), &frame);
  EXPECT_NEAR(Depth(frame, 16, 12), 2.0f, 1e-5);
  EXPECT_EQ(Id(frame, 16, 12), scene.BodyHitId(crate, 0));
  EXPECT_EQ(Id(frame, 0, 0), 0);  // the wall around it
}

TEST(DepthCameraTest, NearFarClippingAndEmptyWorld) {
  World world;
  world.shapes.push_back(Box({2.5, 0, 0}, {1, 40, 40}));  // face x = 2
  world.shapes.back().color = Eigen::Vector3f(0, 0, 1);
  const RayScene scene(world);
  DepthFrame frame;

  DepthCameraSpec spec = Spec(16, 12, 1.0);
  spec.near_clip = 2.5;
  spec.far_clip = 20.0;
  DepthCamera too_near(spec);
  too_near.Render(scene, CameraPose({0, 0, 0}), &frame);
  for (std::size_t p = 0; p < frame.depth.size(); ++p) {
    EXPECT_EQ(frame.depth[p], kInf);
    EXPECT_EQ(frame.hit_id[p], 0);       // the face is still there ...
    EXPECT_GT(frame.rgb[3 * p + 2], 60);  // ... and blocks the view
  }

  spec.near_clip = 0.1;
  spec.far_clip = 1.5;
  DepthCamera too_far(spec);
  too_far.Render(scene, CameraPose({0, 0, 0}), &frame);
  for (std::size_t p = 0; p < frame.depth.size(); ++p) {
    EXPECT_EQ(frame.depth[p], kInf);
    EXPECT_EQ(frame.hit_id[p], RayScene::kNoHit);
    EXPECT_NEAR(frame.rgb[3 * p], 0.7 * 255, 1.0);  // the background
  }

  const RayScene empty{World()};
  DepthCamera camera(Spec(16, 12, 1.0));
  camera.Render(empty, CameraPose({0, 0, 0}), &frame);
  for (std::size_t p = 0; p < frame.depth.size(); ++p) {
    EXPECT_EQ(frame.depth[p], kInf);
    EXPECT_EQ(frame.hit_id[p], RayScene::kNoHit);
  }
}

TEST(DepthCameraTest, RedBoxIsRedOnTheBackground) {
  World world;
  world.shapes.push_back(Box({3, 0, 0}, {1, 1, 1}));
  world.shapes.back().color = Eigen::Vector3f(1, 0, 0);
  const RayScene scene(world);
  DepthCameraSpec spec = Spec(41, 31, 1.0);
  DepthFrame frame;
  DepthCamera rgb(spec);
  rgb.Render(scene, CameraPose({0, 0, 0}), &frame);
  ASSERT_EQ(frame.channels, 3);
  const std::uint8_t* centre = &frame.rgb[3 * (15 * 41 + 20)];
  EXPECT_EQ(centre[0], 255);  // seen face-on: full colour
  EXPECT_EQ(centre[1], 0);
  EXPECT_EQ(centre[2], 0);
  const std::uint8_t* corner = &frame.rgb[0];
  EXPECT_EQ(Id(frame, 0, 0), RayScene::kNoHit);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(corner[c], 0.7 * 255, 1.0);

  spec.format = PixelFormat::kB8G8R8;
  DepthCamera bgr(spec);
  bgr.Render(scene, CameraPose({0, 0, 0}), &frame);
  EXPECT_EQ(frame.rgb[3 * (15 * 41 + 20) + 2], 255);
  EXPECT_EQ(frame.rgb[3 * (15 * 41 + 20)], 0);

  spec.format = PixelFormat::kL8;
  DepthCamera mono(spec);
  mono.Render(scene, CameraPose({0, 0, 0}), &frame);
  ASSERT_EQ(frame.channels, 1);
  ASSERT_EQ(frame.rgb.size(), 41u * 31u);
  EXPECT_EQ(frame.rgb[15 * 41 + 20], 76);  // 0.299 · 255
}

TEST(DepthCameraTest, FacesAtDifferentAnglesAreShadedApart) {
  World world;
  world.shapes.push_back(Box({3, 0, 0}, {1, 1, 1}));
  world.shapes.back().pose.linear() =
      Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const RayScene scene(world);
  DepthCamera camera(Spec(41, 31, 0.6));
  DepthFrame frame;
  camera.Render(scene, CameraPose({0, 0, 0}), &frame);
  // The box turned 0.5 rad shows its −x face (normal 0.5 rad from the view axis) in columns ~14..36
  // and its +y face (1.07 rad) in columns ~6..14: shades 0.3 + 0.7·cos of those, 0.91 and 0.64.
  const int left = frame.rgb[3 * (15 * 41 + 10)], right = frame.rgb[3 * (15 * 41 + 22)];
  ASSERT_EQ(Id(frame, 10, 15), 0);
  ASSERT_EQ(Id(frame, 22, 15), 0);
  EXPECT_LT(left, right);
  EXPECT_GT(std::abs(left - right), 20);
}

TEST(DepthCameraTest, IntrinsicsAndPointCloudAsGazeboReportsThem) {
  World world;
  world.shapes.push_back(Box({2.5, 0, 0}, {1, 40, 40}));  // face x = 2
  const RayScene scene(world);
  const int w = 64, h = 48;
  const double hfov = 1.2;
  DepthCamera camera(Spec(w, h, hfov));
  const CameraIntrinsics k = camera.Intrinsics();
  const double f = w / (2.0 * std::tan(hfov / 2.0));
  EXPECT_DOUBLE_EQ(k.fx, f);
  EXPECT_DOUBLE_EQ(k.fy, f);
  EXPECT_DOUBLE_EQ(k.cx, 32.5);  // (W + 1)/2
  EXPECT_DOUBLE_EQ(k.cy, 24.5);
  DepthFrame frame;
  camera.Render(scene, CameraPose({0, 0, 0}), &frame);

  std::vector<float> points;
  PointsFromDepth(frame, camera.focal_length(), 0.4, -1.0, &points);
  ASSERT_EQ(points.size(), 64u * 48u * 3u);
  for (const int u : {0, 17, 63}) {
    for (const int v : {0, 30, 47}) {
      const float* p = &points[3 * (v * w + u)];
      EXPECT_NEAR(p[0], 2.0 * (u - 31.5) / f, 1e-5);  // right
      EXPECT_NEAR(p[1], 2.0 * (v - 23.5) / f, 1e-5);  // down
      EXPECT_NEAR(p[2], 2.0, 1e-5);                   // forward
    }
  }
  // The plugin's cutoffs: (cutoff, cutoff_max), open at both ends.
  PointsFromDepth(frame, camera.focal_length(), 2.5, -1.0, &points);
  EXPECT_TRUE(std::isnan(points[0]) && std::isnan(points[1]) && std::isnan(points[2]));
  PointsFromDepth(frame, camera.focal_length(), 0.4, 1.9, &points);
  EXPECT_TRUE(std::isnan(points[2]));
  PointsFromDepth(frame, camera.focal_length(), 0.4, 2.1, &points);
  EXPECT_NEAR(points[2], 2.0, 1e-5);
  frame.depth[0] = kInf;  // no return
  PointsFromDepth(frame, camera.focal_length(), 0.4, -1.0, &points);
  EXPECT_TRUE(std::isnan(points[0]));
}

TEST(DepthCameraTest, SpecErrorsNameTheField) {
  const auto message = [](const DepthCameraSpec& spec) -> std::string {
    try {
      DepthCamera camera(spec);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  DepthCameraSpec spec = Spec(40000, 10, 1.0);
  std::string m = message(spec);
  EXPECT_NE(m.find("width"), std::string::npos) << m;
  EXPECT_NE(m.find("40000"), std::string::npos) << m;
  spec = Spec(10, 0, 1.0);
  EXPECT_NE(message(spec).find("height"), std::string::npos);
  spec = Spec(10, 10, M_PI);
  EXPECT_NE(message(spec).find("horizontal_fov"), std::string::npos);
  spec = Spec(10, 10, 1.0);
  spec.far_clip = spec.near_clip;
  EXPECT_NE(message(spec).find("far_clip"), std::string::npos);
  spec = Spec(10, 10, 1.0);
  spec.noise_stddev = -1;
  EXPECT_NE(message(spec).find("noise_stddev"), std::string::npos);
  EXPECT_EQ(message(Spec(DepthCameraSpec::kMaxSize, 1, 1.0)), "");
}

#ifdef MINIBOT3D_SIM_SOURCE_DIR
TEST(DepthCameraTest, SameFramesForAnyThreadCount) {
  WorldLoadOptions options;
  options.use_gazebo_model_path_env = false;
  const World world = LoadWorld(std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/worlds/default.world",
                                options, nullptr);
  RayScene scene(world);
  Shape torso = Box({0, 0, 0.9}, {0.3, 0.5, 0.6}, "torso");
  const int person = scene.AddBody({torso}, "person");
  Eigen::Isometry3d person_pose = Eigen::Isometry3d::Identity();
  person_pose.translation() = Eigen::Vector3d(-1.5, -1.2, 0);
  scene.SetBodyPose(person, person_pose);
  scene.Commit();

  DepthCameraSpec spec = Spec(97, 61, 1.3);  // not a whole number of 4×4 tiles
  spec.noise_stddev = 0.01;
  spec.seed = 7;
  const Eigen::Isometry3d pose = CameraPose({-3.0, -1.5, 0.3}, 0.2, 0.1);
  DepthFrame one[2], three[2], clean;
  DepthCamera a(spec);
  spec.threads = 3;
  DepthCamera b(spec);
  for (int i = 0; i < 2; ++i) {
    a.Render(scene, pose, &one[i]);
    b.Render(scene, pose, &three[i]);
    ASSERT_EQ(one[i].depth.size(), three[i].depth.size());
    EXPECT_EQ(std::memcmp(one[i].depth.data(), three[i].depth.data(),
                          one[i].depth.size() * sizeof(float)),
              0);
    EXPECT_EQ(one[i].rgb, three[i].rgb);
    EXPECT_EQ(one[i].hit_id, three[i].hit_id);
  }
  // The generator runs on: the second frame's noise is not the first's.
  EXPECT_NE(std::memcmp(one[0].depth.data(), one[1].depth.data(),
                        one[0].depth.size() * sizeof(float)),
            0);
  spec.noise_stddev = 0.0;
  DepthCamera noiseless(spec);
  noiseless.Render(scene, pose, &clean);
  int finite = 0, person_pixels = 0;
  for (std::size_t p = 0; p < clean.depth.size(); ++p) {
    if (!std::isfinite(clean.depth[p])) continue;
    ++finite;
    person_pixels += clean.hit_id[p] == scene.BodyHitId(person, 0);
    if (std::isfinite(one[0].depth[p])) {
      EXPECT_NEAR(one[0].depth[p], clean.depth[p], 0.06);
    }
  }
  EXPECT_GT(finite, 97 * 61 / 2);
  EXPECT_GT(person_pixels, 10);
}
#endif

}  // namespace
}  // namespace minibot3d_sim
