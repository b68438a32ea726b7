// Adaptive Monte Carlo localization (AMCL), ROS-free core.
//
// References: Thrun, Burgard & Fox, "Probabilistic Robotics" (2005), ch. 8
// (MCL, table 8.2; augmented MCL, table 8.3; low-variance resampling,
// table 4.4) and Fox, "KLD-sampling: Adaptive particle filters" (2003).
// Behaviour and parameters follow ROS 1 amcl.
//
// The belief over the robot pose in the map frame is a set of weighted
// particles.  Each Update(odom_pose, scan):
//  1. gating: nothing happens until odometry has moved more than update_min_d
//     (Euclidean) or turned more than update_min_a since the last update,
//     unless RequestNoMotionUpdate() was called (amcl's
//     request_nomotion_update) or it is the first scan after initialization;
//  2. prediction: every particle is moved by the odometry increment with
//     sampled noise (motion_model.h);
//  3. correction: weights are multiplied by the laser likelihood
//     (sensor_model.h), in log space so no likelihood underflows, and
//     normalised.  The average likelihood feeds two exponential filters,
//     w_slow and w_fast (recovery_alpha_slow/fast);
//  4. every resample_interval corrections, the set is resampled with the
//     low-variance (systematic) sampler.  Its size is chosen by KLD-sampling
//     (kld_sampling.h): the smallest n >= min_particles for which the n drawn
//     particles occupy few enough histogram bins that Fox's bound is met
//     (found by fixed-point iteration: draw n, count bins k, n <- bound(k)),
//     clamped to max_particles.  With probability max(0, 1 - w_fast/w_slow)
//     each draw is replaced by a pose uniform over free space (augmented MCL:
//     recovers from a wrong convergence / kidnapping); after an actual
//     injection w_fast restarts at w_slow (amcl restarts both, see
//     Resample() for why not here);
//  5. the pose estimate is the weighted mean/covariance of the heaviest
//     cluster of particles (pose_clusters.h).
//
// Confidence (what the published covariance claims, so that a global
// localization knows when it is wrong):
//  * explained fraction: of the used (non-max-range) beams, the share whose
//    end point at the estimate lies within confidence_hit_dist of a mapped
//    obstacle (the likelihood field's distance);
//  * modes: the heaviest clusters that together hold 1 -
//    confidence_mode_weight of the weight;
//  * evidence: consecutive updates with the scan explained and one mode,
//    each from a new view: a place (in odometry) at least update_min_d from
//    every place counted before in the run.  A turn on the spot shows a laser
//    that sees all round the same scan, rotated, which fits a wrong place as
//    well as before, and driving back and forth re-reads the same views; for
//    a laser with a blind sector wider than update_min_a, a heading turned by
//    update_min_a from those counted nearby is a new view too.  Updates
//    without a new view do not count, but an unexplained one (or two modes)
//    still breaks the run.
//    It restarts at 0 on global localization and on a re-seed, and starts
//    satisfied for a pose the user gave (initial pose).
//  * constraint: the views must also fix the pose in every direction.  Each
//    evidence update adds what its scan says about the pose at the estimate
//    (ScanInformation: the map's surface normals at the explained end
//    points); the least constrained direction must gather
//    confidence_min_constraint.  Along a corridor whose walls are bare, or
//    across a hall wider than the laser's range, the scans fix the pose
//    across but not along: the particles there agree only because they all
//    came from the same guess, which can be metres off.  The sum restarts
//    with the evidence.
//  * origin: each particle knows whether it descends from augmented MCL's
//    random draws since the hypotheses were last set (Particle::injected).
//    A heaviest cluster made mostly of such particles is a place resampling
//    stumbled on, never weighed against the map's look-alikes (in a building
//    of similar rooms a kidnapped robot's filter would otherwise claim the
//    first room that fits): it earns no evidence, and once
//    it explains the scan the map-wide search runs, keeping it as one more
//    candidate (without a search it is treated like any other mode).
//  The claim covariance (PoseEstimate::claim_covariance, what the node
//  publishes on amcl_pose) is the second moment of all modes about the
//  estimate, so a split set claims the distance between its modes; unless
//  the filter is confident (explained >= confidence_min_explained, one mode,
//  evidence >= confidence_min_updates, constraint >=
//  confidence_min_constraint) its diagonal is raised to at least
//  kUnconfidentVarianceXY / kUnconfidentVarianceYaw.  Resampling alone never
//  earns a claim: only updates after motion count.
//  * challenge: one mode only says that the filter's own hypotheses agree.
//    When the evidence first reaches confidence_min_updates after a global
//    localization or a re-seed, the map-wide search runs on the current scan
//    (up to confidence_challenges times per seeding); places that explain it
//    as well as the estimate's own place in that search, or better
//    (>= confidence_challenge_min_relative_score of its score; of the best
//    place's when the estimate's is not among the candidates), and lie
//    >= 1 m or >= 45 deg from the estimate (the true place may have ranked
//    below the look-alikes the first search kept, or be a twin room it
//    missed) are added as
//    hypotheses beside the estimate, evidence restarts, and motion must
//    decide again.  A pose the user gave is never challenged.
//
// Hypotheses: every particle seeded round a search candidate carries the
// candidate's index (Particle::hypothesis), and so do its descendants; the
// total weight of a candidate's particles is its probability: the search's
// score as prior, times the likelihood of every scan since.  Resampling
// keeps each probability in expectation, but a light hypothesis on a few
// particles can die by chance, and an under-sampled one after an unlucky
// stretch of updates.  A dead hypothesis never comes back, whatever the robot
// sees later, so the survivor would earn the claim by default, even when the
// dead one was the truth.  So resampling keeps at least
// hypothesis_min_particles particles on every hypothesis not yet refuted:
// drawn from its own particles in proportion to their weights, and weighted
// so that the hypothesis keeps its probability exactly (stratified
// resampling, the rest of the set sharing the rest).  A hypothesis is refuted
// once its probability falls below hypothesis_refuted_ratio times the most
// probable one's, and from then on is resampled like any other particles.
// With one hypothesis (or none: a pose the user gave, a uniform spread) this
// is plain resampling.
//
// Global localization with the map-wide search (global_search.h): the set is
// first spread uniformly (amcl); the next Update() runs the search on its
// scan and, if it finds candidates, replaces the set by Gaussians round them
// (weights proportional to the scores).  The same happens when the filter
// finds itself lost: confidence_lost_updates consecutive motion-triggered
// updates in which none of the ten heaviest clusters explains the scan (a
// kidnapped robot, or candidates that were all wrong), or when a place found
// by random draws explains it (origin, above); the current estimate is then
// kept as one more candidate.
//
// Deliberate differences from ROS amcl (each explained where implemented):
// update gating uses the Euclidean odometry distance (amcl: |dx| or |dy|);
// KLD gives min_particles for one occupied bin (amcl: max_particles); the
// average likelihood omits amcl's extra 1/N; only w_fast restarts, and only
// after an actual injection; the estimate's covariance is that of the chosen
// cluster (amcl publishes the whole-set one: WholeSetStatistics()), and the
// claim covariance covers every mode (see Confidence above).
//
// Errors: configuration mistakes (options, map, initial pose) throw
// std::invalid_argument with a message naming the offending value, and leave
// the filter unchanged.  Bad run-time inputs (non-finite odometry, malformed
// scan) are rejected by Update() with a status; the filter keeps its last
// good state (odometry is not consumed, so the motion is applied by the next
// good update).  Not thread-safe: call from one thread.
#ifndef MINIBOT3D_NAVIGATION_AMCL_AMCL_FILTER_H_
#define MINIBOT3D_NAVIGATION_AMCL_AMCL_FILTER_H_

#include <cstddef>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "minibot3d_navigation/amcl/amcl_options.h"
#include "minibot3d_navigation/amcl/global_search.h"
#include "minibot3d_navigation/amcl/motion_model.h"
#include "minibot3d_navigation/amcl/occupancy_map.h"
#include "minibot3d_navigation/amcl/pose_clusters.h"
#include "minibot3d_navigation/amcl/sensor_model.h"
#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace amcl {

enum class UpdateStatus {
  kUpdated,              // prediction + correction applied
  kMotionOnly,           // prediction applied; the scan had no usable beams
                         // (e.g. all max range) or no particle explained it
  kSkippedNoMotion,      // below update_min_d / update_min_a: nothing changed
  kRejectedBadOdometry,  // non-finite odometry pose: nothing changed
  kRejectedBadScan,      // malformed scan (see PrepareScan): nothing changed
};

const char* UpdateStatusName(UpdateStatus status);

struct UpdateResult {
  UpdateStatus status = UpdateStatus::kSkippedNoMotion;
  bool resampled = false;
  std::string message;  // why, for kMotionOnly and the rejections
};

struct PoseEstimate {
  Pose2 mean;                                           // map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // x, y, yaw
  double weight = 0.0;    // probability mass of the chosen cluster
  int cluster_count = 0;  // number of hypotheses in the set
  // What the filter claims (see the header comment): covers every mode, and
  // is large while the filter is not confident.  Published on amcl_pose.
  Eigen::Matrix3d claim_covariance = Eigen::Matrix3d::Identity();
};

// Floors of the claim covariance's diagonal while the filter is not
// confident: far above any "converged" threshold (the demo's is
// cov_xx + cov_yy < 0.05 m^2).
constexpr double kUnconfidentVarianceXY = 1.0;                   // m^2
constexpr double kUnconfidentVarianceYaw = (kPi / 4) * (kPi / 4);  // rad^2

// Share of the scan's used (non-max-range) beams whose end points, seen from
// the robot at `pose`, lie within hit_dist of a mapped obstacle (off-map end
// points are unexplained).  *beams_used (if given) gets the beam count; 0
// beams give 0.
double ExplainedFraction(const MapModel& map, const PreparedScan& scan,
                         const Pose2& pose, double hit_dist,
                         int* beams_used = nullptr);

// What a scan tells about the pose, by direction: the information matrix of
// its explained beams at `pose` (Gauss-Newton's J^T J for the distance from
// each end point to the map's nearest obstacle), divided by the used beams.
// Beam i contributes J_i = (n_x, n_y, n . (z x r)), n the map's surface
// normal at its end point (the distance field's gradient just in front of
// the obstacle, towards the laser) and r the end point relative to the robot.
// Along a corridor with bare walls every n is across it: the along-corridor
// row is zero, the degenerate direction of Zhang, Kaess & Singh, "On
// degeneracy of optimization-based state estimation problems" (ICRA 2016).
// Beams whose end point is not within hit_dist of an obstacle, or whose
// normal is undefined (a corner, a one-cell pillar), add nothing.
Eigen::Matrix3d ScanInformation(const MapModel& map, const PreparedScan& scan,
                                const Pose2& pose, double hit_dist);

// The translation information left once the heading is marginalised (the
// Schur complement of the yaw entry): its smallest eigenvalue, the
// information in the least constrained direction (*direction, if given, a
// unit vector in the map frame).
double WeakestTranslationInformation(const Eigen::Matrix3d& information,
                                     Eigen::Vector2d* direction = nullptr);

struct Confidence {
  // Share of the used beams explained by the map at the estimate, in [0, 1];
  // 0 before the first correction after an initialization.
  double explained_fraction = 0.0;
  int beams_used = 0;         // beams the fraction is over
  int modes = 0;              // clusters holding 1 - confidence_mode_weight
  int evidence_updates = 0;   // see the header comment
  int lost_updates = 0;       // consecutive motion updates no mode explains
  // The information in the least constrained direction, summed over the
  // evidence updates (ScanInformation, WeakestTranslationInformation): a
  // claim needs confidence_min_constraint.  Infinite for a pose the user gave.
  double constraint = 0.0;
  bool confident = false;
};

// What the last map-wide search did (for logs and tests).
struct SearchReport {
  int count = 0;            // searches run so far (changes when one runs)
  bool relocalization = false;  // triggered by the lost test, not a request
  bool found_by_injection = false;  // ... because random draws found a place
  bool challenge = false;       // run before a claim (see Confidence above)
  double seconds = 0.0;      // wall
  double cpu_seconds = 0.0;  // of the calling thread (what the budget is about)
  std::vector<SearchCandidate> candidates;  // best first; empty: none found
};

// A seeded hypothesis (see "Hypotheses" in the header comment).
struct Hypothesis {
  SearchCandidate candidate;  // where the search put it, and its score
  double probability = 0.0;   // its particles' total weight
  int particles = 0;          // how many particles carry it
  bool refuted = false;       // probability fell below the refuted ratio
};

class AmclFilter {
 public:
  enum class Initialization {
    kFromOptions,      // Gaussian at initial_pose_* with initial_cov_*
    kGlobal,           // uniform over free space (global localization)
    kCurrentEstimate,  // SetMap only: Gaussian at the current estimate
  };

  // Validates the options, precomputes the map (distance field, free cells)
  // and initialises the particles.  Throws std::invalid_argument on invalid
  // options, a malformed map or one without free cells, or (kFromOptions)
  // an initial pose outside the map.
  AmclFilter(const AmclOptions& options, const OccupancyGrid& grid,
             Initialization init = Initialization::kFromOptions,
             uint64_t seed = 0x5eed);
  // Same with an already built map model (shared, e.g. between filters).
  AmclFilter(const AmclOptions& options, std::shared_ptr<const MapModel> map,
             Initialization init = Initialization::kFromOptions,
             uint64_t seed = 0x5eed);

  // Replaces the map (new distance field) and re-initialises the particles.
  // Throws (and keeps the old map and particles) like the constructor.
  void SetMap(const OccupancyGrid& grid,
              Initialization init = Initialization::kCurrentEstimate);

  // Gaussian initialization (amcl's initialpose): max_particles particles
  // drawn from N(mean, covariance).  Throws std::invalid_argument, leaving
  // the filter unchanged, if the mean is not finite or outside the map, or
  // the covariance is not finite, symmetric and positive semi-definite.
  void SetPose(const Pose2& mean, const Eigen::Matrix3d& covariance);

  // max_particles particles uniform over free space (amcl's
  // global_localization service); with the global search available, the
  // next Update() replaces them by the search's candidates.
  void GlobalLocalization();

  // Replaces the set by max_particles particles spread round the candidates
  // (Gaussian, 0.15 m / 0.1 rad; equal shares, weights proportional to the
  // scores) and restarts the evidence.  Ignored for an empty list.
  void SeedFromCandidates(const std::vector<SearchCandidate>& candidates);

  // The map-wide search (built with the map when global_search is on and the
  // map fits global_search_budget).  Null when not available; then
  // global_search_fallback() says why.
  const GlobalSearch* global_search() const {
    return search_ && search_->available() ? search_.get() : nullptr;
  }
  std::string global_search_fallback() const {
    return search_ ? search_->fallback_reason() : "no occupancy grid given";
  }
  const SearchReport& last_search() const { return last_search_; }
  // The hypotheses of the last seeding (empty after a pose, a uniform spread
  // or a map change), in the order of the candidates they were seeded from.
  const std::vector<Hypothesis>& hypotheses() const { return hypotheses_; }
  const Confidence& confidence() const { return confidence_; }

  // The next Update() corrects even if the robot has not moved (amcl's
  // request_nomotion_update service).
  void RequestNoMotionUpdate() { force_update_ = true; }

  // One filter step for a scan and the odometry pose of the robot base at
  // the scan's time stamp (see the header comment).
  UpdateResult Update(const Pose2& odom_pose, const LaserScan& scan);

  // Current pose estimate: heaviest cluster.  Always available (computed at
  // initialization and after every prediction / correction).
  const PoseEstimate& estimate() const { return estimate_; }
  // All hypotheses, heaviest first.
  const std::vector<PoseCluster>& clusters() const { return clusters_; }
  // The particle cloud (for publishing particlecloud); weights sum to 1.
  const std::vector<Particle>& particles() const { return particles_; }
  // amcl's convergence test: all particles within 0.5 m (x and y) of the
  // mean.  Enables beam skipping.
  bool converged() const { return converged_; }
  // Probability with which the next resampling injects random poses,
  // max(0, 1 - w_fast / w_slow); 0 when recovery is disabled.
  double InjectionProbability() const;
  // Odometry pose of the last applied update (valid after the first).
  bool has_odom_reference() const { return have_odom_; }
  const Pose2& odom_reference() const { return odom_ref_; }

  const AmclOptions& options() const { return options_; }
  const MapModel& map() const { return *map_; }
  const MotionModel& motion_model() const { return *motion_; }
  const SensorModel& sensor_model() const { return *sensor_; }

  // Heap bytes of the particle set and the filter's scratch buffers
  // (capacity-based), and of the map and sensor-model tables.
  size_t ParticleMemoryBytes() const;
  size_t MapMemoryBytes() const;

 private:
  void SampleGaussian(const Pose2& mean, const Eigen::Matrix3d& cov,
                      const MapModel& map, std::vector<Particle>* out);
  void ResetAfterInitialization(int evidence_updates);
  // Multiplies weights by exp(log_likelihoods_) and normalises; updates
  // w_slow / w_fast.  False (weights untouched) if no particle has a
  // positive finite likelihood.
  bool ApplyLikelihoods();
  void Resample();
  // Low-variance resampling of `count` particles into resample_buffer_,
  // each replaced by a free-space pose with probability inject_probability.
  // Returns the number of injected poses.
  int LowVarianceDraw(int count, double inject_probability);
  // After a resampling draw into resample_buffer_ (from particles_): keeps
  // hypothesis_min_particles on every hypothesis not refuted, with its
  // probability (see Hypotheses in the header comment).
  void KeepHypothesisFloors();
  // Hypotheses' probabilities and particle counts from particles_.
  void MeasureHypotheses();
  void UpdateConvergence();
  void UpdateEstimate();
  // After a correction: explained fraction, evidence, lost test.
  void UpdateConfidence(bool motion_update, const Pose2& odom_pose,
                        const LaserScan& scan);
  // Whether the robot at odom_pose sees from a new place: at least
  // update_min_d (in odometry) from every update counted in the current run
  // of evidence, or, for a laser with a blind sector wider than update_min_a,
  // turned by update_min_a from those within that distance.
  bool IsNewView(const Pose2& odom_pose, const LaserScan& scan) const;
  // The look-alike check before a claim (see Confidence above).
  void Challenge(const LaserScan& scan);
  // Modes' second moment and the confidence floors -> claim_covariance.
  void UpdateClaim();
  void RunSearch(const LaserScan& scan, bool relocalization);

  AmclOptions options_;
  std::shared_ptr<const MapModel> map_;
  std::unique_ptr<MotionModel> motion_;
  std::unique_ptr<SensorModel> sensor_;
  std::mt19937_64 rng_;

  std::vector<Particle> particles_;
  std::vector<Particle> resample_buffer_;
  std::vector<double> log_likelihoods_;
  std::vector<uint64_t> bin_scratch_;
  PreparedScan scan_;

  bool have_odom_ = false;
  Pose2 odom_ref_;
  bool force_update_ = false;
  int resample_count_ = 0;
  // Augmented MCL averages, in log space (likelihoods of a scan with many
  // beams are far below the smallest double).
  bool have_w_avg_ = false;
  double log_w_slow_ = 0.0;
  double log_w_fast_ = 0.0;
  bool converged_ = false;

  std::vector<PoseCluster> clusters_;
  PoseEstimate estimate_;

  std::shared_ptr<const GlobalSearch> search_;
  bool pending_search_ = false;
  bool pending_relocalization_ = false;
  bool pending_found_by_injection_ = false;
  SearchReport last_search_;
  std::vector<Hypothesis> hypotheses_;
  Confidence confidence_;
  bool measured_ = false;  // explained fraction measured since the last init
  int challenges_left_ = 0;  // look-alike checks left before the next claim
  // Odometry poses of the updates that counted in the current run of
  // evidence (IsNewView).
  std::vector<Pose2> evidence_views_;
  // Sum of ScanInformation over the same updates.
  Eigen::Matrix3d evidence_information_ = Eigen::Matrix3d::Zero();
};

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_AMCL_FILTER_H_
