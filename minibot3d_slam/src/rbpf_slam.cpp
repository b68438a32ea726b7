// Grid-based Rao-Blackwellized particle filter SLAM after Grisetti, Stachniss & Burgard, "Improved
// techniques for grid mapping with Rao-Blackwellized particle filters" (IEEE T-RO 2007) — the
// algorithm of OpenSLAM/ROS gmapping.
//
// Each particle carries a pose, a log-weight, its own occupancy grid and its trajectory. Per scan:
//   1. Motion: every odometry increment moves every particle through the sampling odometry model
//      (motion_model.h), also for scans that are not processed, so the spread accumulates.
//   2. A scan is processed when the odometry has travelled linearUpdate (path length) or turned
//      angularUpdate since the last processed scan, when temporalUpdate seconds passed (if ≥ 0), or
//      when it is the first scan (which only initialises the maps).
//   3. Scan matching, per particle, as gmapping's code does it: the scan is matched against the
//      particle's own map by hill climbing from the particle's predicted pose and (subcellMatch)
//      refined to sub-cell precision; when the match score exceeds minimumScore the particle moves
//      to the matched pose, else it keeps the prediction, and its weight is multiplied by the scan
//      likelihood at that pose. After a turn whose match from the prediction is poor, the climb
//      also starts from the prediction turned back by turnSlip of the odometry's turn (wheels
//      slipping in a turn in place make odometry count several times the rotation) and keeps
//      that match when it scores clearly higher. The motion model's spread and the matcher's
//      basin of attraction make this a proposal centred on the match. With sampleProposal = 1 the paper's form is used
//      instead: the likelihood is sampled on a small grid around the match, a Gaussian is fitted
//      to it and the new pose drawn from it, weighted by the mean likelihood of the grid (η). On
//      the Intel log the draw adds up to a centimetre of noise to every pose and the map, and
//      scores 0.0461 m against 0.0444 m for the matched pose (5 seeds, without refinement).
//   4. The scan is integrated into each particle's map at its new pose (ray-traced free space).
//   5. Adaptive resampling: weights are normalised as gmapping does, w ∝ exp((log w - max) /
//      (ogain·N)) — the ogain smoothing keeps the very peaked beam likelihoods from collapsing the
//      filter — and the particles are resampled (low-variance / systematic) only when
//      N_eff = 1 / Σ w² drops below resampleThreshold · N; the weights are then reset.
// Memory: the maps share copy-on-write tiles (grid.h), so resampling copies pointer tables, not
// cells; trajectories are nodes of a tree shared by the particles (each particle points to its
// newest node, nodes point to their parents), so copying a particle copies one pointer and the best
// trajectory is a walk up the tree.
// The best particle is the one with the largest accumulated log-likelihood (gmapping's weightSum).
//   6. Loop closure (loopClosure = 1, loop_closer.h): the processed scan becomes a node of a pose
//      graph of the best particle's trajectory and is searched for in older submaps; when the graph
//      is optimised, the map is rebuilt from the corrected trajectory and every particle is reset
//      onto it (loop_closer.h says why a reset and not a common rigid shift).
#include "minibot3d_slam/rbpf_slam.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <unordered_set>

#include "grid.h"
#include "loop_closer.h"
#include "motion_model.h"
#include "parallel_for.h"
#include "resampling.h"
#include "scan_matcher.h"

namespace minibot3d_slam {

namespace {

// turnSlip: the climb from the prediction turned back wins only with a score this much higher
// (as a fraction), so that where the map allows two headings (a round pillar, a symmetric hall)
// the odometry's keeps the benefit of the doubt.
constexpr double kSlipMargin = 0.1;
// ... and is tried only when the match from the prediction is poor: a score below this share of
// the matched beams (a beam on its mean endpoint scores 1).
constexpr double kSlipPoorMatch = 0.5;

// Localize: passes of the sub-cell refinement for the position (each moves at most a cell).
constexpr int kLocalizeRefinePasses = 5;

// A node of the trajectory tree.
struct TrajectoryNode {
  StampedPose stamped;
  std::shared_ptr<TrajectoryNode> parent;

  TrajectoryNode(const StampedPose& s, std::shared_ptr<TrajectoryNode> p)
      : stamped(s), parent(std::move(p)) {}
  // Releases a long chain of ancestors iteratively: the default destructor would recurse once per
  // ancestor and could exhaust the stack on long runs.
  ~TrajectoryNode() {
    std::shared_ptr<TrajectoryNode> p = std::move(parent);
    while (p && p.use_count() == 1) {
      std::shared_ptr<TrajectoryNode> next = std::move(p->parent);
      p = std::move(next);
    }
  }
  TrajectoryNode(const TrajectoryNode&) = delete;
  TrajectoryNode& operator=(const TrajectoryNode&) = delete;
};

struct Particle {
  Pose2 pose;               // current pose (moved by the motion model at every scan)
  double weight = 0.0;      // log-weight since the last resampling
  double weight_sum = 0.0;  // accumulated log-likelihood over the whole run
  Grid grid;
  std::shared_ptr<TrajectoryNode> node;  // pose at the last processed scan

  explicit Particle(double resolution) : grid(resolution) {}
};

// Draws from N(mean, cov) through the eigen-decomposition (cov may be singular).
Pose2 SampleGaussian(const Pose2& mean, const Eigen::Matrix3d& cov, std::mt19937_64* rng) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::Vector3d z(unit(*rng), unit(*rng), unit(*rng));
  const Eigen::Vector3d sd = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  const Eigen::Vector3d d = eig.eigenvectors() * sd.cwiseProduct(z);
  return Pose2{mean.x + d.x(), mean.y + d.y(), NormalizeAngle(mean.yaw + d.z())};
}

}  // namespace

class RbpfSlam::Impl {
 public:
  explicit Impl(const GmappingOptions& options)
      : options_((ValidateOptions(options), options)),
        matcher_(options),
        motion_(options),
        rng_(options.seed),
        threads_(ResolveThreads(options.threads)) {
    if (options_.loopClosure != 0) loop_ = std::make_unique<LoopCloser>(options_, &matcher_);
  }

  bool AddScan(const LaserScan& scan, const Pose2& odom);
  Pose2 BestPose() const;
  GridMap Map() const;
  std::vector<StampedPose> BestTrajectory() const;
  double Entropy() const;
  std::vector<double> NormalizedWeights() const;
  int BestIndex() const;

  GmappingOptions options_;
  ScanMatcher matcher_;
  MotionModel motion_;
  std::mt19937_64 rng_;
  int threads_;  // for the per-particle matching (options_.threads resolved)
  std::vector<Particle> particles_;
  bool initialized_ = false;
  Pose2 last_odom_;            // odometry at the last scan given
  Pose2 processed_odom_;       // odometry at the last processed scan
  double processed_time_ = 0.0;
  double linear_ = 0.0, angular_ = 0.0;  // motion since the last processed scan
  int processed_ = 0;
  int resamples_ = 0;
  std::unique_ptr<LoopCloser> loop_;
  int closures_ = 0;

  // Optimises the pose graph and, when the correction is large enough, rebuilds the map and resets
  // the particles onto the corrected trajectory (`stamped`, `poses`: the best trajectory now).
  void OptimizeAndApply(const std::vector<StampedPose>& stamped, const std::vector<Pose2>& poses);
  void FinishLoops() {
    if (!loop_ || loop_->constraints().empty()) return;
    std::vector<StampedPose> stamped = BestTrajectory();
    std::vector<Pose2> poses(stamped.size());
    for (std::size_t i = 0; i < stamped.size(); ++i) poses[i] = stamped[i].pose;
    OptimizeAndApply(stamped, poses);
  }

 private:
  void CloseLoops(const PreparedScan& scan);
  void Process(const LaserScan& scan);
  void Resample(const std::vector<double>& weights);
};

bool RbpfSlam::Impl::AddScan(const LaserScan& scan, const Pose2& odom) {
  if (scan.ranges.size() != scan.angles.size()) {
    throw std::invalid_argument("RbpfSlam::AddScan: scan has " + std::to_string(scan.ranges.size()) +
                                " ranges but " + std::to_string(scan.angles.size()) + " angles");
  }
  if (!initialized_) {
    initialized_ = true;
    // The map frame starts at the first odometry pose (as ROS gmapping), and all particles share
    // the first scan's map.
    Particle first(options_.delta);
    first.pose = odom;
    const PreparedScan prepared = matcher_.Prepare(scan);
    matcher_.Register(prepared, odom, &first.grid);
    if (loop_) loop_->AddNode(prepared);
    first.node = std::make_shared<TrajectoryNode>(StampedPose{scan.time, odom}, nullptr);
    particles_.assign(static_cast<std::size_t>(options_.particles), first);
    last_odom_ = processed_odom_ = odom;
    processed_time_ = scan.time;
    processed_ = 1;
    return true;
  }
  for (Particle& p : particles_) p.pose = motion_.Sample(p.pose, last_odom_, odom, &rng_);
  const Pose2 u = Between(last_odom_, odom);
  linear_ += std::hypot(u.x, u.y);
  angular_ += std::fabs(u.yaw);
  last_odom_ = odom;
  const bool came_to_rest = options_.stopUpdate && (linear_ >= 0.02 || angular_ >= 0.02) &&
                            std::hypot(u.x, u.y) < 1e-3 && std::fabs(u.yaw) < 1e-3;
  const bool due = linear_ >= options_.linearUpdate || angular_ >= options_.angularUpdate ||
                   came_to_rest ||
                   (options_.temporalUpdate >= 0.0 && scan.time - processed_time_ > options_.temporalUpdate);
  if (!due) return false;
  Process(scan);
  linear_ = angular_ = 0.0;
  processed_odom_ = odom;
  processed_time_ = scan.time;
  ++processed_;
  return true;
}

void RbpfSlam::Impl::Process(const LaserScan& scan) {
  const PreparedScan prepared = matcher_.Prepare(scan);
  // Each particle's match reads only its own map and writes only its own slot, so the particles
  // are matched on `threads` threads; the proposal's random draws follow in particle order, so
  // the result does not depend on the thread count.
  struct Match {
    bool trusted = false;
    Pose2 pose;             // the refined match (trusted), else the odometry prediction
    double log_likelihood = 0.0;
    ProposalFit fit;        // sampleProposal = 1 and trusted
  };
  std::vector<Match> matches(particles_.size());
  // Wheel slip in turns (turnSlip): a second start for the climb, the prediction turned back by a
  // share of the odometry's turn since the last processed scan.
  const double slip_turn =
      options_.turnSlip * minibot3d_common::AngleDiff(last_odom_.yaw, processed_odom_.yaw);
  const double slip = std::fabs(slip_turn);
  ParallelFor(particles_.size(), threads_, [&](std::size_t i) {
    const Particle& p = particles_[i];
    Match& m = matches[i];
    Pose2 mode;
    double score = matcher_.Optimize(p.grid, prepared, p.pose, &mode);
    const double beams = static_cast<double>(prepared.match_range.size());
    if (slip > options_.astep && score < kSlipPoorMatch * beams) {
      // Climbed only when it starts better than the prediction did (one score each), so a poor
      // match after a turn without slip costs two evaluations, not a second climb.
      Pose2 start = p.pose, other;
      start.yaw = NormalizeAngle(start.yaw - slip_turn);
      if (matcher_.Score(p.grid, prepared, start) > matcher_.Score(p.grid, prepared, p.pose)) {
        const double s = matcher_.Optimize(p.grid, prepared, start, &other);
        if (s > score * (1.0 + kSlipMargin)) {
          score = s;
          mode = other;
        }
      }
    }
    if (score <= options_.minimumScore) {
      // The match is not trusted: keep the odometry prediction.
      m.pose = p.pose;
      m.log_likelihood = matcher_.LogLikelihood(p.grid, prepared, p.pose);
      return;
    }
    m.trusted = true;
    m.pose = options_.subcellMatch != 0 ? matcher_.Refine(p.grid, prepared, mode) : mode;
    if (options_.sampleProposal != 0) {
      m.fit = matcher_.SampleAround(p.grid, prepared, m.pose);
      m.log_likelihood = m.fit.log_weight;
    } else {
      m.log_likelihood = matcher_.LogLikelihood(p.grid, prepared, m.pose);
    }
  });
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    Particle& p = particles_[i];
    const Match& m = matches[i];
    p.pose = m.trusted && options_.sampleProposal != 0 ? SampleGaussian(m.fit.mean, m.fit.covariance, &rng_)
                                                       : m.pose;
    p.weight += m.log_likelihood;
    p.weight_sum += m.log_likelihood;
  }
  // Integrate the scan before resampling: copies of a particle then share the freshly written
  // tiles instead of each writing (and owning) an identical copy.
  for (Particle& p : particles_) {
    matcher_.Register(prepared, p.pose, &p.grid);
    p.node = std::make_shared<TrajectoryNode>(StampedPose{scan.time, p.pose}, std::move(p.node));
  }
  const std::vector<double> w = NormalizedWeights();
  double sum_sq = 0.0;
  for (double x : w) sum_sq += x * x;
  const double neff = 1.0 / sum_sq;
  if (neff < options_.resampleThreshold * static_cast<double>(particles_.size())) Resample(w);
  if (loop_) CloseLoops(prepared);
}

void RbpfSlam::Impl::CloseLoops(const PreparedScan& scan) {
  loop_->AddNode(scan);
  std::vector<StampedPose> stamped = BestTrajectory();
  std::vector<Pose2> poses(stamped.size());
  for (std::size_t i = 0; i < stamped.size(); ++i) poses[i] = stamped[i].pose;
  if (!loop_->Detect(poses)) return;
  OptimizeAndApply(stamped, poses);
}

void RbpfSlam::Impl::OptimizeAndApply(const std::vector<StampedPose>& stamped, const std::vector<Pose2>& poses) {
  const std::vector<Pose2> corrected = loop_->Optimize(poses);
  // A correction smaller than the filter's own precision is left out: resetting the particles
  // costs the filter its diversity and a map rebuild, and moves nodes by the constraints'
  // centimetre noise (on the Intel log, where the filter alone stays consistent, applying every
  // optimisation made the relations error worse). The constraints stay in the graph.
  // Judged at the newest node: that is where the filter goes on mapping, and where a closed loop
  // moves the estimate most; a deformation far back in the graph alone (a few constraints pulling
  // one old node) is no reason to reset the filter.
  const double shift = std::hypot(poses.back().x - corrected.back().x, poses.back().y - corrected.back().y);
  const double turn = std::fabs(NormalizeAngle(poses.back().yaw - corrected.back().yaw));
  if (shift < LoopCloser::kApplyShift && turn < LoopCloser::kApplyTurn) return;
  // Reset every particle onto the corrected trajectory and its map (loop_closer.h: why).
  const Particle& best = particles_[static_cast<std::size_t>(BestIndex())];
  Particle reset(options_.delta);
  reset.weight = 0.0;
  reset.weight_sum = best.weight_sum;
  loop_->RenderMap(corrected, &reset.grid);
  std::shared_ptr<TrajectoryNode> node;
  for (std::size_t i = 0; i < corrected.size(); ++i) {
    node = std::make_shared<TrajectoryNode>(StampedPose{stamped[i].time, corrected[i]}, std::move(node));
  }
  reset.node = std::move(node);
  reset.pose = corrected.back();
  particles_.assign(particles_.size(), reset);
  ++closures_;
}

void RbpfSlam::Impl::Resample(const std::vector<double>& weights) {
  const std::size_t n = particles_.size();
  std::uniform_real_distribution<double> uniform(0.0, 1.0 / static_cast<double>(n));
  std::vector<Particle> next;
  next.reserve(n);
  for (std::size_t parent : LowVarianceResample(weights, uniform(rng_))) {
    next.push_back(particles_[parent]);  // shares tiles and trajectory with its parent
    next.back().weight = 0.0;
  }
  particles_ = std::move(next);
  ++resamples_;
}

std::vector<double> RbpfSlam::Impl::NormalizedWeights() const {
  const double gain = 1.0 / (options_.ogain * static_cast<double>(particles_.size()));
  double lmax = -std::numeric_limits<double>::infinity();
  for (const Particle& p : particles_) lmax = std::max(lmax, p.weight);
  std::vector<double> w(particles_.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    w[i] = std::exp(gain * (particles_[i].weight - lmax));
    sum += w[i];
  }
  for (double& x : w) x /= sum;
  return w;
}

int RbpfSlam::Impl::BestIndex() const {
  int best = 0;
  for (std::size_t i = 1; i < particles_.size(); ++i) {
    if (particles_[i].weight_sum > particles_[static_cast<std::size_t>(best)].weight_sum) {
      best = static_cast<int>(i);
    }
  }
  return best;
}

Pose2 RbpfSlam::Impl::BestPose() const {
  if (!initialized_) return Pose2{};
  const Particle& best = particles_[static_cast<std::size_t>(BestIndex())];
  // Deterministic between processed scans: the processed pose moved by the odometry increment.
  return Compose(best.node->stamped.pose, Between(processed_odom_, last_odom_));
}

GridMap RbpfSlam::Impl::Map() const {
  GridMap map;
  map.resolution = options_.delta;
  const double inv = 1.0 / options_.delta;
  int ix0 = static_cast<int>(std::floor(options_.xmin * inv + 1e-9));
  int iy0 = static_cast<int>(std::floor(options_.ymin * inv + 1e-9));
  int ix1 = static_cast<int>(std::ceil(options_.xmax * inv - 1e-9)) - 1;
  int iy1 = static_cast<int>(std::ceil(options_.ymax * inv - 1e-9)) - 1;
  if (initialized_) {
    const Grid& grid = particles_[static_cast<std::size_t>(BestIndex())].grid;
    int ax0, ay0, ax1, ay1;
    if (grid.AllocatedBounds(&ax0, &ay0, &ax1, &ay1)) {
      ix0 = std::min(ix0, ax0);
      iy0 = std::min(iy0, ay0);
      ix1 = std::max(ix1, ax1);
      iy1 = std::max(iy1, ay1);
    }
  }
  map.origin_x = ix0 * options_.delta;
  map.origin_y = iy0 * options_.delta;
  map.width = ix1 - ix0 + 1;
  map.height = iy1 - iy0 + 1;
  map.data.assign(static_cast<std::size_t>(map.width) * map.height, -1);
  if (!initialized_) return map;
  const Grid& grid = particles_[static_cast<std::size_t>(BestIndex())].grid;
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const GridCell& c = grid.At(ix0 + x, iy0 + y);
      if (c.visits == 0) continue;
      const double occupancy = static_cast<double>(c.hits) / c.visits;
      map.data[static_cast<std::size_t>(y) * map.width + x] = occupancy > options_.occ_thresh ? 100 : 0;
    }
  }
  return map;
}

std::vector<StampedPose> RbpfSlam::Impl::BestTrajectory() const {
  std::vector<StampedPose> out;
  if (!initialized_) return out;
  for (const TrajectoryNode* n = particles_[static_cast<std::size_t>(BestIndex())].node.get();
       n != nullptr; n = n->parent.get()) {
    out.push_back(n->stamped);
  }
  std::reverse(out.begin(), out.end());
  return out;
}

double RbpfSlam::Impl::Entropy() const {
  if (!initialized_) return 0.0;
  double h = 0.0;
  for (double w : NormalizedWeights()) {
    if (w > 0.0) h -= w * std::log(w);
  }
  return h;
}

RbpfSlam::RbpfSlam(const GmappingOptions& options) : impl_(std::make_unique<Impl>(options)) {}
RbpfSlam::~RbpfSlam() = default;
bool RbpfSlam::AddScan(const LaserScan& scan, const Pose2& odom) { return impl_->AddScan(scan, odom); }
Pose2 RbpfSlam::BestPose() const { return impl_->BestPose(); }
Pose2 RbpfSlam::MapToOdom() const {
  // map→odom T satisfies T ⊕ odom = best pose, so T = best ⊕ odom⁻¹.
  const Pose2 odom_inverse = Between(impl_->last_odom_, Pose2{});
  return Compose(impl_->BestPose(), odom_inverse);
}
GridMap RbpfSlam::Map() const { return impl_->Map(); }
std::vector<StampedPose> RbpfSlam::BestTrajectory() const { return impl_->BestTrajectory(); }
double RbpfSlam::Entropy() const { return impl_->Entropy(); }
int RbpfSlam::processed_scans() const { return impl_->processed_; }
int RbpfSlam::resamples() const { return impl_->resamples_; }
Pose2 RbpfSlam::Localize(const LaserScan& scan, const Pose2& guess) const {
  if (!impl_->initialized_) return guess;
  const Grid& grid = impl_->particles_[static_cast<std::size_t>(impl_->BestIndex())].grid;
  const PreparedScan prepared = impl_->matcher_.Prepare(scan);
  Pose2 mode;
  const double score = impl_->matcher_.Optimize(grid, prepared, guess, &mode);
  if (score <= impl_->options_.minimumScore) return guess;
  if (impl_->options_.subcellMatch == 0) return mode;  // the climber's pose as is
  mode = impl_->matcher_.Refine(grid, prepared, mode);
  // The position: from the guess's, at the climb's heading, by the refinement alone — a few
  // passes, each bounded to a cell (Refine returns its input when a pass would go further, i.e.
  // when the problem is degenerate there).
  Pose2 pose{guess.x, guess.y, mode.yaw};
  for (int pass = 0; pass < kLocalizeRefinePasses; ++pass) {
    const Pose2 next = impl_->matcher_.Refine(grid, prepared, pose);
    if (std::hypot(next.x - pose.x, next.y - pose.y) < 1e-6 && std::fabs(next.yaw - pose.yaw) < 1e-7) break;
    pose = next;
  }
  return pose;
}
void RbpfSlam::FinishLoops() { impl_->FinishLoops(); }
std::size_t RbpfSlam::MapMemoryBytes() const {
  std::unordered_set<const void*> tiles;
  for (const Particle& p : impl_->particles_) {
    p.grid.ForEachTile([&](const Grid::Tile* t) { tiles.insert(t); });
  }
  return tiles.size() * sizeof(Grid::Tile);
}
std::size_t RbpfSlam::TrajectoryBytes() const {
  std::unordered_set<const TrajectoryNode*> nodes;
  for (const Particle& p : impl_->particles_) {
    // Stop at the first node already counted: its ancestors are counted too.
    for (const TrajectoryNode* n = p.node.get(); n != nullptr && nodes.insert(n).second; n = n->parent.get()) {
    }
  }
  // make_shared puts the node and its control block (two counters, a vtable) in one allocation.
  constexpr std::size_t kControlBlock = 2 * sizeof(long) + sizeof(void*);
  return nodes.size() * (sizeof(TrajectoryNode) + kControlBlock);
}
std::size_t RbpfSlam::LoopScanBytes() const { return impl_->loop_ ? impl_->loop_->ScanBytes() : 0; }
int RbpfSlam::loop_closures() const { return impl_->closures_; }
int RbpfSlam::loop_constraints() const {
  return impl_->loop_ ? static_cast<int>(impl_->loop_->constraints().size()) : 0;
}
const GmappingOptions& RbpfSlam::options() const { return impl_->options_; }

}  // namespace minibot3d_slam
