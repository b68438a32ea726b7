#include "minibot3d_sim/imu.h"

#include <cmath>

namespace minibot3d_sim {

Eigen::Isometry3d RootTransform(const minibot3d_common::Pose2& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(pose.x, pose.y, 0.0);
  t.linear() = Eigen::AngleAxisd(pose.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

namespace {

// The world velocity of a point fixed to the body at `r` (world-frame offset from the root).
Eigen::Vector3d PointVelocity(const minibot3d_common::Pose2& pose,
                              const minibot3d_common::Twist2& twist, const Eigen::Vector3d& r) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  const Eigen::Vector3d v_root(c * twist.vx - s * twist.vy, s * twist.vx + c * twist.vy, 0.0);
  return v_root + Eigen::Vector3d(0.0, 0.0, twist.wz).cross(r);
}

double Draw(std::mt19937* rng, double mean, double stddev) {
  if (!(stddev > 0.0)) return mean;
  return std::normal_distribution<double>(mean, stddev)(*rng);
}

}  // namespace

Imu::Imu(const ImuSpec& spec, unsigned seed) : spec_(spec), rng_(seed) {
  const ImuSensorOptions& n = spec_.noise;
  // Gazebo draws each bias once, and flips its sign with probability 1/2.
  auto bias = [&](double mean, double stddev) {
    double b = Draw(&rng_, mean, stddev);
    if (std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < 0.5) b = -b;
    return b;
  };
  rate_bias_ = Eigen::Vector3d(bias(n.av_x_bias_mean, n.av_x_bias_stddev),
                               bias(n.av_y_bias_mean, n.av_y_bias_stddev),
                               bias(n.av_z_bias_mean, n.av_z_bias_stddev));
  accel_bias_ = Eigen::Vector3d(bias(n.la_x_bias_mean, n.la_x_bias_stddev),
                                bias(n.la_y_bias_mean, n.la_y_bias_stddev),
                                bias(n.la_z_bias_mean, n.la_z_bias_stddev));
}

double Imu::Noise(double mean, double stddev) { return Draw(&rng_, mean, stddev); }

ImuReading Imu::Sample(double t, const minibot3d_common::Pose2& pose,
                       const minibot3d_common::Twist2& twist) {
  const Eigen::Isometry3d root = RootTransform(pose);
  const Eigen::Isometry3d imu = root * spec_.pose_in_root;
  const Eigen::Matrix3d to_imu = imu.linear().transpose();
  const Eigen::Vector3d r = root.linear() * spec_.pose_in_root.translation();
  const Eigen::Vector3d velocity = PointVelocity(pose, twist, r);
  Eigen::Vector3d accel_world = Eigen::Vector3d::Zero();
  if (have_previous_ && t > previous_time_) {
    accel_world = (velocity - previous_velocity_) / (t - previous_time_);
  }
  have_previous_ = true;
  previous_time_ = t;
  previous_velocity_ = velocity;
  if (spec_.gravity) accel_world -= Eigen::Vector3d(0.0, 0.0, -kGravity);

  Eigen::Quaterniond q(imu.linear());
  if (spec_.initial_orientation_as_reference) {
    if (!have_reference_) {
      reference_ = q;
      have_reference_ = true;
    }
    q = reference_.conjugate() * q;
  }
  q = spec_.orientation_offset * q;

  ImuReading out;
  out.angular_velocity = to_imu * Eigen::Vector3d(0.0, 0.0, twist.wz);
  out.linear_acceleration = to_imu * accel_world;
  const ImuSensorOptions& n = spec_.noise;
  const double av_mean[3] = {n.av_x_mean, n.av_y_mean, n.av_z_mean};
  const double av_std[3] = {n.av_x_stddev, n.av_y_stddev, n.av_z_stddev};
  const double la_mean[3] = {n.la_x_mean, n.la_y_mean, n.la_z_mean};
  const double la_std[3] = {n.la_x_stddev, n.la_y_stddev, n.la_z_stddev};
  for (int k = 0; k < 3; ++k) {
    out.angular_velocity[k] += rate_bias_[k] + Noise(av_mean[k], av_std[k]);
    out.linear_acceleration[k] += accel_bias_[k] + Noise(la_mean[k], la_std[k]);
  }
  const double g = spec_.gaussian_noise;
  if (g > 0.0) {
    for (int k = 0; k < 3; ++k) {
      out.angular_velocity[k] += Noise(0.0, g);
      out.linear_acceleration[k] += Noise(0.0, g);
    }
    if (spec_.gravity) {  // the sensor plugin also perturbs the quaternion, not renormalised
      q = Eigen::Quaterniond(q.w() + Noise(0.0, g), q.x() + Noise(0.0, g), q.y() + Noise(0.0, g),
                             q.z() + Noise(0.0, g));
    }
  }
  out.orientation = q;
  out.variance = g * g;
  return out;
}

GroundTruth::GroundTruth(const GroundTruthSpec& spec, unsigned seed) : spec_(spec), rng_(seed) {}

GroundTruthReading GroundTruth::Sample(const minibot3d_common::Pose2& pose,
                                       const minibot3d_common::Twist2& twist) {
  const Eigen::Isometry3d root = RootTransform(pose);
  Eigen::Isometry3d link = root * spec_.link_in_root;
  // Gazebo's p3d: position + offset, orientation offset before the link's.
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = link.translation() + spec_.offset.translation();
  p.linear() = spec_.offset.linear() * link.linear();
  const Eigen::Vector3d r = link.translation() - root.translation();
  Eigen::Vector3d linear = PointVelocity(pose, twist, r);
  Eigen::Vector3d angular(0.0, 0.0, twist.wz);
  GroundTruthReading out;
  if (!spec_.reference_link.empty()) {
    const Eigen::Isometry3d ref = root * spec_.reference_in_root;
    const Eigen::Vector3d v_ref =
        PointVelocity(pose, twist, ref.translation() - root.translation());
    out.pose.translation() = ref.linear().transpose() * (p.translation() - ref.translation());
    out.pose.linear() = p.linear() * ref.linear().transpose();
    linear = ref.linear() * (linear - v_ref);
    angular = ref.linear() * (angular - Eigen::Vector3d(0.0, 0.0, twist.wz));
  } else {
    out.pose = p;
  }
  const double g = spec_.options.gaussian_noise;
  for (int k = 0; k < 3 && g > 0.0; ++k) {
    linear[k] += std::normal_distribution<double>(0.0, g)(rng_);
    angular[k] += std::normal_distribution<double>(0.0, g)(rng_);
  }
  out.linear = linear;
  out.angular = angular;
  out.variance = g * g;
  return out;
}

}  // namespace minibot3d_sim
