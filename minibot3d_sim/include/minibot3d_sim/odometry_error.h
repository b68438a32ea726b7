// Odometry error: what a real base's wheel odometry gets wrong, laid over any drive's odometry.
//
// Systematic errors are those of a miscalibrated base (Borenstein and Feng, "Measurement and
// correction of systematic odometry errors in mobile robots", IEEE T-RA 12(6), 1996): wheels
// whose radius the odometry overestimates (distance scale), a track it misjudges (rotation scale)
// and wheels of unequal size (a heading drift per metre). Random errors grow with the square root
// of the distance driven and the angle turned, as independent per-step errors do (the variances
// of Thrun, Burgard and Fox's odometry motion model, Probabilistic Robotics ch. 5.4, grow
// linearly with the motion).
//
// Per physics step, the drive's odometry moved by d (in its previous pose's frame); the erroneous
// odometry moves by
//   translation  d.xy × (1 + scale + distance_noise × n1 / sqrt(|s|))        (|s| = |d.xy|)
//   rotation     d.yaw × (1 + turn_scale) + heading_drift × s
//                + turn_noise × sqrt(|d.yaw|) × n2 + heading_noise × sqrt(|s|) × n3
// with s signed by the direction of travel and n1..n3 standard normal draws from a seeded stream,
// so the error is the same on every run of the same commands. The twist is scaled alike (no
// noise). All zero: the drive's odometry exactly.
#ifndef MINIBOT3D_SIM_ODOMETRY_ERROR_H_
#define MINIBOT3D_SIM_ODOMETRY_ERROR_H_

#include <random>

#include "minibot3d_common/geometry2d.h"

namespace minibot3d_sim {

using minibot3d_common::Pose2;
using minibot3d_common::Twist2;

struct OdometryErrorOptions {
  double scale = 0.0;           // relative distance error (+0.02: reports 2 % too far)
  double turn_scale = 0.0;      // relative rotation error (-0.02: reports 2 % too little)
  double heading_drift = 0.0;   // rad per m travelled (+: the odometry curves left)
  double distance_noise = 0.0;  // m per sqrt(m): distance error's std after 1 m
  double turn_noise = 0.0;      // rad per sqrt(rad): rotation error's std after 1 rad turned
  double heading_noise = 0.0;   // rad per sqrt(m): heading error's std after 1 m travelled

  bool enabled() const {
    return scale != 0.0 || turn_scale != 0.0 || heading_drift != 0.0 || distance_noise != 0.0 ||
           turn_noise != 0.0 || heading_noise != 0.0;
  }
};

// Throws std::invalid_argument naming the option: scales must be > -1, noises >= 0, all finite.
void ValidateOdometryError(const OdometryErrorOptions& options);

class OdometryError {
 public:
  OdometryError(const OdometryErrorOptions& options, unsigned seed);

  // The drive's odometry after a step; returns the erroneous one.
  void Update(const Pose2& drive_pose, const Twist2& drive_twist);
  const Pose2& pose() const { return pose_; }
  const Twist2& twist() const { return twist_; }
  // The drive's odometry was zeroed: start again from zero (the random stream goes on).
  void Reset();

 private:
  OdometryErrorOptions o_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Pose2 last_drive_;
  Pose2 pose_;
  Twist2 twist_;
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_ODOMETRY_ERROR_H_
