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

const options::OptionTable<O>& Table() {
  static const options::OptionTable<O> table(
      "AMCL",
      {Field("min_particles", &O::min_particles),
       Field("max_particles", &O::max_particles),
       Field("kld_err", &O::kld_err),
       Field("kld_z", &O::kld_z),
       Field("update_min_d", &O::update_min_d),
       Field("update_min_a", &O::update_min_a),
       Field("resample_interval", &O::resample_interval),
       Field("recovery_alpha_slow", &O::recovery_alpha_slow),
       Field("recovery_alpha_fast", &O::recovery_alpha_fast),
       Field("odom_model_type", &O::odom_model_type),
       Field("odom_alpha1", &O::odom_alpha1),
       Field("odom_alpha2", &O::odom_alpha2),
       Field("odom_alpha3", &O::odom_alpha3),
       Field("odom_alpha4", &O::odom_alpha4),
       Field("odom_alpha5", &O::odom_alpha5),
       Field("laser_model_type", &O::laser_model_type),
       Field("laser_max_beams", &O::laser_max_beams),
       Field("laser_z_hit", &O::laser_z_hit),
       Field("laser_z_short", &O::laser_z_short),
       Field("laser_z_max", &O::laser_z_max),
       Field("laser_z_rand", &O::laser_z_rand),
       Field("laser_sigma_hit", &O::laser_sigma_hit),
       Field("laser_lambda_short", &O::laser_lambda_short),
       Field("laser_likelihood_max_dist", &O::laser_likelihood_max_dist),
       Field("laser_min_range", &O::laser_min_range),
       Field("laser_max_range", &O::laser_max_range),
       Field("do_beamskip", &O::do_beamskip),
       Field("beam_skip_distance", &O::beam_skip_distance),
       Field("beam_skip_threshold", &O::beam_skip_threshold),
       Field("beam_skip_error_threshold", &O::beam_skip_error_threshold),
       Field("laser_independent_beams", &O::laser_independent_beams),
       Field("initial_pose_x", &O::initial_pose_x),
       Field("initial_pose_y", &O::initial_pose_y),
       Field("initial_pose_a", &O::initial_pose_a),
       Field("initial_cov_xx", &O::initial_cov_xx),
       Field("initial_cov_yy", &O::initial_cov_yy),
       Field("initial_cov_aa", &O::initial_cov_aa),
       Field("confidence_hit_dist", &O::confidence_hit_dist),
       Field("confidence_min_explained", &O::confidence_min_explained),
       Field("confidence_mode_weight", &O::confidence_mode_weight),
       Field("confidence_min_updates", &O::confidence_min_updates),
       Field("confidence_lost_updates", &O::confidence_lost_updates),
       Field("confidence_challenges", &O::confidence_challenges),
       Field("confidence_challenge_min_relative_score",
             &O::confidence_challenge_min_relative_score),
       Field("hypothesis_min_particles", &O::hypothesis_min_particles),
       Field("hypothesis_refuted_ratio", &O::hypothesis_refuted_ratio),
       Field("global_search", &O::global_search),
       Field("global_search_budget", &O::global_search_budget),
       Field("global_search_max_candidates", &O::global_search_max_candidates),
       Field("global_search_min_score", &O::global_search_min_score),
       Field("global_search_min_relative_score",
             &O::global_search_min_relative_score),
       Field("global_search_depth", &O::global_search_depth),
       Field("global_search_max_beams", &O::global_search_max_beams),
       Field("global_search_angular_step", &O::global_search_angular_step)});
  return table;
}

}  // namespace

void SetAmclOption(const std::string& name, const std::string& text,
                   AmclOptions* options) {
  Table().Set(name, text, options);
}

bool IsAmclOptionName(const std::string& name) { return Table().Has(name); }

std::vector<std::string> AmclOptionNames() { return Table().Names(); }

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
