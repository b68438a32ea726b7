#include "minibot3d_navigation/amcl/amcl_options.h"

#include <cmath>
#include <string>
#include <vector>

#include "minibot3d_common/options.h"

namespace options = minibot3d_common::options;

namespace minibot3d_navigation {
namespace amcl {
namespace {

using options::Field;
using options::Num;
using O = AmclOptions;

}  // namespace

const options::OptionTable<AmclOptions>& AmclOptionTable() {
  static const options::OptionTable<O> table(
      "amcl",
      {Field("min_particles", &O::min_particles,
             "Fewest particles KLD-sampling keeps."),
       Field("max_particles", &O::max_particles,
             "Most particles KLD-sampling keeps (also the size of a global spread)."),
       Field("kld_err", &O::kld_err,
             "KLD-sampling's bound on the error between the true and the sampled distribution."),
       Field("kld_z", &O::kld_z,
             "KLD-sampling's upper standard normal quantile, used directly as the quantile "
             "(as in ROS amcl; 0.99 is not a probability here)."),
       Field("update_min_d", &O::update_min_d,
             "Odometry travel (m, straight-line) since the last filter update that triggers the "
             "next one."),
       Field("update_min_a", &O::update_min_a,
             "Odometry rotation (rad) since the last filter update that triggers the next one."),
       Field("resample_interval", &O::resample_interval,
             "Sensor updates between resamplings."),
       Field("recovery_alpha_slow", &O::recovery_alpha_slow,
             "Decay rate of the long-term average likelihood for augmented-MCL recovery "
             "(random particles injected when the short-term average falls below it); 0 "
             "disables."),
       Field("recovery_alpha_fast", &O::recovery_alpha_fast,
             "Decay rate of the short-term average likelihood for augmented-MCL recovery; 0 "
             "disables."),
       Field("odom_model_type", &O::odom_model_type,
             "Odometry motion model: diff, diff-corrected, omni or omni-corrected (the "
             "-corrected models fix ROS amcl's historical noise formulas)."),
       Field("odom_alpha1", &O::odom_alpha1,
             "Expected rotation noise from the robot's rotation."),
       Field("odom_alpha2", &O::odom_alpha2,
             "Expected rotation noise from the robot's translation."),
       Field("odom_alpha3", &O::odom_alpha3,
             "Expected translation noise from the robot's translation."),
       Field("odom_alpha4", &O::odom_alpha4,
             "Expected translation noise from the robot's rotation."),
       Field("odom_alpha5", &O::odom_alpha5,
             "Expected sideways (strafe) noise from translation (omni models only)."),
       Field("laser_model_type", &O::laser_model_type,
             "Laser model: likelihood_field, likelihood_field_prob (with beam skipping and "
             "laser_independent_beams) or beam."),
       Field("laser_max_beams", &O::laser_max_beams,
             "Beams of each scan the filter uses, evenly spaced."),
       Field("laser_z_hit", &O::laser_z_hit, "Weight of the hit (Gaussian) term."),
       Field("laser_z_short", &O::laser_z_short,
             "Weight of the unexpected-short-reading term (beam model only)."),
       Field("laser_z_max", &O::laser_z_max,
             "Weight of the max-range term (beam model only)."),
       Field("laser_z_rand", &O::laser_z_rand, "Weight of the random-reading term."),
       Field("laser_sigma_hit", &O::laser_sigma_hit,
             "Standard deviation (m) of the hit term's Gaussian."),
       Field("laser_lambda_short", &O::laser_lambda_short,
             "Exponential decay rate of the short-reading term (beam model only)."),
       Field("laser_likelihood_max_dist", &O::laser_likelihood_max_dist,
             "Distance (m) to the nearest obstacle up to which the likelihood field is "
             "computed."),
       Field("laser_min_range", &O::laser_min_range,
             "Shortest reading (m) used; <= 0 uses the scan's range_min."),
       Field("laser_max_range", &O::laser_max_range,
             "Longest reading (m) used; <= 0 uses the scan's range_max."),
       Field("do_beamskip", &O::do_beamskip,
             "Skip beams most particles disagree with once the filter has converged "
             "(likelihood_field_prob only)."),
       Field("beam_skip_distance", &O::beam_skip_distance,
             "Distance (m) from the nearest obstacle beyond which a beam end point counts as "
             "unexplained for beam skipping."),
       Field("beam_skip_threshold", &O::beam_skip_threshold,
             "Fraction of particles that must explain a beam for it to be kept."),
       Field("beam_skip_error_threshold", &O::beam_skip_error_threshold,
             "Fraction of skipped beams above which beam skipping is abandoned for the scan "
             "(the filter is probably lost)."),
       Field("laser_independent_beams", &O::laser_independent_beams,
             "likelihood_field_prob only: the scan counts as this many independent beams (the "
             "log-likelihood sum is scaled by min(1, this / beams used)); 0: every beam is "
             "independent, as in ROS amcl."),
       Field("initial_pose_x", &O::initial_pose_x,
             "Initial pose mean, x (m, map frame)."),
       Field("initial_pose_y", &O::initial_pose_y,
             "Initial pose mean, y (m, map frame)."),
       Field("initial_pose_a", &O::initial_pose_a, "Initial pose mean, yaw (rad)."),
       Field("initial_cov_xx", &O::initial_cov_xx, "Initial pose variance in x (m^2)."),
       Field("initial_cov_yy", &O::initial_cov_yy, "Initial pose variance in y (m^2)."),
       Field("initial_cov_aa", &O::initial_cov_aa, "Initial pose variance in yaw (rad^2)."),
       Field("confidence_hit_dist", &O::confidence_hit_dist,
             "A beam end point within this distance (m) of a mapped obstacle counts as "
             "explained at the estimate; <= 0: 2 x laser_sigma_hit."),
       Field("confidence_min_explained", &O::confidence_min_explained,
             "Fraction of the used (non-max-range) beams that must be explained for the scan to "
             "count as explained."),
       Field("confidence_mode_weight", &O::confidence_mode_weight,
             "The particle set's modes are its heaviest clusters holding at least 1 - this of "
             "the weight; a claim needs exactly one mode."),
       Field("confidence_min_updates", &O::confidence_min_updates,
             "Consecutive updates, each from a new view (update_min_d of travel), with the scan "
             "explained and one mode before the filter claims a pose after global "
             "localization; 0: claim at once."),
       Field("confidence_min_constraint", &O::confidence_min_constraint,
             "Information the evidence updates must gather in the least constrained direction "
             "before a claim: the sum over the updates of the share of the used beams ending on "
             "a surface that faces it (squared cosine); 0 disables. Views along a bare corridor "
             "add about 0 along it."),
       Field("confidence_lost_updates", &O::confidence_lost_updates,
             "Consecutive motion-triggered updates with the scan unexplained after which the "
             "filter counts itself lost and (with global_search) seeds again from the "
             "map-wide search; 0 disables."),
       Field("confidence_challenges", &O::confidence_challenges,
             "Map-wide look-alike checks before the first claim after global localization or "
             "a re-seed; 0 disables."),
       Field("confidence_challenge_min_relative_score",
             &O::confidence_challenge_min_relative_score,
             "A look-alike place counts against a claim when it scores at least this fraction "
             "of the estimate's own place in that search."),
       Field("hypothesis_min_particles", &O::hypothesis_min_particles,
             "Particles every seeded hypothesis keeps through resampling until the evidence "
             "refutes it; 0: plain resampling."),
       Field("hypothesis_refuted_ratio", &O::hypothesis_refuted_ratio,
             "A hypothesis is refuted once its probability falls below this fraction of the "
             "most probable hypothesis's."),
       Field("global_search", &O::global_search,
             "Global localization seeds the filter from a map-wide correlative scan search; "
             "false: a uniform spread over free space, as ROS amcl."),
       Field("global_search_budget", &O::global_search_budget,
             "CPU time (s) a map-wide search may take; a larger map falls back to the uniform "
             "spread, saying why."),
       Field("global_search_max_candidates", &O::global_search_max_candidates,
             "Poses the filter is seeded with from one search."),
       Field("global_search_min_score", &O::global_search_min_score,
             "Lowest search score (mean occupancy probability at the beam end points, 0..1) of "
             "a candidate."),
       Field("global_search_min_relative_score", &O::global_search_min_relative_score,
             "Lowest score of a candidate as a fraction of the best candidate's."),
       Field("global_search_depth", &O::global_search_depth,
             "Branch-and-bound levels of the search (the coarsest covers 2^(depth-1) cells a "
             "side)."),
       Field("global_search_max_beams", &O::global_search_max_beams,
             "Returns (evenly spaced over the scan) the search matches at most."),
       Field("global_search_angular_step", &O::global_search_angular_step,
             "Heading step (rad) of the search; 0 derives it from the farthest return d as "
             "acos(1 - r^2 / 2d^2), about one cell at d.")});
  return table;
}

void SetAmclOption(const std::string& name, const std::string& text,
                   AmclOptions* options) {
  AmclOptionTable().Set(name, text, options);
}

bool IsAmclOptionName(const std::string& name) { return AmclOptionTable().Has(name); }

std::vector<std::string> AmclOptionNames() { return AmclOptionTable().Names(); }

const options::OptionTable<AmclNodeOptions>& AmclNodeOptionTable() {
  using N = AmclNodeOptions;
  static const options::OptionTable<N> table(
      "amcl",
      {Field("base_frame_id", &N::base_frame_id, "The robot's base frame."),
       Field("odom_frame_id", &N::odom_frame_id, "The odometry frame."),
       Field("global_frame_id", &N::global_frame_id,
             "The map frame: amcl publishes global_frame_id -> odom_frame_id."),
       Field("use_map_topic", &N::use_map_topic,
             "Subscribe to the map topic instead of calling the static_map service."),
       Field("first_map_only", &N::first_map_only,
             "Keep the first map received and ignore later ones."),
       Field("tf_broadcast", &N::tf_broadcast,
             "Publish the map -> odom transform (false: only amcl_pose)."),
       Field("transform_tolerance", &N::transform_tolerance,
             "Time (s) the published map -> odom transform is post-dated by, so that it stays "
             "valid until the next scan."),
       Field("save_pose_rate", &N::save_pose_rate,
             "Rate (Hz, wall clock) at which the estimate is stored in ~initial_pose_* and "
             "~initial_cov_* so a restart resumes from it; <= 0 disables."),
       Field("gui_publish_rate", &N::gui_publish_rate,
             "Largest rate (Hz) of the particlecloud visualisation; <= 0: every update.")});
  return table;
}

void ValidateAmclNodeOptions(const AmclNodeOptions& o) {
  options::Problems problems("amcl");
  problems.Require(!o.base_frame_id.empty(), "base_frame_id must not be empty");
  problems.Require(!o.odom_frame_id.empty(), "odom_frame_id must not be empty");
  problems.Require(!o.global_frame_id.empty(), "global_frame_id must not be empty");
  problems.NonNegative("transform_tolerance", o.transform_tolerance);
  problems.Finite("save_pose_rate", o.save_pose_rate);
  problems.Finite("gui_publish_rate", o.gui_publish_rate);
  problems.ThrowIfAny();
}

void ValidateAmclOptions(const AmclOptions& o) {
  options::Problems problems("AMCL");
  auto require = [&problems](bool ok, const std::string& what) {
    problems.Require(ok, what);
  };

  require(o.min_particles >= 1,
          "min_particles=" + std::to_string(o.min_particles) + " must be >= 1");
  require(o.max_particles >= 1,
          "max_particles=" + std::to_string(o.max_particles) + " must be >= 1");
  require(o.min_particles <= o.max_particles,
          "min_particles=" + std::to_string(o.min_particles) +
              " > max_particles=" + std::to_string(o.max_particles));
  problems.Positive("kld_err", o.kld_err);
  problems.Positive("kld_z", o.kld_z);
  problems.NonNegative("update_min_d", o.update_min_d);
  problems.NonNegative("update_min_a", o.update_min_a);
  require(o.resample_interval >= 1, "resample_interval=" +
                                        std::to_string(o.resample_interval) +
                                        " must be >= 1");
  problems.InUnitInterval("recovery_alpha_slow", o.recovery_alpha_slow);
  problems.InUnitInterval("recovery_alpha_fast", o.recovery_alpha_fast);
  // Augmented MCL injects when the short-term average falls below the
  // long-term one; with alpha_slow >= alpha_fast that test is inverted.
  if (o.recovery_alpha_slow > 0.0 && o.recovery_alpha_fast > 0.0) {
    require(o.recovery_alpha_slow < o.recovery_alpha_fast,
            "recovery_alpha_slow=" + Num(o.recovery_alpha_slow) +
                " must be < recovery_alpha_fast=" + Num(o.recovery_alpha_fast));
  }

  const std::string& odom = o.odom_model_type;
  require(odom == "diff" || odom == "diff-corrected" || odom == "omni" ||
              odom == "omni-corrected",
          "odom_model_type='" + odom +
              "' is not one of diff, diff-corrected, omni, omni-corrected");
  problems.NonNegative("odom_alpha1", o.odom_alpha1);
  problems.NonNegative("odom_alpha2", o.odom_alpha2);
  problems.NonNegative("odom_alpha3", o.odom_alpha3);
  problems.NonNegative("odom_alpha4", o.odom_alpha4);
  problems.NonNegative("odom_alpha5", o.odom_alpha5);

  const bool beam = o.laser_model_type == "beam";
  require(beam || o.laser_model_type == "likelihood_field" ||
              o.laser_model_type == "likelihood_field_prob",
          "laser_model_type='" + o.laser_model_type +
              "' is not one of likelihood_field, likelihood_field_prob, beam");
  require(o.laser_max_beams >= 1, "laser_max_beams=" +
                                      std::to_string(o.laser_max_beams) +
                                      " must be >= 1");
  problems.NonNegative("laser_z_hit", o.laser_z_hit);
  problems.NonNegative("laser_z_short", o.laser_z_short);
  problems.NonNegative("laser_z_max", o.laser_z_max);
  problems.NonNegative("laser_z_rand", o.laser_z_rand);
  // The likelihood-field models only use z_hit and z_rand; the beam model all
  // four.  A zero mixture makes every particle weight zero.
  const double z_sum = beam ? o.laser_z_hit + o.laser_z_short + o.laser_z_max +
                                  o.laser_z_rand
                            : o.laser_z_hit + o.laser_z_rand;
  require(z_sum > 0.0,
          std::string(beam ? "laser_z_hit+laser_z_short+laser_z_max+"
                             "laser_z_rand="
                           : "laser_z_hit+laser_z_rand=") +
              Num(z_sum) + " must be > 0");
  problems.Positive("laser_sigma_hit", o.laser_sigma_hit);
  problems.Positive("laser_lambda_short", o.laser_lambda_short);
  problems.Positive("laser_likelihood_max_dist", o.laser_likelihood_max_dist);
  problems.Finite("laser_min_range", o.laser_min_range);
  problems.Finite("laser_max_range", o.laser_max_range);
  if (o.laser_min_range > 0.0 && o.laser_max_range > 0.0) {
    require(o.laser_min_range < o.laser_max_range,
            "laser_min_range=" + Num(o.laser_min_range) +
                " must be < laser_max_range=" + Num(o.laser_max_range));
  }
  problems.NonNegative("beam_skip_distance", o.beam_skip_distance);
  problems.InUnitInterval("beam_skip_threshold", o.beam_skip_threshold);
  problems.InUnitInterval("beam_skip_error_threshold", o.beam_skip_error_threshold);
  problems.NonNegative("laser_independent_beams", o.laser_independent_beams);
  require(o.laser_independent_beams == 0.0 ||
              o.laser_model_type == "likelihood_field_prob",
          "laser_independent_beams=" + Num(o.laser_independent_beams) +
              " applies only to laser_model_type likelihood_field_prob (it is '" +
              o.laser_model_type + "'); set it to 0");

  problems.Finite("initial_pose_x", o.initial_pose_x);
  problems.Finite("initial_pose_y", o.initial_pose_y);
  problems.Finite("initial_pose_a", o.initial_pose_a);
  problems.NonNegative("initial_cov_xx", o.initial_cov_xx);
  problems.NonNegative("initial_cov_yy", o.initial_cov_yy);
  problems.NonNegative("initial_cov_aa", o.initial_cov_aa);

  problems.Finite("confidence_hit_dist", o.confidence_hit_dist);
  problems.InUnitInterval("confidence_min_explained", o.confidence_min_explained);
  require(std::isfinite(o.confidence_mode_weight) &&
              o.confidence_mode_weight >= 0.0 && o.confidence_mode_weight < 0.5,
          "confidence_mode_weight=" + Num(o.confidence_mode_weight) +
              " must be in [0, 0.5)");
  require(o.confidence_min_updates >= 0,
          "confidence_min_updates=" + std::to_string(o.confidence_min_updates) +
              " must be >= 0");
  problems.InUnitInterval("confidence_challenge_min_relative_score",
                o.confidence_challenge_min_relative_score);
  problems.NonNegative("confidence_min_constraint", o.confidence_min_constraint);
  require(o.confidence_challenges >= 0,
          "confidence_challenges=" + std::to_string(o.confidence_challenges) +
              " must be >= 0");
  require(o.confidence_lost_updates >= 0,
          "confidence_lost_updates=" +
              std::to_string(o.confidence_lost_updates) + " must be >= 0");
  require(o.hypothesis_min_particles >= 0 &&
              o.hypothesis_min_particles <= o.max_particles,
          "hypothesis_min_particles=" +
              std::to_string(o.hypothesis_min_particles) +
              " must be in [0, max_particles=" +
              std::to_string(o.max_particles) + "]");
  require(std::isfinite(o.hypothesis_refuted_ratio) &&
              o.hypothesis_refuted_ratio > 0.0 &&
              o.hypothesis_refuted_ratio < 1.0,
          "hypothesis_refuted_ratio=" + Num(o.hypothesis_refuted_ratio) +
              " must be in (0, 1)");
  problems.Positive("global_search_budget", o.global_search_budget);
  require(o.global_search_max_candidates >= 1,
          "global_search_max_candidates=" +
              std::to_string(o.global_search_max_candidates) + " must be >= 1");
  problems.InUnitInterval("global_search_min_score", o.global_search_min_score);
  problems.InUnitInterval("global_search_min_relative_score",
                o.global_search_min_relative_score);
  require(o.global_search_angular_step >= 0.0 &&
              o.global_search_angular_step <= 0.1,
          "global_search_angular_step=" +
              std::to_string(o.global_search_angular_step) +
              " must be in [0, 0.1] rad (0: derived from the farthest return)");
  require(o.global_search_max_beams >= 1,
          "global_search_max_beams=" +
              std::to_string(o.global_search_max_beams) + " must be >= 1");
  require(o.global_search_depth >= 1 && o.global_search_depth <= 12,
          "global_search_depth=" + std::to_string(o.global_search_depth) +
              " must be in [1, 12]");

  problems.ThrowIfAny();
}

}  // namespace amcl
}  // namespace minibot3d_navigation
