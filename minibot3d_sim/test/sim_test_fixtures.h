// Small inline fixtures shared by the simulator core's tests: a robot model like minibot3d and a
// walled room built in code.
#ifndef MINIBOT3D_SIM_TEST_SIM_TEST_FIXTURES_H_
#define MINIBOT3D_SIM_TEST_SIM_TEST_FIXTURES_H_

#include <string>

#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world.h"

namespace minibot3d_sim {
namespace testing {

inline RobotModel MakeRobot() {
  RobotModel m;
  m.name = "fixture";
  m.root_link = "base_footprint";
  const double xs[4] = {0.075, 0.075, -0.075, -0.075}, ys[4] = {0.1, -0.1, 0.1, -0.1};
  const char* joints[4] = {"fl", "fr", "rl", "rr"};
  for (int i = 0; i < 4; ++i) {
    WheelSpec& w = m.wheels[i];
    w.joint = joints[i];
    w.link = std::string(joints[i]) + "_wheel";
    w.position = Eigen::Vector3d(xs[i], ys[i], 0.04);
    w.radius = 0.04;
    w.width = 0.025;
    w.mass = 0.08;
    w.inertia_axle = 0.5 * 0.08 * 0.04 * 0.04;
    w.effort_limit = 2.0;
    w.velocity_limit = 40.0;
    m.drive.joints[i] = joints[i];
  }
  m.drive.wheel_separation = 0.2;
  m.drive.wheel_diameter = 0.08;
  m.drive.torque = 2.0;
  m.body_size = Eigen::Vector3d(0.24, 0.16, 0.05);
  m.body_pose.translation() = Eigen::Vector3d(0, 0, 0.07);
  m.body_mass = 1.2;
  m.total_mass = 1.52;
  m.body_inertia_z = 0.012;
  m.footprint = {{0.12, -0.1125}, {0.12, 0.1125}, {-0.12, 0.1125}, {-0.12, -0.1125}};
  m.lidar.link = m.lidar.frame_id = "laser";
  m.lidar.pose_in_root.translation() = Eigen::Vector3d(0.02, 0, 0.125);
  m.lidar.link_in_root.translation() = Eigen::Vector3d(0.02, 0, 0.095);
  m.lidar.samples = 360;
  m.lidar.min_angle = -M_PI;
  m.lidar.max_angle = M_PI;
  m.lidar.min_range = 0.15;
  m.lidar.max_range = 12.0;
  m.lidar.resolution = 0.0;
  m.lidar.update_rate = 10.0;
  m.lidar.noise_stddev = 0.0;
  return m;
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
