// Pose estimate from a particle set: clustering + weighted statistics.
//
// The mean of a multi-modal particle set is meaningless (it can fall between
// two hypotheses, inside a wall), so as ROS amcl does, particles are first
// grouped: occupied KLD histogram bins (kld_sampling.h, 0.5 m x 0.5 m x
// 10 deg) that touch each other (26-neighbourhood, yaw bins wrapping at
// +-pi) form one cluster.  Each cluster gets its total weight, weighted mean
// and 3x3 covariance over (x, y, yaw).  Yaw uses circular statistics: the
// mean is atan2(sum w sin, sum w cos) and deviations are wrapped to [-pi, pi)
// around it, so a cluster straddling +-pi is not averaged to 0.  The pose
// estimate is the heaviest cluster.
#ifndef MINIBOT3D_NAVIGATION_AMCL_POSE_CLUSTERS_H_
#define MINIBOT3D_NAVIGATION_AMCL_POSE_CLUSTERS_H_

#include <vector>

#include <Eigen/Core>

#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace amcl {

struct PoseCluster {
  double weight = 0.0;  // sum of member weights / sum of all weights
  double injected_weight = 0.0;  // the part of `weight` on injected particles
  int particle_count = 0;
  Pose2 mean;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // x, y, yaw
};

// Clusters sorted by decreasing weight (empty for an empty set).  Weights
// that are all zero or not finite are treated as uniform.
std::vector<PoseCluster> ClusterParticles(
    const std::vector<Particle>& particles);

// Weighted mean/covariance of a whole set with the same circular yaw
// statistics (what amcl calls the set covariance).
PoseCluster WholeSetStatistics(const std::vector<Particle>& particles);

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_POSE_CLUSTERS_H_
