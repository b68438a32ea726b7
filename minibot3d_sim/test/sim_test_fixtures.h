// Small inline fixtures shared by the simulator core's tests: a robot model like minibot3d and a
// walled room built in code.
#ifndef MINIBOT3D_SIM_TEST_SIM_TEST_FIXTURES_H_
#define MINIBOT3D_SIM_TEST_SIM_TEST_FIXTURES_H_

#include <string>

#include "minibot3d_sim/drive.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world.h"

namespace minibot3d_sim {
namespace testing {

// A skid-steer robot like minibot3d: four wheels at (±0.075, ±0.1), a 0.24 × 0.16 body, one
// 360-beam laser. Wheels in the skid-steer plugin's order: left front, right front, left rear,
// right rear.
inline RobotModel MakeRobot() {
  RobotModel m;
  m.name = "fixture";
  m.root_link = "base_footprint";
  const double xs[4] = {0.075, 0.075, -0.075, -0.075}, ys[4] = {0.1, -0.1, 0.1, -0.1};
  const char* joints[4] = {"fl", "fr", "rl", "rr"};
  for (int i = 0; i < 4; ++i) {
    WheelSpec w;
    w.joint = joints[i];
    w.link = std::string(joints[i]) + "_wheel";
    w.position = Eigen::Vector3d(xs[i], ys[i], 0.04);
    w.left = ys[i] > 0;
    w.radius = 0.04;
    w.width = 0.025;
    w.mass = 0.08;
    w.inertia_axle = 0.5 * 0.08 * 0.04 * 0.04;
    w.effort_limit = 2.0;
    w.velocity_limit = 40.0;
    w.torque = 2.0;
    m.wheels.push_back(w);
  }
  m.drive.kind = DriveKind::kSkidSteer;
  m.drive.robot_namespace = "/";
  m.drive.skid_steer.left_front_joint = "fl";
  m.drive.skid_steer.right_front_joint = "fr";
  m.drive.skid_steer.left_rear_joint = "rl";
  m.drive.skid_steer.right_rear_joint = "rr";
  m.drive.skid_steer.wheel_separation = 0.2;
  m.drive.skid_steer.wheel_diameter = 0.08;
  m.drive.skid_steer.torque = 2.0;
  m.body_size = Eigen::Vector3d(0.24, 0.16, 0.05);
  m.body_pose.translation() = Eigen::Vector3d(0, 0, 0.07);
  m.body_mass = 1.2;
  m.total_mass = 1.52;
  m.body_inertia_z = 0.012;
  m.footprint = {{0.12, -0.1125}, {0.12, 0.1125}, {-0.12, 0.1125}, {-0.12, -0.1125}};
  LaserSpec l;
  l.link = l.frame_id = "laser";
  l.topic = "scan";
  l.pose_in_root.translation() = Eigen::Vector3d(0.02, 0, 0.125);
  l.link_in_root.translation() = Eigen::Vector3d(0.02, 0, 0.095);
  l.samples = 360;
  l.min_angle = -M_PI;
  l.max_angle = M_PI;
  l.min_range = 0.15;
  l.max_range = 12.0;
  l.resolution = 0.0;
  l.update_rate = 10.0;
  l.noise_stddev = 0.0;
  m.lasers.push_back(l);
  return m;
}

struct PhysicsRobotParams {
  double torque = 2.0;
  double mu1 = 1.0;
  double mu2 = 1.0;
};

// The small skid-steer robot of the physics tests and benchmarks: 0.24 x 0.16 x 0.05 body centred
// 0.06 m up, four 0.08 m wheels at (±0.07, ±0.1), 1.5 kg in all.
inline RobotModel MakePhysicsRobot(const PhysicsRobotParams& p = PhysicsRobotParams()) {
  RobotModel m;
  m.name = "minibot";
  m.root_link = "base_footprint";
  m.total_mass = 1.5;
  m.body_mass = 1.1;
  m.body_size = Eigen::Vector3d(0.24, 0.16, 0.05);
  m.body_pose = Eigen::Isometry3d::Identity();
  m.body_pose.translation() = Eigen::Vector3d(0, 0, 0.06);
  m.body_inertia_z = 0.0136;
  const double xs[4] = {0.07, 0.07, -0.07, -0.07};
  const double ys[4] = {0.1, -0.1, 0.1, -0.1};
  for (int i = 0; i < 4; ++i) {
    WheelSpec w;
    w.position = Eigen::Vector3d(xs[i], ys[i], 0.04);
    w.left = ys[i] > 0;
    w.radius = 0.04;
    w.width = 0.03;
    w.mass = 0.1;
    w.inertia_axle = 0.5 * w.mass * 0.04 * 0.04;
    w.mu1 = p.mu1;
    w.mu2 = p.mu2;
    w.torque = p.torque;
    m.wheels.push_back(w);
  }
  m.drive.kind = DriveKind::kSkidSteer;
  m.drive.skid_steer.wheel_separation = 0.2;
  m.drive.skid_steer.wheel_diameter = 0.08;
  m.drive.skid_steer.torque = p.torque;
  m.footprint = {{-0.12, -0.115}, {0.12, -0.115}, {0.12, 0.115}, {-0.12, 0.115}};
  return m;
}

// The skid-steer plugin's wheel speed targets for a body twist (track 0.2 m, radius 0.04 m).
inline DriveTargets SkidTargets(double v, double w, double separation = 0.2, double radius = 0.04) {
  const double left = (v - w * separation / 2.0) / radius;
  const double right = (v + w * separation / 2.0) / radius;
  DriveTargets t;
  t.wheel_speeds = {left, right, left, right};
  t.body_twist = Twist2{v, 0.0, w};
  return t;
}

inline Shape Box(const std::string& name, double x, double y, double sx, double sy,
                 double sz = 1.0) {
  Shape s;
  s.type = ShapeType::kBox;
  s.name = name;
  s.pose.translation() = Eigen::Vector3d(x, y, sz / 2);
  s.size = Eigen::Vector3d(sx, sy, sz);
  return s;
}

// Floor plane (shape 0), a 0.5 m high, 0.1 m thick wall whose near face is at x = wall_x spanning
// y in [-2, 2] (shape 1) and a post far away (shape 2).
inline World MakeWallWorld(double wall_x = 50.0) {
  World w;
  Shape floor;
  floor.type = ShapeType::kPlane;
  floor.name = "ground_plane::link::collision";
  w.shapes.push_back(floor);
  Shape wall = Box("wall::link::collision", wall_x + 0.05, 0, 0.1, 4.0, 0.5);
  w.shapes.push_back(wall);
  w.shapes.push_back(Box("post::link::collision", -5, 5, 0.2, 0.2, 0.5));
  return w;
}

// A floor and a square room with inner faces at ±half (walls 0.1 m thick).
inline World MakeRoom(double half = 2.0) {
  World w;
  w.source = "fixture";
  Shape floor;
  floor.type = ShapeType::kPlane;
  floor.name = "ground_plane::link::collision";
  w.shapes.push_back(floor);
  const double t = 0.1, len = 2 * half + 2 * t;
  w.shapes.push_back(Box("north", 0, half + t / 2, len, t));
  w.shapes.push_back(Box("south", 0, -half - t / 2, len, t));
  w.shapes.push_back(Box("east", half + t / 2, 0, t, len));
  w.shapes.push_back(Box("west", -half - t / 2, 0, t, len));
  return w;
}

}  // namespace testing
}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_TEST_SIM_TEST_FIXTURES_H_
