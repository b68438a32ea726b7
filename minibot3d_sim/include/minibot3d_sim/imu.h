// An IMU on a planar robot, as Gazebo's two IMU plugins report it.
//
// Angular velocity: the body's yaw rate (0, 0, ω) rotated into the IMU frame. Linear acceleration:
// the IMU point's mean acceleration since the previous sample (Δv / Δt of its velocity v_root +
// ω × r), as libgazebo_ros_imu.so takes it, rotated into the IMU frame; libgazebo_ros_imu_sensor.so
// reports specific force, the acceleration minus gravity (+9.81 m/s² up at rest), the model plugin
// the acceleration alone. Orientation: the IMU frame's in the world (REP 145), or relative to its
// first one, times rpyOffset. Noise: the sensor plugin's per-axis SDF noise (mean, stddev and a
// bias drawn once, its sign flipped with probability 1/2, as Gazebo's GaussianNoiseModel) and both
// plugins' gaussianNoise, from one seeded generator (deterministic on sim time).
#ifndef MINIBOT3D_SIM_IMU_H_
#define MINIBOT3D_SIM_IMU_H_

#include <random>

#include <Eigen/Geometry>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/gazebo_plugins.h"

namespace minibot3d_sim {

struct ImuReading {
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();     // rad/s, IMU frame
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  // m/s², IMU frame
  double variance = 0.0;  // gaussianNoise², for the message's covariances
};

class Imu {
 public:
  static constexpr double kGravity = 9.81;

  Imu(const ImuSpec& spec, unsigned seed);

  // A sample at sim time t with the root at `pose` moving at `twist` (body frame).
  ImuReading Sample(double t, const minibot3d_common::Pose2& pose,
                    const minibot3d_common::Twist2& twist);
  // Forget the previous sample (after a teleport: no acceleration across it).
  void Restart() { have_previous_ = false; }
  const ImuSpec& spec() const { return spec_; }

 private:
  double Noise(double mean, double stddev);

  ImuSpec spec_;
  std::mt19937 rng_;
  Eigen::Vector3d rate_bias_ = Eigen::Vector3d::Zero(), accel_bias_ = Eigen::Vector3d::Zero();
  bool have_previous_ = false;
  double previous_time_ = 0.0;
  Eigen::Vector3d previous_velocity_ = Eigen::Vector3d::Zero();  // world frame
  bool have_reference_ = false;
  Eigen::Quaterniond reference_ = Eigen::Quaterniond::Identity();
};

struct GroundTruthReading {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // the link (with offsets) in the frame
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();        // world-frame velocity, as Gazebo
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
  double variance = 0.0;
};

// libgazebo_ros_p3d.so: a link's true pose (in the world or relative to another link of the
// robot) and its world-frame velocity, with Gaussian noise on the velocity only.
class GroundTruth {
 public:
  GroundTruth(const GroundTruthSpec& spec, unsigned seed);
  GroundTruthReading Sample(const minibot3d_common::Pose2& pose,
                            const minibot3d_common::Twist2& twist);
  const GroundTruthSpec& spec() const { return spec_; }

 private:
  GroundTruthSpec spec_;
  std::mt19937 rng_;
};

// The root frame at a planar pose, as a 3-D transform.
Eigen::Isometry3d RootTransform(const minibot3d_common::Pose2& pose);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_IMU_H_
