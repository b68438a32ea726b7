// Parameters of the ROS-free AMCL core.
//
// Names and defaults follow the ROS 1 `amcl` node (navigation stack) so that
// existing amcl YAML files can be loaded parameter by parameter through
// SetAmclOption().  See amcl_filter.h for the algorithm they configure
// (Thrun, Burgard & Fox, "Probabilistic Robotics" ch. 8; Fox, "KLD-sampling:
// Adaptive particle filters", 2003).
#ifndef MINIBOT3D_NAVIGATION_AMCL_AMCL_OPTIONS_H_
#define MINIBOT3D_NAVIGATION_AMCL_AMCL_OPTIONS_H_

#include <string>
#include <vector>

#include "minibot3d_common/options.h"
#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace amcl {

struct AmclOptions {
  // --- Filter (KLD-sampling, resampling, recovery) ---
  int min_particles = 100;
  int max_particles = 5000;
  double kld_err = 0.01;  // epsilon: max K-L error between true and sampled pdf
  // Upper standard normal quantile z_{1-delta}.  As in ROS amcl the value is
  // used directly as the quantile (0.99 is *not* a probability here).
  double kld_z = 0.99;
  // Odometry travel (metres, Euclidean) / rotation (radians) since the last
  // filter update before the next one.
  double update_min_d = 0.2;
  double update_min_a = kPi / 6.0;
  int resample_interval = 2;        // sensor updates between resamplings
  double recovery_alpha_slow = 0.0;  // 0 disables augmented-MCL injection
  double recovery_alpha_fast = 0.0;

  // --- Odometry model (see motion_model.h) ---
  // diff, diff-corrected, omni, omni-corrected
  std::string odom_model_type = "diff";
  double odom_alpha1 = 0.2;  // rotation noise from rotation
  double odom_alpha2 = 0.2;  // rotation noise from translation
  double odom_alpha3 = 0.2;  // translation noise from translation
  double odom_alpha4 = 0.2;  // translation noise from rotation
  double odom_alpha5 = 0.2;  // strafe noise from translation (omni only)

  // --- Laser model (see sensor_model.h) ---
  // likelihood_field, likelihood_field_prob, beam
  std::string laser_model_type = "likelihood_field";
  int laser_max_beams = 30;
  double laser_z_hit = 0.95;
  double laser_z_short = 0.1;
  double laser_z_max = 0.05;
  double laser_z_rand = 0.05;
  double laser_sigma_hit = 0.2;
  double laser_lambda_short = 0.1;
  double laser_likelihood_max_dist = 2.0;
  double laser_min_range = -1.0;  // <= 0: use the scan's range_min
  double laser_max_range = -1.0;  // <= 0: use the scan's range_max
  bool do_beamskip = false;
  double beam_skip_distance = 0.5;
  double beam_skip_threshold = 0.3;
  double beam_skip_error_threshold = 0.9;
  // likelihood_field_prob only (not in ROS amcl): the scan counts as this
  // many independent beams, i.e. the sum of log pz over the n used beams is
  // scaled by min(1, laser_independent_beams / n).  0: every beam is
  // independent (ROS amcl's product).  See sensor_model.h.
  double laser_independent_beams = 0.0;

  // --- Initial pose (Gaussian) ---
  double initial_pose_x = 0.0;
  double initial_pose_y = 0.0;
  double initial_pose_a = 0.0;
  double initial_cov_xx = 0.5 * 0.5;
  double initial_cov_yy = 0.5 * 0.5;
  double initial_cov_aa = (kPi / 12.0) * (kPi / 12.0);

  // --- Confidence: what the published covariance claims (not in ROS amcl; see
  // amcl_filter.h "Confidence") ---
  // A beam end point within this distance (m) of a mapped obstacle counts as
  // explained by the map at the estimate; <= 0: 2 * laser_sigma_hit (the
  // sensor model's own idea of a hit).
  double confidence_hit_dist = -1.0;
  // The scan counts as explained when at least this fraction of the used
  // (non-max-range) beams is.
  double confidence_min_explained = 0.8;
  // The modes of the particle set are its heaviest clusters that together hold
  // at least 1 - confidence_mode_weight of the weight; the lighter rest is
  // ignored.  One mode is needed for a claim.
  double confidence_mode_weight = 0.05;
  // Consecutive updates with the scan explained and one mode, each from a new
  // view (update_min_d of travel; amcl_filter.h "evidence"), before the
  // filter claims a pose after global localization (evidence over motion;
  // resampling alone earns nothing).  0: claim at once.
  int confidence_min_updates = 15;
  // Information the evidence updates must gather in the least constrained
  // direction (amcl_filter.h "constraint"): the sum over the updates of the
  // share of the used beams whose end points lie on a surface facing that
  // direction (weighted by the squared cosine).  Views of a room add about
  // 0.3 each, views along a bare corridor about 0 along it.  0 disables.
  double confidence_min_constraint = 1.0;
  // Consecutive motion-triggered updates with the scan not explained after
  // which the filter counts itself lost (kidnapped) and, with the global
  // search, seeds again from the map-wide search.  0 disables.
  int confidence_lost_updates = 8;
  // Map-wide look-alike checks before the first claim after a global
  // localization or re-seed (amcl_filter.h, "challenge"); 0 disables.
  int confidence_challenges = 1;
  // ... counting only places that score at least this fraction of the
  // estimate's own place in that search (of the best place found when the
  // estimate's is not among the candidates).  1.0: only places that explain
  // the view as well as the estimate or better; 0.9 also near look-alikes
  // (safer among identical rooms, at the cost of more travel before a claim;
  // docs/localization.md).
  double confidence_challenge_min_relative_score = 1.0;
  // Particles every seeded hypothesis keeps through resampling until the
  // evidence refutes it (amcl_filter.h, "Hypotheses"); 0: plain resampling,
  // where a light hypothesis can die by chance.
  int hypothesis_min_particles = 100;
  // A hypothesis is refuted (and loses its floor) once its probability falls
  // below this fraction of the most probable hypothesis's.
  double hypothesis_refuted_ratio = 1e-6;

  // --- Map-wide correlative search for global localization (see
  // global_search.h) ---
  bool global_search = true;            // false: uniform spread only (amcl)
  double global_search_budget = 1.0;    // s of CPU a search may take
  int global_search_max_candidates = 6; // poses the filter is seeded with
  double global_search_min_score = 0.4; // mean occupancy at the end points
  double global_search_min_relative_score = 0.7;  // of the best candidate
  int global_search_depth = 7;          // branch-and-bound levels
  // Returns the search matches at most (evenly spaced over the scan): its time
  // is nearly proportional to them.
  int global_search_max_beams = 120;
  // Heading step (rad) of the search lattice; 0 derives it from the farthest
  // return d (acos(1 - r^2 / 2d^2): about one cell at d, 0.24 deg at 12 m).
  // The search time is nearly proportional to the number of headings; the
  // filter refines the candidates, so a step that moves the farthest return
  // by two cells loses no candidate (tools/bench/global_loc_study.py checks
  // it).
  double global_search_angular_step = 0.012;
};

// Throws std::invalid_argument whose message lists every offending parameter
// with its value (not just the first), e.g. "invalid AMCL parameters:
// min_particles=600 > max_particles=500; laser_sigma_hit=-0.1 must be > 0".
void ValidateAmclOptions(const AmclOptions& options);

// Sets the option called `name` (ROS amcl parameter name) from its text form
// ("0.25", "500", "true", "likelihood_field").  Throws std::invalid_argument
// for an unknown name or text that does not parse as the option's type.  Does
// not validate ranges; call ValidateAmclOptions() once all are set.
void SetAmclOption(const std::string& name, const std::string& text,
                   AmclOptions* options);

// True if `name` is an option SetAmclOption() understands.  Lets the ROS node
// skip node-only parameters (frame ids, tf tolerances, ...) of a shared YAML.
bool IsAmclOptionName(const std::string& name);

// All option names, in declaration order.
std::vector<std::string> AmclOptionNames();

// The table behind the three functions above (names, parsing, the docs' reference).
const minibot3d_common::options::OptionTable<AmclOptions>& AmclOptionTable();

// The amcl node's own parameters (frames, tf, map source), ROS amcl's names and defaults.
struct AmclNodeOptions {
  std::string base_frame_id = "base_link";
  std::string odom_frame_id = "odom";
  std::string global_frame_id = "map";
  bool use_map_topic = false;
  bool first_map_only = false;
  bool tf_broadcast = true;
  double transform_tolerance = 0.1;  // s
  double save_pose_rate = 0.5;       // Hz
  double gui_publish_rate = -1.0;    // Hz
};

const minibot3d_common::options::OptionTable<AmclNodeOptions>& AmclNodeOptionTable();

// Throws std::invalid_argument naming every bad value.
void ValidateAmclNodeOptions(const AmclNodeOptions& options);

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_AMCL_OPTIONS_H_
