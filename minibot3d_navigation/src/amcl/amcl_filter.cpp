#include "minibot3d_navigation/amcl/amcl_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>

#include "minibot3d_navigation/amcl/kld_sampling.h"

namespace minibot3d_navigation {
namespace amcl {
namespace {

// amcl's pf->dist_threshold: the set counts as converged when every particle
// is within this many metres (in x and in y) of the mean.
constexpr double kConvergenceDistance = 0.5;
// Fixed-point iterations of the KLD sample-size search.  The count grows
// monotonically and in practice settles in 2-4 draws; the cap only bounds
// pathological cases (the last count is then used as is).
constexpr int kMaxKldIterations = 8;

std::shared_ptr<const MapModel> BuildMap(const AmclOptions& options,
                                         const OccupancyGrid& grid) {
  ValidateAmclOptions(options);  // option errors before map errors
  return std::make_shared<MapModel>(grid, options.laser_likelihood_max_dist);
}

// log((1 - alpha) e^a + alpha e^b): the exponential filter
// w += alpha (w_avg - w) of augmented MCL, carried out in log space.
double LogMix(double log_a, double log_b, double alpha) {
  if (alpha <= 0.0) return log_a;
  if (alpha >= 1.0) return log_b;
  const double m = std::max(log_a, log_b);
  return m + std::log((1.0 - alpha) * std::exp(log_a - m) +
                      alpha * std::exp(log_b - m));
}

// Least travel (m) that counts as a new view when update_min_d is smaller.
constexpr double kMinViewTravel = 0.01;

// Widest angle between neighbouring beams of the scan, all round: about one
// increment for a laser that sees all round, its blind sector otherwise.
double LargestBeamGap(const LaserScan& scan) {
  std::vector<double> a;
  a.reserve(scan.angles.size());
  for (double b : scan.angles) {
    if (std::isfinite(b)) a.push_back(NormalizeAngle(b));
  }
  if (a.size() < 2) return 2.0 * kPi;
  std::sort(a.begin(), a.end());
  double gap = 2.0 * kPi - (a.back() - a.front());
  for (size_t k = 1; k < a.size(); ++k) gap = std::max(gap, a[k] - a[k - 1]);
  return gap;
}

std::string PoseText(const Pose2& p) {
  std::ostringstream os;
  os << "(x=" << p.x << ", y=" << p.y << ", yaw=" << p.yaw << ")";
  return os.str();
}

void CheckPoseInMap(const Pose2& mean, const MapModel& map, const char* what) {
  if (!IsFinite(mean)) {
    throw std::invalid_argument(std::string(what) + " " + PoseText(mean) +
                                " is not finite");
  }
  int i, j;
  if (!map.WorldToCell(mean.x, mean.y, &i, &j)) {
    // Report the map's extent in world coordinates (its corners' bounding
    // box) so the mistake (wrong frame, wrong units) is easy to spot.
    double min_x = std::numeric_limits<double>::infinity(), max_x = -min_x;
    double min_y = min_x, max_y = -min_x;
    for (int ci = 0; ci < 2; ++ci) {
      for (int cj = 0; cj < 2; ++cj) {
        const Pose2 c = map.GridFrameToWorld(
            {ci * map.width() * map.resolution(),
             cj * map.height() * map.resolution(), 0.0});
        min_x = std::min(min_x, c.x);
        max_x = std::max(max_x, c.x);
        min_y = std::min(min_y, c.y);
        max_y = std::max(max_y, c.y);
      }
    }
    std::ostringstream os;
    os << what << " " << PoseText(mean) << " lies outside the map (x in ["
       << min_x << ", " << max_x << "], y in [" << min_y << ", " << max_y
       << "])";
    throw std::invalid_argument(os.str());
  }
}

// Returns the factor L with L L^T = cov, after checking that cov is a valid
// covariance.
Eigen::Matrix3d CovarianceFactor(const Eigen::Matrix3d& cov) {
  if (!cov.allFinite()) {
    throw std::invalid_argument("initial pose covariance is not finite");
  }
  const double scale = 1.0 + cov.cwiseAbs().maxCoeff();
  if ((cov - cov.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    throw std::invalid_argument("initial pose covariance is not symmetric");
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d lambda = eig.eigenvalues();
  if (lambda.minCoeff() < -1e-9 * scale) {
    std::ostringstream os;
    os << "initial pose covariance is not positive semi-definite "
       << "(smallest eigenvalue " << lambda.minCoeff() << ")";
    throw std::invalid_argument(os.str());
  }
  return eig.eigenvectors() * lambda.cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

}  // namespace

const char* UpdateStatusName(UpdateStatus status) {
  switch (status) {
    case UpdateStatus::kUpdated:
      return "updated";
    case UpdateStatus::kMotionOnly:
      return "motion_only";
    case UpdateStatus::kSkippedNoMotion:
      return "skipped_no_motion";
    case UpdateStatus::kRejectedBadOdometry:
      return "rejected_bad_odometry";
    case UpdateStatus::kRejectedBadScan:
      return "rejected_bad_scan";
  }
  return "unknown";
}

double ExplainedFraction(const MapModel& map, const PreparedScan& scan,
                         const Pose2& pose, double hit_dist, int* beams_used) {
  const Pose2 laser = map.WorldToGridFrame(Compose(pose, scan.sensor_in_base));
  int used = 0, hit = 0;
  for (const PreparedScan::Beam& b : scan.beams) {
    if (b.is_max) continue;
    ++used;
    const double a = laser.yaw + b.bearing;
    const double d = map.DistanceAtGridPoint(laser.x + b.range * std::cos(a),
                                             laser.y + b.range * std::sin(a));
    // An off-map end point reads max_occ_dist: unexplained unless hit_dist
    // is at least that far.
    if (d <= hit_dist) ++hit;
  }
  if (beams_used != nullptr) *beams_used = used;
  return used > 0 ? static_cast<double>(hit) / used : 0.0;
}

Eigen::Matrix3d ScanInformation(const MapModel& map, const PreparedScan& scan,
                                const Pose2& pose, double hit_dist) {
  const Pose2 laser = map.WorldToGridFrame(Compose(pose, scan.sensor_in_base));
  const Pose2 robot = map.WorldToGridFrame(pose);
  const double res = map.resolution();
  // The normal is read two cells in front of the obstacle, towards the
  // laser, where the distance field grows away from the surface (on the
  // obstacle itself a one-cell wall has no gradient).
  const double back = 2.0 * res;
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  int used = 0;
  for (const PreparedScan::Beam& b : scan.beams) {
    if (b.is_max) continue;
    ++used;
    const double a = laser.yaw + b.bearing;
    const double c = std::cos(a), s = std::sin(a);
    const double ex = laser.x + b.range * c, ey = laser.y + b.range * s;
    if (map.DistanceAtGridPoint(ex, ey) > hit_dist) continue;
    const double qx = ex - back * c, qy = ey - back * s;
    const double gx = map.DistanceAtGridPoint(qx + res, qy) -
                      map.DistanceAtGridPoint(qx - res, qy);
    const double gy = map.DistanceAtGridPoint(qx, qy + res) -
                      map.DistanceAtGridPoint(qx, qy - res);
    const double norm = std::hypot(gx, gy);
    // A clean surface gives |gradient| = 2 res; a corner or a thin pillar,
    // where the nearest obstacle changes between the samples, much less.
    if (!(norm > res)) continue;
    Eigen::Vector3d j(gx / norm, gy / norm, 0.0);
    // d(distance)/d(yaw): the end point moves by z x r as the robot turns.
    j(2) = j(0) * -(ey - robot.y) + j(1) * (ex - robot.x);
    info += j * j.transpose();
  }
  if (used == 0) return info;
  // In the grid frame; rotate the translation block to the map frame.
  const double co = std::cos(map.origin().yaw), so = std::sin(map.origin().yaw);
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
  rot.topLeftCorner<2, 2>() << co, -so, so, co;
  return rot * info * rot.transpose() / used;
}

double WeakestTranslationInformation(const Eigen::Matrix3d& information,
                                     Eigen::Vector2d* direction) {
  Eigen::Matrix2d t = information.topLeftCorner<2, 2>();
  if (information(2, 2) > 1e-12) {
    const Eigen::Vector2d cross = information.topRightCorner<2, 1>();
    t -= cross * cross.transpose() / information(2, 2);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(t);
  if (direction != nullptr) *direction = eig.eigenvectors().col(0);
  return std::max(0.0, eig.eigenvalues()(0));
}

AmclFilter::AmclFilter(const AmclOptions& options, const OccupancyGrid& grid,
                       Initialization init, uint64_t seed)
    : AmclFilter(options, BuildMap(options, grid), init, seed) {
  search_ = std::make_shared<const GlobalSearch>(grid, options_);
  if (init == Initialization::kGlobal) {
    pending_search_ = global_search() != nullptr;
  }
}

AmclFilter::AmclFilter(const AmclOptions& options,
                       std::shared_ptr<const MapModel> map, Initialization init,
                       uint64_t seed)
    : options_(options), map_(std::move(map)), rng_(seed) {
  ValidateAmclOptions(options_);
  if (map_ == nullptr) throw std::invalid_argument("AmclFilter: map is null");
  if (std::fabs(map_->max_occ_dist() - options_.laser_likelihood_max_dist) >
      1e-9) {
    std::ostringstream os;
    os << "map distance field was built for laser_likelihood_max_dist="
       << map_->max_occ_dist() << " but the options say "
       << options_.laser_likelihood_max_dist;
    throw std::invalid_argument(os.str());
  }
  motion_ = CreateMotionModel(options_);
  sensor_ = CreateSensorModel(options_, map_);
  if (init == Initialization::kGlobal) {
    GlobalLocalization();
  } else {
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    cov.diagonal() << options_.initial_cov_xx, options_.initial_cov_yy,
        options_.initial_cov_aa;
    SetPose({options_.initial_pose_x, options_.initial_pose_y,
             options_.initial_pose_a},
            cov);
  }
}

void AmclFilter::SampleGaussian(const Pose2& mean, const Eigen::Matrix3d& cov,
                                const MapModel& map,
                                std::vector<Particle>* out) {
  CheckPoseInMap(mean, map, "initial pose");
  const Eigen::Matrix3d factor = CovarianceFactor(cov);
  std::normal_distribution<double> gauss(0.0, 1.0);
  out->resize(options_.max_particles);
  const double w = 1.0 / options_.max_particles;
  for (Particle& p : *out) {
    const Eigen::Vector3d z(gauss(rng_), gauss(rng_), gauss(rng_));
    const Eigen::Vector3d d = factor * z;
    p.pose = {mean.x + d.x(), mean.y + d.y(), NormalizeAngle(mean.yaw + d.z())};
    p.weight = w;
    p.injected = false;
    p.hypothesis = -1;
  }
}

void AmclFilter::SetPose(const Pose2& mean,
                         const Eigen::Matrix3d& covariance) {
  std::vector<Particle> fresh;
  SampleGaussian(mean, covariance, *map_, &fresh);  // throws before any change
  particles_.swap(fresh);
  hypotheses_.clear();
  pending_search_ = false;
  ResetAfterInitialization(options_.confidence_min_updates);  // user's pose
}

void AmclFilter::GlobalLocalization() {
  particles_.resize(options_.max_particles);
  const double w = 1.0 / options_.max_particles;
  for (Particle& p : particles_) {
    p.pose = map_->SampleFreePose(&rng_);
    p.weight = w;
    p.injected = false;
    p.hypothesis = -1;
  }
  hypotheses_.clear();
  pending_search_ = global_search() != nullptr;
  pending_relocalization_ = false;
  ResetAfterInitialization(0);
}

void AmclFilter::SeedFromCandidates(
    const std::vector<SearchCandidate>& candidates) {
  if (candidates.empty()) return;
  // Spread round a candidate: the search lattice's error (a cell, a fraction
  // of a degree) plus room for the filter to settle.
  constexpr double kSigmaXY = 0.15, kSigmaYaw = 0.1;
  constexpr int kTries = 10;  // draws before falling back to the candidate
  std::normal_distribution<double> gauss(0.0, 1.0);
  const int n = options_.max_particles;
  // Particle::hypothesis is 16 bits; the search returns a handful.
  const int k = std::min<int>(static_cast<int>(candidates.size()),
                              std::numeric_limits<int16_t>::max());
  std::vector<Particle> fresh(n);
  double total = 0.0;
  for (int m = 0; m < n; ++m) {
    const SearchCandidate& c = candidates[m % k];
    Pose2 p = c.pose;
    for (int t = 0; t < kTries; ++t) {
      const Pose2 q{c.pose.x + kSigmaXY * gauss(rng_),
                     c.pose.y + kSigmaXY * gauss(rng_),
                     NormalizeAngle(c.pose.yaw + kSigmaYaw * gauss(rng_))};
      int i, j;
      if (map_->WorldToCell(q.x, q.y, &i, &j) && map_->IsFree(i, j)) {
        p = q;
        break;
      }
    }
    fresh[m].pose = p;
    fresh[m].weight = std::max(c.score, 1e-6);
    fresh[m].hypothesis = static_cast<int16_t>(m % k);
    total += fresh[m].weight;
  }
  for (Particle& p : fresh) p.weight /= total;
  particles_.swap(fresh);
  hypotheses_.assign(k, Hypothesis());
  for (int h = 0; h < k; ++h) hypotheses_[h].candidate = candidates[h];
  ResetAfterInitialization(0);
}

void AmclFilter::RunSearch(const LaserScan& scan, bool relocalization) {
  pending_search_ = false;
  pending_relocalization_ = false;
  const bool found_by_injection = relocalization && pending_found_by_injection_;
  pending_found_by_injection_ = false;
  const GlobalSearch* search = global_search();
  if (search == nullptr) return;
  SearchReport report;
  report.count = last_search_.count + 1;
  report.relocalization = relocalization;
  report.found_by_injection = found_by_injection;
  report.candidates =
      search->Search(scan, &report.seconds, &report.cpu_seconds);
  std::vector<SearchCandidate> seeds = report.candidates;
  if (relocalization) {
    // The filter may only be briefly confused (a crowd in front of the
    // laser): its own estimate stays one of the hypotheses.
    bool known = false;
    double lowest = options_.global_search_min_score;
    for (const SearchCandidate& c : seeds) {
      lowest = std::min(lowest, c.score);
      known = known || (std::hypot(c.pose.x - estimate_.mean.x,
                                   c.pose.y - estimate_.mean.y) < 1.0 &&
                        std::fabs(AngleDiff(c.pose.yaw, estimate_.mean.yaw)) <
                            kPi / 4);
    }
    if (!known) seeds.push_back({estimate_.mean, lowest});
  }
  last_search_ = report;
  SeedFromCandidates(seeds);
}

void AmclFilter::SetMap(const OccupancyGrid& grid, Initialization init) {
  auto new_map =
      std::make_shared<MapModel>(grid, options_.laser_likelihood_max_dist);
  auto new_sensor = CreateSensorModel(options_, new_map);
  auto new_search = std::make_shared<const GlobalSearch>(grid, options_);
  std::vector<Particle> fresh;
  if (init == Initialization::kGlobal) {
    fresh.resize(options_.max_particles);
    for (Particle& p : fresh) {
      p.pose = new_map->SampleFreePose(&rng_);
      p.weight = 1.0 / options_.max_particles;
      p.hypothesis = -1;
    }
  } else if (init == Initialization::kFromOptions) {
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    cov.diagonal() << options_.initial_cov_xx, options_.initial_cov_yy,
        options_.initial_cov_aa;
    SampleGaussian({options_.initial_pose_x, options_.initial_pose_y,
                    options_.initial_pose_a},
                   cov, *new_map, &fresh);
  } else {
    SampleGaussian(estimate_.mean, estimate_.covariance, *new_map, &fresh);
  }
  map_ = std::move(new_map);
  sensor_ = std::move(new_sensor);
  search_ = std::move(new_search);
  particles_.swap(fresh);
  hypotheses_.clear();
  pending_relocalization_ = false;
  pending_search_ = init == Initialization::kGlobal && global_search();
  ResetAfterInitialization(
      init == Initialization::kGlobal
          ? 0
          : init == Initialization::kFromOptions
                ? options_.confidence_min_updates
                : confidence_.evidence_updates);
}

void AmclFilter::ResetAfterInitialization(int evidence_updates) {
  // As amcl after pf_init: the next scan re-anchors odometry and is
  // integrated without motion; recovery averages and convergence restart.
  have_odom_ = false;
  force_update_ = false;
  resample_count_ = 0;
  have_w_avg_ = false;
  converged_ = false;
  measured_ = false;
  confidence_ = Confidence();
  confidence_.evidence_updates = evidence_updates;
  evidence_views_.clear();
  evidence_information_.setZero();
  // A pose the user gave (or any pose, with confidence_min_updates 0: claim
  // at once) is trusted in every direction.
  if (evidence_updates >= options_.confidence_min_updates) {
    confidence_.constraint = std::numeric_limits<double>::infinity();
  }
  challenges_left_ = evidence_updates >= options_.confidence_min_updates
                         ? 0
                         : options_.confidence_challenges;
  UpdateEstimate();
}

UpdateResult AmclFilter::Update(const Pose2& odom_pose,
                                const LaserScan& scan) {
  UpdateResult result;
  if (!IsFinite(odom_pose)) {
    result.status = UpdateStatus::kRejectedBadOdometry;
    result.message = "odometry pose " + PoseText(odom_pose) + " is not finite";
    return result;
  }
  std::string error;
  if (!PrepareScan(scan, options_, &scan_, &error)) {
    result.status = UpdateStatus::kRejectedBadScan;
    result.message = error;
    return result;
  }

  // A pending map-wide search replaces the set by poses at this scan's time,
  // so no motion is applied to them (SeedFromCandidates clears have_odom_).
  if (pending_search_) RunSearch(scan, pending_relocalization_);

  bool motion_update = false;  // triggered by motion, not forced
  if (have_odom_) {
    const double moved =
        std::hypot(odom_pose.x - odom_ref_.x, odom_pose.y - odom_ref_.y);
    const double turned = std::fabs(AngleDiff(odom_pose.yaw, odom_ref_.yaw));
    motion_update =
        moved > options_.update_min_d || turned > options_.update_min_a;
    if (!(motion_update || force_update_)) {
      result.status = UpdateStatus::kSkippedNoMotion;
      return result;
    }
    motion_->SamplePoses(odom_ref_, odom_pose, &rng_, &particles_);
  }
  have_odom_ = true;
  odom_ref_ = odom_pose;
  force_update_ = false;

  if (sensor_->UsableBeamCount(scan_) == 0) {
    std::ostringstream os;
    os << "scan has no usable beams for " << sensor_->name() << " ("
       << scan_.subsampled_count << " selected, " << scan_.nan_count
       << " NaN, the rest max-range)";
    result.status = UpdateStatus::kMotionOnly;
    result.message = os.str();
    UpdateEstimate();
    return result;
  }
  sensor_->ComputeLogLikelihoods(scan_, particles_, converged_,
                                 &log_likelihoods_);
  if (!ApplyLikelihoods()) {
    result.status = UpdateStatus::kMotionOnly;
    result.message = "no particle has a positive finite scan likelihood";
    UpdateEstimate();
    return result;
  }
  result.status = UpdateStatus::kUpdated;
  if (++resample_count_ % options_.resample_interval == 0) {
    Resample();
    result.resampled = true;
  }
  UpdateEstimate();
  UpdateConfidence(motion_update, odom_pose, scan);
  return result;
}

bool AmclFilter::ApplyLikelihoods() {
  const size_t n = particles_.size();
  double max_lw = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < n; ++k) {
    const double l = log_likelihoods_[k];
    const double w = particles_[k].weight;
    double lw = -std::numeric_limits<double>::infinity();
    if (w > 0.0 && std::isfinite(l)) lw = std::log(w) + l;
    log_likelihoods_[k] = lw;
    max_lw = std::max(max_lw, lw);
  }
  if (!std::isfinite(max_lw)) return false;
  double sum = 0.0;
  for (size_t k = 0; k < n; ++k) sum += std::exp(log_likelihoods_[k] - max_lw);
  for (size_t k = 0; k < n; ++k) {
    particles_[k].weight = std::exp(log_likelihoods_[k] - max_lw) / sum;
  }
  // Average likelihood of the scan under the predicted belief,
  // sum_i w_i p_i with normalised prior weights (Thrun et al. table 8.3 with
  // weighted particles).  amcl divides this by the particle count once more,
  // which makes w_avg jump whenever KLD-sampling changes the set size and
  // can fake (or mask) a drop in fit; that factor is left out here.
  const double log_w_avg = max_lw + std::log(sum);
  if (!have_w_avg_) {
    log_w_slow_ = log_w_fast_ = log_w_avg;
    have_w_avg_ = true;
  } else {
    log_w_slow_ = LogMix(log_w_slow_, log_w_avg, options_.recovery_alpha_slow);
    log_w_fast_ = LogMix(log_w_fast_, log_w_avg, options_.recovery_alpha_fast);
  }
  return true;
}

double AmclFilter::InjectionProbability() const {
  if (!have_w_avg_) return 0.0;
  return std::max(0.0, 1.0 - std::exp(log_w_fast_ - log_w_slow_));
}

int AmclFilter::LowVarianceDraw(int count, double inject_probability) {
  // Thrun et al. table 4.4: one random offset, then `count` equally spaced
  // pointers into the cumulative weights.  O(N + count), and the result
  // reproduces the weights with far less variance than independent draws.
  const size_t n = particles_.size();
  resample_buffer_.resize(count);
  const double step = 1.0 / count;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double start = unit(rng_) * step;
  double cumulative = particles_[0].weight;
  size_t i = 0;
  int injected = 0;
  for (int m = 0; m < count; ++m) {
    const double target = start + m * step;
    while (target > cumulative && i + 1 < n) {
      cumulative += particles_[++i].weight;
    }
    Particle& out = resample_buffer_[m];
    if (inject_probability > 0.0 && unit(rng_) < inject_probability) {
      out.pose = map_->SampleFreePose(&rng_);
      out.injected = true;
      out.hypothesis = -1;
      ++injected;
    } else {
      out.pose = particles_[i].pose;
      out.injected = particles_[i].injected;
      out.hypothesis = particles_[i].hypothesis;
    }
    out.weight = step;
  }
  return injected;
}

void AmclFilter::Resample() {
  if (particles_.empty()) return;
  const double inject = InjectionProbability();
  int count = std::min(options_.min_particles, options_.max_particles);
  bool settled = false;
  int injected = 0;
  for (int iter = 0; iter < kMaxKldIterations && !settled; ++iter) {
    injected = LowVarianceDraw(count, inject);
    const int bins = CountOccupiedBins(resample_buffer_, &bin_scratch_);
    const int required =
        KldSampleCount(bins, options_.kld_err, options_.kld_z,
                       options_.min_particles, options_.max_particles);
    if (required <= count) {
      settled = true;
    } else {
      count = required;
    }
  }
  if (!settled) injected = LowVarianceDraw(count, inject);
  KeepHypothesisFloors();
  particles_.swap(resample_buffer_);
  // Injected particles fit the scan badly and drag the next averages down,
  // which would inject more and more ("spiralling into randomness").  amcl
  // therefore restarts both averages whenever w_fast < w_slow; that also
  // throws away w_slow's long-term memory about every other resampling
  // (normal scan-to-scan noise), after which a real drop such as a
  // kidnapping is never registered.  Here only the short-term average
  // restarts, at the long-term level, and only after an actual injection:
  // injection pauses until the fit drops again, and keeps recurring while
  // the robot stays lost.
  if (injected > 0) log_w_fast_ = log_w_slow_;
  UpdateConvergence();
}

void AmclFilter::MeasureHypotheses() {
  if (hypotheses_.empty()) return;  // tracking: nothing to measure
  for (Hypothesis& h : hypotheses_) {
    h.probability = 0.0;
    h.particles = 0;
  }
  const int k = static_cast<int>(hypotheses_.size());
  for (const Particle& p : particles_) {
    if (p.hypothesis < 0 || p.hypothesis >= k) continue;
    hypotheses_[p.hypothesis].probability += p.weight;
    ++hypotheses_[p.hypothesis].particles;
  }
  double best = 0.0;
  for (const Hypothesis& h : hypotheses_) best = std::max(best, h.probability);
  if (best <= 0.0) return;
  // Refuted: far less probable than the best.  Final: a hypothesis the
  // evidence has ruled out is not brought back by keeping its particles.
  for (Hypothesis& h : hypotheses_) {
    if (h.probability < options_.hypothesis_refuted_ratio * best) {
      h.refuted = true;
    }
  }
}

void AmclFilter::KeepHypothesisFloors() {
  const int floor_count = options_.hypothesis_min_particles;
  const int k = static_cast<int>(hypotheses_.size());
  if (k < 2 || floor_count <= 0) return;
  MeasureHypotheses();  // probabilities before this resampling
  std::vector<int> drawn(k, 0);
  for (const Particle& p : resample_buffer_) {
    if (p.hypothesis >= 0 && p.hypothesis < k) ++drawn[p.hypothesis];
  }
  // Hypotheses the draw left short of the floor: their particles are drawn
  // again from their own, floor_count of them, keeping their probability.
  std::vector<char> short_of_floor(k, 0);
  double floored_probability = 0.0;
  bool any = false;
  for (int h = 0; h < k; ++h) {
    const Hypothesis& hyp = hypotheses_[h];
    if (hyp.refuted || hyp.probability <= 0.0 || drawn[h] >= floor_count) {
      continue;
    }
    short_of_floor[h] = 1;
    floored_probability += hyp.probability;
    any = true;
  }
  if (!any) return;
  auto floored = [&](const Particle& p) {
    return p.hypothesis >= 0 && p.hypothesis < k && short_of_floor[p.hypothesis];
  };
  // The rest of the draw shares the rest of the probability equally (it was
  // drawn with equal weights).
  size_t kept = 0;
  for (size_t m = 0; m < resample_buffer_.size(); ++m) {
    if (!floored(resample_buffer_[m])) resample_buffer_[kept++] = resample_buffer_[m];
  }
  resample_buffer_.resize(kept);
  const double rest = std::max(0.0, 1.0 - floored_probability);
  for (Particle& p : resample_buffer_) p.weight = kept > 0 ? rest / kept : 0.0;
  // Low-variance draw of floor_count particles within each short hypothesis.
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int h = 0; h < k; ++h) {
    if (!short_of_floor[h]) continue;
    const double mass = hypotheses_[h].probability;
    const double step = mass / floor_count;
    double target = unit(rng_) * step;
    double cumulative = 0.0;
    for (const Particle& p : particles_) {
      if (p.hypothesis != h) continue;
      cumulative += p.weight;
      while (target < cumulative && target < mass) {
        Particle out = p;
        out.weight = step;
        resample_buffer_.push_back(out);
        target += step;
      }
    }
  }
  double total = 0.0;
  for (const Particle& p : resample_buffer_) total += p.weight;
  for (Particle& p : resample_buffer_) p.weight /= total;
}

void AmclFilter::UpdateConvergence() {
  if (particles_.empty()) {
    converged_ = false;
    return;
  }
  double mx = 0.0, my = 0.0;
  for (const Particle& p : particles_) {
    mx += p.pose.x;
    my += p.pose.y;
  }
  mx /= particles_.size();
  my /= particles_.size();
  converged_ = true;
  for (const Particle& p : particles_) {
    if (std::fabs(p.pose.x - mx) > kConvergenceDistance ||
        std::fabs(p.pose.y - my) > kConvergenceDistance) {
      converged_ = false;
      return;
    }
  }
}

void AmclFilter::UpdateEstimate() {
  MeasureHypotheses();
  clusters_ = ClusterParticles(particles_);
  estimate_ = PoseEstimate();
  estimate_.cluster_count = static_cast<int>(clusters_.size());
  confidence_.modes = 0;
  if (clusters_.empty()) {
    UpdateClaim();
    return;
  }
  estimate_.mean = clusters_.front().mean;
  estimate_.covariance = clusters_.front().covariance;
  estimate_.weight = clusters_.front().weight;
  // Modes: the heaviest clusters holding 1 - confidence_mode_weight.
  const double needed = 1.0 - options_.confidence_mode_weight;
  double held = 0.0;
  for (const PoseCluster& c : clusters_) {
    if (held >= needed - 1e-12) break;
    held += c.weight;
    ++confidence_.modes;
  }
  UpdateClaim();
}

void AmclFilter::UpdateClaim() {
  // Second moment of the modes about the estimate: a mixture's covariance
  // plus the spread of its means, taken round the mean actually published.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  double total = 0.0;
  for (int k = 0; k < confidence_.modes; ++k) {
    const PoseCluster& c = clusters_[k];
    const Eigen::Vector3d d(c.mean.x - estimate_.mean.x,
                            c.mean.y - estimate_.mean.y,
                            AngleDiff(c.mean.yaw, estimate_.mean.yaw));
    cov += c.weight * (c.covariance + d * d.transpose());
    total += c.weight;
  }
  if (total > 0.0) cov /= total;
  confidence_.confident =
      measured_ &&
      confidence_.explained_fraction >= options_.confidence_min_explained &&
      confidence_.modes == 1 &&
      confidence_.evidence_updates >= options_.confidence_min_updates &&
      confidence_.constraint >= options_.confidence_min_constraint;
  if (!confidence_.confident) {
    cov(0, 0) = std::max(cov(0, 0), kUnconfidentVarianceXY);
    cov(1, 1) = std::max(cov(1, 1), kUnconfidentVarianceXY);
    cov(2, 2) = std::max(cov(2, 2), kUnconfidentVarianceYaw);
  }
  estimate_.claim_covariance = cov;
}

void AmclFilter::Challenge(const LaserScan& scan) {
  const GlobalSearch* search = global_search();
  if (search == nullptr) return;
  SearchReport report;
  report.count = last_search_.count + 1;
  report.challenge = true;
  // One more than the seeding search keeps: the estimate itself is one.
  report.candidates =
      search->Search(scan, &report.seconds, &report.cpu_seconds,
                     options_.global_search_max_candidates + 1);
  auto here = [&](const SearchCandidate& c) {
    return std::hypot(c.pose.x - estimate_.mean.x,
                      c.pose.y - estimate_.mean.y) < 1.0 &&
           std::fabs(AngleDiff(c.pose.yaw, estimate_.mean.yaw)) < kPi / 4;
  };
  // The bar a look-alike must reach: a share of the score of the estimate's
  // own place in this search (scored on the same lattice as the others), or
  // of the best place found when the estimate's is not among the candidates.
  double best = options_.global_search_min_score, own = 0.0;
  for (const SearchCandidate& c : report.candidates) {
    best = std::max(best, c.score);
    if (here(c)) own = std::max(own, c.score);
  }
  const double bar =
      options_.confidence_challenge_min_relative_score * (own > 0.0 ? own : best);
  std::vector<SearchCandidate> seeds;
  for (const SearchCandidate& c : report.candidates) {
    if (c.score >= bar && !here(c)) seeds.push_back(c);
  }
  last_search_ = report;
  if (seeds.empty()) return;  // the view has no look-alike: claim
  // The estimate stays, as heavy as the best place the search found.
  seeds.insert(seeds.begin(), SearchCandidate{estimate_.mean, best});
  const int left = challenges_left_;
  SeedFromCandidates(seeds);  // restarts the evidence
  challenges_left_ = left;
}

bool AmclFilter::IsNewView(const Pose2& odom_pose, const LaserScan& scan) const {
  const double min_travel = std::max(options_.update_min_d, kMinViewTravel);
  int blind_sector = -1;  // the scan's beam gap, computed only when needed
  for (const Pose2& v : evidence_views_) {
    if (std::hypot(odom_pose.x - v.x, odom_pose.y - v.y) >= min_travel) continue;
    if (blind_sector < 0) {
      blind_sector = LargestBeamGap(scan) > options_.update_min_a ? 1 : 0;
    }
    if (blind_sector &&
        std::fabs(AngleDiff(odom_pose.yaw, v.yaw)) >= options_.update_min_a) {
      continue;
    }
    return false;  // seen from here before
  }
  return true;
}

void AmclFilter::UpdateConfidence(bool motion_update, const Pose2& odom_pose,
                                  const LaserScan& scan) {
  const double hit_dist = options_.confidence_hit_dist > 0.0
                              ? options_.confidence_hit_dist
                              : 2.0 * options_.laser_sigma_hit;
  confidence_.explained_fraction = ExplainedFraction(
      *map_, scan_, estimate_.mean, hit_dist, &confidence_.beams_used);
  measured_ = true;
  const bool explained =
      confidence_.explained_fraction >= options_.confidence_min_explained;
  // A mode made mostly of augmented MCL's random draws (a kidnapped robot's
  // filter re-finding a place that fits) was never weighed against the map's
  // look-alikes: resampling found it, not the evidence.  It earns nothing;
  // the map-wide search runs with it as one more candidate, and the filter
  // then decides among them as after any search.
  const bool found_by_injection =
      global_search() != nullptr && !clusters_.empty() &&
      clusters_.front().injected_weight > 0.5 * clusters_.front().weight;
  if (explained && confidence_.modes == 1 && !found_by_injection) {
    // Only a new view brings new evidence (see IsNewView): a forced update
    // re-reads the same one, and so do a turn on the spot for a laser that
    // sees all round (the same scan, rotated, fits a wrong place exactly as
    // well as before) and driving back and forth over the same half metre
    // (the study's false claims were made both ways, in a corner).
    if (motion_update && IsNewView(odom_pose, scan)) {
      ++confidence_.evidence_updates;
      evidence_views_.push_back(odom_pose);
      if (std::isfinite(confidence_.constraint)) {
        evidence_information_ +=
            ScanInformation(*map_, scan_, estimate_.mean, hit_dist);
        confidence_.constraint =
            WeakestTranslationInformation(evidence_information_);
      }
      // A long run (hours of confident tracking) keeps only its recent
      // views: by then the claim has been earned, and the check stays cheap.
      const size_t keep = 4 * static_cast<size_t>(
                                  std::max(options_.confidence_min_updates, 16));
      if (evidence_views_.size() > 2 * keep) {
        evidence_views_.erase(evidence_views_.begin(),
                              evidence_views_.end() - keep);
      }
    }
  } else {
    confidence_.evidence_updates = 0;
    evidence_views_.clear();
    evidence_information_.setZero();
    confidence_.constraint = 0.0;
  }
  if (found_by_injection && explained) {
    pending_search_ = true;
    pending_relocalization_ = true;
    pending_found_by_injection_ = true;
    confidence_.lost_updates = 0;
    UpdateClaim();
    return;
  }
  if (confidence_.evidence_updates >= options_.confidence_min_updates &&
      challenges_left_ > 0) {
    --challenges_left_;
    Challenge(scan);
    if (confidence_.evidence_updates == 0) {  // re-seeded: nothing to check
      UpdateClaim();
      return;
    }
  }
  // Lost: no hypothesis explains what the robot sees.  (While several modes
  // remain the heaviest may well be a wrong one; motion decides among them,
  // not a new search.)  The heaviest clusters are enough: after a kidnapping
  // augmented MCL sprinkles random poses, a cloud of light clusters.
  constexpr int kLostCheckClusters = 10;
  bool any_explained = explained;
  for (int k = 1; !any_explained && k < static_cast<int>(clusters_.size()) &&
                  k < kLostCheckClusters;
       ++k) {
    any_explained = ExplainedFraction(*map_, scan_, clusters_[k].mean,
                                      hit_dist) >=
                    options_.confidence_min_explained;
  }
  if (any_explained) {
    confidence_.lost_updates = 0;
  } else if (motion_update) {
    ++confidence_.lost_updates;
    if (options_.confidence_lost_updates > 0 &&
        confidence_.lost_updates >= options_.confidence_lost_updates &&
        global_search() != nullptr) {
      pending_search_ = true;
      pending_relocalization_ = true;
      pending_found_by_injection_ = false;
      confidence_.lost_updates = 0;
    }
  }
  UpdateClaim();
}

size_t AmclFilter::ParticleMemoryBytes() const {
  return particles_.capacity() * sizeof(Particle) +
         resample_buffer_.capacity() * sizeof(Particle) +
         log_likelihoods_.capacity() * sizeof(double) +
         bin_scratch_.capacity() * sizeof(uint64_t);
}

size_t AmclFilter::MapMemoryBytes() const {
  return map_->MemoryBytes() + sensor_->MemoryBytes();
}

}  // namespace amcl
}  // namespace minibot3d_navigation
