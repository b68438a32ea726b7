// Odometry motion model of the RBPF (Grisetti, Stachniss & Burgard, IEEE T-RO 2007; the sampling
// form of the odometry model in Thrun, Burgard & Fox, "Probabilistic Robotics", ch. 5).
//
// The odometry increment u = (dx, dy, dθ), expressed in the frame of the previous odometry pose, is
// perturbed with zero-mean Gaussian noise whose standard deviation grows with the motion, using the
// four gmapping parameters with their documented meaning:
//   σ_x = srr·|dx| + 0.3·srr·|dy| + srt·|dθ|     (translation error from translation and rotation)
//   σ_y = srr·|dy| + 0.3·srr·|dx| + srt·|dθ|     (the 0.3·srr lateral slip term is gmapping's)
//   σ_θ = str·√(dx²+dy²) + stt·|dθ|              (rotation error from translation and rotation)
// and the perturbed increment is composed onto the particle's pose. As in gmapping, the model is
// applied to every incoming odometry increment, so the particles' spread accumulates between the
// scans that are processed.
#ifndef MINIBOT3D_SLAM_SRC_MOTION_MODEL_H_
#define MINIBOT3D_SLAM_SRC_MOTION_MODEL_H_

#include <random>

#include "minibot3d_slam/gmapping_options.h"
#include "minibot3d_slam/types.h"

namespace minibot3d_slam {

class MotionModel {
 public:
  explicit MotionModel(const GmappingOptions& options)
      : srr_(options.srr), srt_(options.srt), str_(options.str), stt_(options.stt) {}

  // Draws the pose after the odometry moved from odom_old to odom_new, starting from `pose`.
  Pose2 Sample(const Pose2& pose, const Pose2& odom_old, const Pose2& odom_new,
               std::mt19937_64* rng) const;

 private:
  double srr_, srt_, str_, stt_;
};

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_SRC_MOTION_MODEL_H_
