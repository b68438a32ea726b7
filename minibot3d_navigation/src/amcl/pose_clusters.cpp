#include "minibot3d_navigation/amcl/pose_clusters.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "minibot3d_navigation/amcl/kld_sampling.h"

namespace minibot3d_navigation {
namespace amcl {
namespace {

// Union-find over occupied bins, with path halving.
int Find(std::vector<int>* parent, int a) {
  while ((*parent)[a] != a) {
    (*parent)[a] = (*parent)[(*parent)[a]];
    a = (*parent)[a];
  }
  return a;
}

// Per-particle weights that are safe to average with.
std::vector<double> UsableWeights(const std::vector<Particle>& particles) {
  std::vector<double> w(particles.size());
  double total = 0.0;
  for (size_t k = 0; k < particles.size(); ++k) {
    const double v = particles[k].weight;
    w[k] = (std::isfinite(v) && v > 0.0) ? v : 0.0;
    total += w[k];
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    std::fill(w.begin(), w.end(), 1.0);
    total = static_cast<double>(w.size());
  }
  for (double& v : w) v /= total;
  return w;
}

// Weighted first moments of a group of particles (yaw as a unit vector).
struct Moments {
  double w = 0.0, injected = 0.0, x = 0.0, y = 0.0, c = 0.0, s = 0.0;
  int count = 0;
};

PoseCluster Finish(const Moments& m) {
  PoseCluster pc;
  pc.weight = m.w;
  pc.injected_weight = m.injected;
  pc.particle_count = m.count;
  if (m.w > 0.0) {
    pc.mean.x = m.x / m.w;
    pc.mean.y = m.y / m.w;
  }
  pc.mean.yaw = NormalizeAngle(std::atan2(m.s, m.c));
  return pc;
}

}  // namespace

std::vector<PoseCluster> ClusterParticles(
    const std::vector<Particle>& particles) {
  std::vector<PoseCluster> result;
  if (particles.empty()) return result;
  const std::vector<double> w = UsableWeights(particles);

  // Occupied bins and each particle's bin id.
  std::unordered_map<uint64_t, int> bin_ids;
  bin_ids.reserve(particles.size() * 2);
  std::vector<PoseBin> bins;
  std::vector<int> particle_bin(particles.size());
  for (size_t k = 0; k < particles.size(); ++k) {
    const PoseBin b = BinOfPose(particles[k].pose);
    auto it = bin_ids.emplace(BinKey(b), static_cast<int>(bins.size()));
    if (it.second) bins.push_back(b);
    particle_bin[k] = it.first->second;
  }

  // Connect touching bins.
  std::vector<int> parent(bins.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t b = 0; b < bins.size(); ++b) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int da = -1; da <= 1; ++da) {
          if (dx == 0 && dy == 0 && da == 0) continue;
          PoseBin n = bins[b];
          n.ix += dx;
          n.iy += dy;
          n.iyaw = (n.iyaw + da + kYawBins) % kYawBins;
          auto it = bin_ids.find(BinKey(n));
          if (it == bin_ids.end()) continue;
          const int ra = Find(&parent, static_cast<int>(b));
          const int rb = Find(&parent, it->second);
          if (ra != rb) parent[ra] = rb;
        }
      }
    }
  }

  // Dense cluster labels.
  std::vector<int> root_label(bins.size(), -1);
  std::vector<int> label(particles.size());
  int num_clusters = 0;
  for (size_t k = 0; k < particles.size(); ++k) {
    const int r = Find(&parent, particle_bin[k]);
    if (root_label[r] < 0) root_label[r] = num_clusters++;
    label[k] = root_label[r];
  }

  std::vector<Moments> m(num_clusters);
  for (size_t k = 0; k < particles.size(); ++k) {
    Moments& c = m[label[k]];
    const Pose2& p = particles[k].pose;
    c.w += w[k];
    if (particles[k].injected) c.injected += w[k];
    c.x += w[k] * p.x;
    c.y += w[k] * p.y;
    c.c += w[k] * std::cos(p.yaw);
    c.s += w[k] * std::sin(p.yaw);
    ++c.count;
  }
  result.reserve(num_clusters);
  for (const Moments& c : m) result.push_back(Finish(c));
  for (size_t k = 0; k < particles.size(); ++k) {
    PoseCluster& c = result[label[k]];
    const Pose2& p = particles[k].pose;
    const Eigen::Vector3d d(p.x - c.mean.x, p.y - c.mean.y,
                            AngleDiff(p.yaw, c.mean.yaw));
    c.covariance += w[k] * d * d.transpose();
  }
  for (PoseCluster& c : result) {
    if (c.weight > 0.0) c.covariance /= c.weight;
  }
  std::stable_sort(result.begin(), result.end(),
                   [](const PoseCluster& a, const PoseCluster& b) {
                     return a.weight > b.weight;
                   });
  return result;
}

PoseCluster WholeSetStatistics(const std::vector<Particle>& particles) {
  if (particles.empty()) return PoseCluster();
  const std::vector<double> w = UsableWeights(particles);
  Moments m;
  for (size_t k = 0; k < particles.size(); ++k) {
    const Pose2& p = particles[k].pose;
    m.w += w[k];
    m.x += w[k] * p.x;
    m.y += w[k] * p.y;
    m.c += w[k] * std::cos(p.yaw);
    m.s += w[k] * std::sin(p.yaw);
    ++m.count;
  }
  PoseCluster pc = Finish(m);
  for (size_t k = 0; k < particles.size(); ++k) {
    const Pose2& p = particles[k].pose;
    const Eigen::Vector3d d(p.x - pc.mean.x, p.y - pc.mean.y,
                            AngleDiff(p.yaw, pc.mean.yaw));
    pc.covariance += w[k] * d * d.transpose();
  }
  if (pc.weight > 0.0) pc.covariance /= pc.weight;
  return pc;
}

}  // namespace amcl
}  // namespace minibot3d_navigation
