// The simulated robot, as read from a URDF with Gazebo extension tags.
//
// The URDF (urdfdom) gives the kinematic tree, link masses and collision boxes; the <gazebo> blocks
// give what Gazebo's plugins would have read: the skid-steer drive plugin (wheel joints,
// wheelSeparation, wheelDiameter, torque, topics, frames, covariances), per-link wheel friction
// (mu1, mu2, kp, kd) and the ray sensor on the lidar link (samples, angles, ranges, noise, rate,
// topic and frame of its ROS plugin).
#ifndef MINIBOT3D_SIM_ROBOT_MODEL_H_
#define MINIBOT3D_SIM_ROBOT_MODEL_H_

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace minibot3d_sim {

class RobotModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Wheel order used everywhere in the simulator.
enum WheelIndex { kFrontLeft = 0, kFrontRight = 1, kRearLeft = 2, kRearRight = 3 };

struct WheelSpec {
  std::string joint;                                  // e.g. front_left_wheel_hinge
  std::string link;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // wheel centre in the root frame (m)
  double radius = 0.0;
  double width = 0.0;
  double mass = 0.0;
  double inertia_axle = 0.0;    // moment of inertia about the axle (kg m^2)
  double mu1 = 1.0, mu2 = 1.0;  // friction along / across the rolling direction
  double kp = 1e6, kd = 1.0;    // contact stiffness / damping (Gazebo/ODE meaning)
  double effort_limit = 0.0;    // from <limit effort>, N m (0: none given)
  double velocity_limit = 0.0;  // from <limit velocity>, rad/s (0: none given)
};

struct DriveSpec {  // libgazebo_ros_skid_steer_drive.so
  double update_rate = 100.0;
  std::string command_topic = "cmd_vel";
  std::string odometry_topic = "odom";
  std::string odometry_frame = "odom";
  std::string robot_base_frame = "base_footprint";
  bool broadcast_tf = true;
  double wheel_separation = 0.0;
  double wheel_diameter = 0.0;
  double torque = 0.0;  // per wheel, N m
  double covariance_x = 1e-4, covariance_y = 1e-4, covariance_yaw = 1e-2;
  std::array<std::string, 4> joints;  // FL, FR, RL, RR
};

struct LidarSpec {  // <sensor type="ray"> + libgazebo_ros_laser.so
  std::string link;                   // the URDF link it is attached to
  std::string frame_id;               // <frameName>
  std::string topic = "scan";         // <topicName>
  Eigen::Isometry3d pose_in_root = Eigen::Isometry3d::Identity();  // ray origin (link ∘ <pose>)
  Eigen::Isometry3d link_in_root = Eigen::Isometry3d::Identity();  // the frame_id's frame
  int samples = 360;
  double min_angle = -M_PI, max_angle = M_PI;
  double min_range = 0.15, max_range = 12.0;
  double resolution = 0.01;
  double update_rate = 10.0;
  double noise_mean = 0.0, noise_stddev = 0.0;
};

struct RobotModel {
  std::string name;
  std::string root_link;  // base_footprint
  double total_mass = 0.0;
  // Body (everything but the wheels) as one box in the root frame: for contacts and footprint.
  Eigen::Vector3d body_size = Eigen::Vector3d::Zero();
  Eigen::Isometry3d body_pose = Eigen::Isometry3d::Identity();
  double body_mass = 0.0;
  double body_inertia_z = 0.0;  // whole robot about the vertical axis through the root (kg m^2)
  std::array<WheelSpec, 4> wheels;
  DriveSpec drive;
  LidarSpec lidar;
  // Convex outline of the body and wheels seen from above, root frame, counter-clockwise.
  std::vector<Eigen::Vector2d> footprint;
  // Non-fatal findings (unknown plugins or tags), one line each, to be logged once.
  std::vector<std::string> warnings;
};

// Parses an expanded URDF document. Throws RobotModelError naming the tag/link/joint at fault
// (missing skid-steer plugin, missing ray sensor, wheel joint not found, ...).
RobotModel ParseRobotModel(const std::string& urdf_xml);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_ROBOT_MODEL_H_
