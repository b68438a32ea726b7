#include "minibot3d_navigation/amcl/kld_sampling.h"

#include <algorithm>
#include <cmath>

namespace minibot3d_navigation {
namespace amcl {
namespace {

constexpr int kXYBits = 21;
constexpr int64_t kXYOffset = int64_t{1} << (kXYBits - 1);
constexpr uint64_t kXYMask = (uint64_t{1} << kXYBits) - 1;

int64_t ClampBin(double v) {
  // Clamp in floating point first: a far-off (or NaN) pose must not overflow.
  if (!(v > -static_cast<double>(kXYOffset))) return -kXYOffset;
  if (v > static_cast<double>(kXYOffset - 1)) return kXYOffset - 1;
  return static_cast<int64_t>(v);
}

}  // namespace

PoseBin BinOfPose(const Pose2& pose) {
  PoseBin b;
  b.ix = static_cast<int>(ClampBin(std::floor(pose.x / kBinSizeXY)));
  b.iy = static_cast<int>(ClampBin(std::floor(pose.y / kBinSizeXY)));
  int a = static_cast<int>(
      std::floor((NormalizeAngle(pose.yaw) + kPi) / kBinSizeYaw));
  if (a < 0 || a >= kYawBins) a = ((a % kYawBins) + kYawBins) % kYawBins;
  b.iyaw = a;
  return b;
}

uint64_t BinKey(const PoseBin& bin) {
  const uint64_t x = static_cast<uint64_t>(bin.ix + kXYOffset) & kXYMask;
  const uint64_t y = static_cast<uint64_t>(bin.iy + kXYOffset) & kXYMask;
  return (x << (kXYBits + 6)) | (y << 6) | static_cast<uint64_t>(bin.iyaw);
}

PoseBin BinFromKey(uint64_t key) {
  PoseBin b;
  b.iyaw = static_cast<int>(key & 63u);
  b.iy = static_cast<int>(static_cast<int64_t>((key >> 6) & kXYMask) -
                          kXYOffset);
  b.ix = static_cast<int>(
      static_cast<int64_t>((key >> (kXYBits + 6)) & kXYMask) - kXYOffset);
  return b;
}

int CountOccupiedBins(const std::vector<Particle>& particles,
                      std::vector<uint64_t>* scratch) {
  scratch->resize(particles.size());
  for (size_t k = 0; k < particles.size(); ++k) {
    (*scratch)[k] = BinKey(BinOfPose(particles[k].pose));
  }
  std::sort(scratch->begin(), scratch->end());
  return static_cast<int>(std::unique(scratch->begin(), scratch->end()) -
                          scratch->begin());
}

int KldSampleCount(int k, double kld_err, double kld_z, int min_particles,
                   int max_particles) {
  double n = 0.0;
  if (k > 1) {
    const double km1 = k - 1;
    const double b = 2.0 / (9.0 * km1);
    const double x = 1.0 - b + std::sqrt(b) * kld_z;
    n = std::ceil(km1 / (2.0 * kld_err) * x * x * x);
  }
  if (!(n >= min_particles)) return min_particles;  // also NaN
  if (n >= max_particles) return max_particles;
  return static_cast<int>(n);
}

}  // namespace amcl
}  // namespace minibot3d_navigation
