// KLD-sampling: how many particles the filter needs (Fox, "KLD-sampling:
// Adaptive particle filters", NIPS 2001 / IJRR 2003).
//
// The posterior is approximated by a histogram over pose space; if the
// particles occupy k bins, then with probability 1 - delta the K-L divergence
// between the sample-based maximum-likelihood estimate and the true
// (histogram) posterior stays below epsilon (kld_err) when
//   n >= (k-1)/(2 eps) * (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) * z_{1-delta})^3
// (Wilson-Hilferty approximation of the chi-square quantile).  z_{1-delta} is
// kld_z, used directly as the normal quantile exactly as ROS amcl does.
// Bins are 0.5 m x 0.5 m x 10 deg like amcl's kd-tree; the same bins drive the
// pose clustering (pose_clusters.h).
#ifndef MINIBOT3D_NAVIGATION_AMCL_KLD_SAMPLING_H_
#define MINIBOT3D_NAVIGATION_AMCL_KLD_SAMPLING_H_

#include <cstdint>
#include <vector>

#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace amcl {

constexpr double kBinSizeXY = 0.5;                 // metres
constexpr double kBinSizeYaw = 10.0 * kPi / 180.0;  // radians
constexpr int kYawBins = 36;                       // 360 deg / 10 deg

struct PoseBin {
  int ix;
  int iy;
  int iyaw;  // 0..kYawBins-1 (yaw in [-pi, pi) -> bins wrap around)
};

PoseBin BinOfPose(const Pose2& pose);

// A unique 64-bit key for a bin (for sorting / hashing).  ix and iy are
// clamped to +-2^20 bins (+-524 km), far beyond any map.
uint64_t BinKey(const PoseBin& bin);
PoseBin BinFromKey(uint64_t key);

// Number of distinct bins occupied by the particle poses (weights ignored).
// *scratch is reused storage so the filter does not allocate per resampling.
int CountOccupiedBins(const std::vector<Particle>& particles,
                      std::vector<uint64_t>* scratch);

// Fox's bound for k occupied bins, clamped to [min_particles, max_particles].
// For k <= 1 the bound is 0 (a single bin is represented exactly by any
// sample), so min_particles is returned; ROS amcl returns max_particles
// there, which only matters for a filter collapsed into one 0.5 m bin.
int KldSampleCount(int k, double kld_err, double kld_z, int min_particles,
                   int max_particles);

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_KLD_SAMPLING_H_
