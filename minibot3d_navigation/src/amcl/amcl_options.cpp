#include "minibot3d_navigation/amcl/amcl_options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace minibot3d_navigation {
namespace amcl {
namespace {

// One row of the option table; exactly one member pointer is non-null.  A
// table (rather than a chain of if/else) keeps SetAmclOption, the name list
// and IsAmclOptionName in sync with a single edit per new option.
struct OptionField {
  const char* name;
  int AmclOptions::*int_field;
  double AmclOptions::*double_field;
  bool AmclOptions::*bool_field;
  std::string AmclOptions::*string_field;
};

constexpr OptionField Int(const char* n, int AmclOptions::*f) {
  return {n, f, nullptr, nullptr, nullptr};
}
constexpr OptionField Dbl(const char* n, double AmclOptions::*f) {
  return {n, nullptr, f, nullptr, nullptr};
}
constexpr OptionField Bool(const char* n, bool AmclOptions::*f) {
  return {n, nullptr, nullptr, f, nullptr};
}
constexpr OptionField Str(const char* n, std::string AmclOptions::*f) {
  return {n, nullptr, nullptr, nullptr, f};
}

const OptionField kFields[] = {
    Int("min_particles", &AmclOptions::min_particles),
    Int("max_particles", &AmclOptions::max_particles),
    Dbl("kld_err", &AmclOptions::kld_err),
    Dbl("kld_z", &AmclOptions::kld_z),
    Dbl("update_min_d", &AmclOptions::update_min_d),
    Dbl("update_min_a", &AmclOptions::update_min_a),
    Int("resample_interval", &AmclOptions::resample_interval),
    Dbl("recovery_alpha_slow", &AmclOptions::recovery_alpha_slow),
    Dbl("recovery_alpha_fast", &AmclOptions::recovery_alpha_fast),
    Str("odom_model_type", &AmclOptions::odom_model_type),
    Dbl("odom_alpha1", &AmclOptions::odom_alpha1),
    Dbl("odom_alpha2", &AmclOptions::odom_alpha2),
    Dbl("odom_alpha3", &AmclOptions::odom_alpha3),
    Dbl("odom_alpha4", &AmclOptions::odom_alpha4),
    Dbl("odom_alpha5", &AmclOptions::odom_alpha5),
    Str("laser_model_type", &AmclOptions::laser_model_type),
    Int("laser_max_beams", &AmclOptions::laser_max_beams),
    Dbl("laser_z_hit", &AmclOptions::laser_z_hit),
    Dbl("laser_z_short", &AmclOptions::laser_z_short),
    Dbl("laser_z_max", &AmclOptions::laser_z_max),
    Dbl("laser_z_rand", &AmclOptions::laser_z_rand),
    Dbl("laser_sigma_hit", &AmclOptions::laser_sigma_hit),
    Dbl("laser_lambda_short", &AmclOptions::laser_lambda_short),
    Dbl("laser_likelihood_max_dist", &AmclOptions::laser_likelihood_max_dist),
    Dbl("laser_min_range", &AmclOptions::laser_min_range),
    Dbl("laser_max_range", &AmclOptions::laser_max_range),
    Bool("do_beamskip", &AmclOptions::do_beamskip),
    Dbl("beam_skip_distance", &AmclOptions::beam_skip_distance),
    Dbl("beam_skip_threshold", &AmclOptions::beam_skip_threshold),
    Dbl("beam_skip_error_threshold", &AmclOptions::beam_skip_error_threshold),
    Dbl("initial_pose_x", &AmclOptions::initial_pose_x),
    Dbl("initial_pose_y", &AmclOptions::initial_pose_y),
    Dbl("initial_pose_a", &AmclOptions::initial_pose_a),
    Dbl("initial_cov_xx", &AmclOptions::initial_cov_xx),
    Dbl("initial_cov_yy", &AmclOptions::initial_cov_yy),
    Dbl("initial_cov_aa", &AmclOptions::initial_cov_aa),
};

const OptionField* FindField(const std::string& name) {
  for (const OptionField& f : kFields) {
    if (name == f.name) return &f;
  }
  return nullptr;
}

std::string Trim(const std::string& s) {
  const char* ws = " \t\r\n";
  const size_t b = s.find_first_not_of(ws);
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(ws);
  return s.substr(b, e - b + 1);
}

[[noreturn]] void ThrowBadText(const std::string& name, const std::string& text,
                               const char* type) {
  throw std::invalid_argument("AMCL option " + name + ": cannot parse '" +
                              text + "' as " + type);
}

double ParseDouble(const std::string& name, const std::string& text) {
  const std::string t = Trim(text);
  if (t.empty()) ThrowBadText(name, text, "a number");
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE) {
    ThrowBadText(name, text, "a number");
  }
  return v;
}

int ParseInt(const std::string& name, const std::string& text) {
  const std::string t = Trim(text);
  if (t.empty()) ThrowBadText(name, text, "an integer");
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);  // NOLINT(runtime/int)
  if (end != t.c_str() + t.size() || errno == ERANGE ||
      v > std::numeric_limits<int>::max() ||
      v < std::numeric_limits<int>::min()) {
    ThrowBadText(name, text, "an integer");
  }
  return static_cast<int>(v);
}

bool ParseBool(const std::string& name, const std::string& text) {
  const std::string t = Trim(text);
  // YAML 1.1 spellings that rosparam accepts.
  if (t == "true" || t == "True" || t == "TRUE" || t == "1") return true;
  if (t == "false" || t == "False" || t == "FALSE" || t == "0") return false;
  ThrowBadText(name, text, "a boolean");
}

std::string Num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

void SetAmclOption(const std::string& name, const std::string& text,
                   AmclOptions* options) {
  const OptionField* f = FindField(name);
  if (f == nullptr) {
    throw std::invalid_argument("unknown AMCL option '" + name + "'");
  }
  if (f->int_field != nullptr) {
    options->*(f->int_field) = ParseInt(name, text);
  } else if (f->double_field != nullptr) {
    options->*(f->double_field) = ParseDouble(name, text);
  } else if (f->bool_field != nullptr) {
    options->*(f->bool_field) = ParseBool(name, text);
  } else {
    options->*(f->string_field) = Trim(text);
  }
}

bool IsAmclOptionName(const std::string& name) {
  return FindField(name) != nullptr;
}

std::vector<std::string> AmclOptionNames() {
  std::vector<std::string> names;
  for (const OptionField& f : kFields) names.emplace_back(f.name);
  return names;
}

void ValidateAmclOptions(const AmclOptions& o) {
  std::vector<std::string> errors;
  auto require = [&errors](bool ok, const std::string& what) {
    if (!ok) errors.push_back(what);
  };
  // Each double check also rejects NaN / inf: a comparison with NaN is false.
  auto positive = [&](const char* name, double v) {
    require(std::isfinite(v) && v > 0.0,
            std::string(name) + "=" + Num(v) + " must be > 0");
  };
  auto non_negative = [&](const char* name, double v) {
    require(std::isfinite(v) && v >= 0.0,
            std::string(name) + "=" + Num(v) + " must be >= 0");
  };
  auto unit_interval = [&](const char* name, double v) {
    require(std::isfinite(v) && v >= 0.0 && v <= 1.0,
            std::string(name) + "=" + Num(v) + " must be in [0, 1]");
  };
  auto finite = [&](const char* name, double v) {
    require(std::isfinite(v),
            std::string(name) + "=" + Num(v) + " must be finite");
  };

  require(o.min_particles >= 1,
          "min_particles=" + std::to_string(o.min_particles) + " must be >= 1");
  require(o.max_particles >= 1,
          "max_particles=" + std::to_string(o.max_particles) + " must be >= 1");
  require(o.min_particles <= o.max_particles,
          "min_particles=" + std::to_string(o.min_particles) +
              " > max_particles=" + std::to_string(o.max_particles));
  positive("kld_err", o.kld_err);
  positive("kld_z", o.kld_z);
  non_negative("update_min_d", o.update_min_d);
  non_negative("update_min_a", o.update_min_a);
  require(o.resample_interval >= 1, "resample_interval=" +
                                        std::to_string(o.resample_interval) +
                                        " must be >= 1");
  unit_interval("recovery_alpha_slow", o.recovery_alpha_slow);
  unit_interval("recovery_alpha_fast", o.recovery_alpha_fast);
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
  non_negative("odom_alpha1", o.odom_alpha1);
  non_negative("odom_alpha2", o.odom_alpha2);
  non_negative("odom_alpha3", o.odom_alpha3);
  non_negative("odom_alpha4", o.odom_alpha4);
  non_negative("odom_alpha5", o.odom_alpha5);

  const bool beam = o.laser_model_type == "beam";
  require(beam || o.laser_model_type == "likelihood_field" ||
              o.laser_model_type == "likelihood_field_prob",
          "laser_model_type='" + o.laser_model_type +
              "' is not one of likelihood_field, likelihood_field_prob, beam");
  require(o.laser_max_beams >= 1, "laser_max_beams=" +
                                      std::to_string(o.laser_max_beams) +
                                      " must be >= 1");
  non_negative("laser_z_hit", o.laser_z_hit);
  non_negative("laser_z_short", o.laser_z_short);
  non_negative("laser_z_max", o.laser_z_max);
  non_negative("laser_z_rand", o.laser_z_rand);
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
  positive("laser_sigma_hit", o.laser_sigma_hit);
  positive("laser_lambda_short", o.laser_lambda_short);
  positive("laser_likelihood_max_dist", o.laser_likelihood_max_dist);
  finite("laser_min_range", o.laser_min_range);
  finite("laser_max_range", o.laser_max_range);
  if (o.laser_min_range > 0.0 && o.laser_max_range > 0.0) {
    require(o.laser_min_range < o.laser_max_range,
            "laser_min_range=" + Num(o.laser_min_range) +
                " must be < laser_max_range=" + Num(o.laser_max_range));
  }
  non_negative("beam_skip_distance", o.beam_skip_distance);
  unit_interval("beam_skip_threshold", o.beam_skip_threshold);
  unit_interval("beam_skip_error_threshold", o.beam_skip_error_threshold);

  finite("initial_pose_x", o.initial_pose_x);
  finite("initial_pose_y", o.initial_pose_y);
  finite("initial_pose_a", o.initial_pose_a);
  non_negative("initial_cov_xx", o.initial_cov_xx);
  non_negative("initial_cov_yy", o.initial_cov_yy);
  non_negative("initial_cov_aa", o.initial_cov_aa);

  if (!errors.empty()) {
    std::string msg = "invalid AMCL options: ";
    for (size_t i = 0; i < errors.size(); ++i) {
      if (i > 0) msg += "; ";
      msg += errors[i];
    }
    throw std::invalid_argument(msg);
  }
}

}  // namespace amcl
}  // namespace minibot3d_navigation
