// Low-variance (systematic) resampling, the resampling step of the RBPF of Grisetti, Stachniss &
// Burgard (IEEE T-RO 2007); see Thrun, Burgard & Fox, "Probabilistic Robotics", table 4.4.
// N pointers spaced 1/N apart from one random offset u0 ∈ [0, 1/N) walk the cumulative weights:
// a particle with weight w is drawn ⌊N·w⌋ or ⌈N·w⌉ times, with less variance than independent draws.
#ifndef MINIBOT3D_SLAM_SRC_RESAMPLING_H_
#define MINIBOT3D_SLAM_SRC_RESAMPLING_H_

#include <cstddef>
#include <vector>

namespace minibot3d_slam {

// `weights` are normalised (sum 1). Returns the index of the parent of each new particle, in
// increasing order.
inline std::vector<std::size_t> LowVarianceResample(const std::vector<double>& weights, double u0) {
  const std::size_t n = weights.size();
  std::vector<std::size_t> parents;
  if (n == 0) return parents;
  parents.reserve(n);
  double cumulative = weights[0];
  std::size_t i = 0;
  for (std::size_t m = 0; m < n; ++m) {
    const double target = u0 + static_cast<double>(m) / static_cast<double>(n);
    while (target > cumulative && i + 1 < n) cumulative += weights[++i];
    parents.push_back(i);
  }
  return parents;
}

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_SRC_RESAMPLING_H_
