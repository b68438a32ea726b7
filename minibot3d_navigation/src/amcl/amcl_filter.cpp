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

std::string PoseText(const Pose2D& p) {
  std::ostringstream os;
  os << "(x=" << p.x << ", y=" << p.y << ", yaw=" << p.yaw << ")";
  return os.str();
}

void CheckPoseInMap(const Pose2D& mean, const MapModel& map, const char* what) {
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
        const Pose2D c = map.GridFrameToWorld(
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

AmclFilter::AmclFilter(const AmclOptions& options, const OccupancyGrid& grid,
                       Initialization init, uint64_t seed)
    : AmclFilter(options, BuildMap(options, grid), init, seed) {}

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

void AmclFilter::SampleGaussian(const Pose2D& mean, const Eigen::Matrix3d& cov,
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
  }
}

void AmclFilter::SetPose(const Pose2D& mean,
                         const Eigen::Matrix3d& covariance) {
  std::vector<Particle> fresh;
  SampleGaussian(mean, covariance, *map_, &fresh);  // throws before any change
  particles_.swap(fresh);
  ResetAfterInitialization();
}

void AmclFilter::GlobalLocalization() {
  particles_.resize(options_.max_particles);
  const double w = 1.0 / options_.max_particles;
  for (Particle& p : particles_) {
    p.pose = map_->SampleFreePose(&rng_);
    p.weight = w;
  }
  ResetAfterInitialization();
}

void AmclFilter::SetMap(const OccupancyGrid& grid, Initialization init) {
  auto new_map =
      std::make_shared<MapModel>(grid, options_.laser_likelihood_max_dist);
  auto new_sensor = CreateSensorModel(options_, new_map);
  std::vector<Particle> fresh;
  if (init == Initialization::kGlobal) {
    fresh.resize(options_.max_particles);
    for (Particle& p : fresh) {
      p.pose = new_map->SampleFreePose(&rng_);
      p.weight = 1.0 / options_.max_particles;
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
  particles_.swap(fresh);
  ResetAfterInitialization();
}

void AmclFilter::ResetAfterInitialization() {
  // As amcl after pf_init: the next scan re-anchors odometry and is
  // integrated without motion; recovery averages and convergence restart.
  have_odom_ = false;
  force_update_ = false;
  resample_count_ = 0;
  have_w_avg_ = false;
  converged_ = false;
  UpdateEstimate();
}

UpdateResult AmclFilter::Update(const Pose2D& odom_pose,
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

  if (have_odom_) {
    const double moved =
        std::hypot(odom_pose.x - odom_ref_.x, odom_pose.y - odom_ref_.y);
    const double turned = std::fabs(AngleDiff(odom_pose.yaw, odom_ref_.yaw));
    if (!(moved > options_.update_min_d || turned > options_.update_min_a ||
          force_update_)) {
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
      ++injected;
    } else {
      out.pose = particles_[i].pose;
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
  clusters_ = ClusterParticles(particles_);
  estimate_ = PoseEstimate();
  estimate_.cluster_count = static_cast<int>(clusters_.size());
  if (clusters_.empty()) return;
  estimate_.mean = clusters_.front().mean;
  estimate_.covariance = clusters_.front().covariance;
  estimate_.weight = clusters_.front().weight;
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
