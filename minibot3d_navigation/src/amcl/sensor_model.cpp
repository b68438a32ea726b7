#include "minibot3d_navigation/amcl/sensor_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace minibot3d_navigation {
namespace amcl {

bool PrepareScan(const LaserScan& scan, const AmclOptions& options,
                 PreparedScan* out, std::string* error) {
  std::ostringstream err;
  const size_t n = scan.ranges.size();
  if (n == 0) {
    err << "scan has no ranges";
  } else if (scan.angles.size() != n) {
    err << "scan has " << n << " ranges but " << scan.angles.size()
        << " angles";
  } else if (!IsFinite(scan.sensor_in_base)) {
    err << "laser pose (" << scan.sensor_in_base.x << ", " << scan.sensor_in_base.y
        << ", " << scan.sensor_in_base.yaw << ") is not finite";
  }
  double range_max = scan.range_max;
  if (options.laser_max_range > 0.0) {
    range_max = std::min(range_max, options.laser_max_range);
  }
  double range_min = scan.range_min;
  if (options.laser_min_range > 0.0) {
    range_min = std::max(range_min, options.laser_min_range);
  }
  if (err.tellp() == 0) {
    if (!(std::isfinite(range_max) && range_max > 0.0)) {
      err << "effective range_max=" << range_max << " must be finite and > 0";
    } else if (!(range_min < range_max)) {  // also rejects NaN range_min
      err << "effective range_min=" << range_min << " must be < range_max="
          << range_max;
    }
  }
  if (err.tellp() == 0) {
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(scan.angles[i])) {
        err << "beam " << i << " angle " << scan.angles[i] << " is not finite";
        break;
      }
    }
  }
  if (err.tellp() != 0) {
    if (error != nullptr) *error = err.str();
    return false;
  }

  // Evenly spaced subset of laser_max_beams beams, stride as amcl.
  const int max_beams = std::max(1, options.laser_max_beams);
  size_t step = 1;
  if (static_cast<size_t>(max_beams) < n) {
    step = max_beams == 1 ? n : std::max<size_t>(1, (n - 1) / (max_beams - 1));
  }
  out->beams.clear();
  out->beams.reserve(n / step + 1);
  out->range_max = range_max;
  out->range_min = range_min;
  out->sensor_in_base = scan.sensor_in_base;
  out->subsampled_count = 0;
  out->nan_count = 0;
  for (size_t i = 0; i < n; i += step) {
    ++out->subsampled_count;
    const double r = scan.ranges[i];
    if (std::isnan(r)) {
      ++out->nan_count;
      continue;
    }
    PreparedScan::Beam b;
    b.bearing = scan.angles[i];
    // amcl has no notion of a minimum range: a reading at or below it is "no
    // return" and is treated like a max-range reading.
    if (r <= range_min || r >= range_max) {
      b.range = range_max;
      b.is_max = true;
    } else {
      b.range = r;
      b.is_max = false;
    }
    out->beams.push_back(b);
  }
  return true;
}

namespace {

// Shared machinery of the two likelihood-field models.  A beam's
// contribution is a function of the cell its end point falls in only:
//   pz(cell) = z_hit * exp(-d(cell)^2 / 2 sigma^2) + z_rand / range_max
// and the models need pz^3 (likelihood_field) or log pz
// (likelihood_field_prob).  So f(pz) is tabulated per cell, and the per-beam
// work is a transform and a lookup.  The table depends on range_max through
// z_rand / range_max and is rebuilt only when that changes (normally once).
class LikelihoodFieldBase : public SensorModel {
 public:
  LikelihoodFieldBase(const AmclOptions& o, std::shared_ptr<const MapModel> map)
      : map_(std::move(map)),
        z_hit_(o.laser_z_hit),
        z_rand_(o.laser_z_rand),
        hit_denom_(2.0 * o.laser_sigma_hit * o.laser_sigma_hit),
        inv_resolution_(1.0 / map_->resolution()),
        width_(map_->width()),
        height_(map_->height()) {}

  int UsableBeamCount(const PreparedScan& scan) const override {
    int count = 0;
    for (const auto& b : scan.beams) count += b.is_max ? 0 : 1;
    return count;
  }

  size_t MemoryBytes() const override {
    return table_.capacity() * sizeof(double) +
           endpoints_.capacity() * sizeof(double);
  }

 protected:
  // f(pz) per beam: pz^3 or log(pz).
  virtual double BeamTerm(double pz) const = 0;

  // Tabulates BeamTerm for every cell and for "off the map" (where amcl
  // uses the capped maximum distance) for the scan's range_max, and
  // computes the beam end points in the robot base frame (laser pose
  // applied once per scan, not per particle), max-range readings excluded.
  void PrepareScanTables(const PreparedScan& scan) {
    const double rand_term = z_rand_ / scan.range_max;
    if (!(rand_term == table_rand_term_)) {
      table_.resize(static_cast<size_t>(width_) * height_);
      for (int j = 0; j < height_; ++j) {
        for (int i = 0; i < width_; ++i) {
          table_[static_cast<size_t>(j) * width_ + i] =
              BeamTerm(HitTerm(map_->Distance(i, j)) + rand_term);
        }
      }
      off_map_term_ = BeamTerm(HitTerm(map_->max_occ_dist()) + rand_term);
      table_rand_term_ = rand_term;
    }
    endpoints_.clear();
    const Pose2& lp = scan.sensor_in_base;
    for (const auto& b : scan.beams) {
      if (b.is_max) continue;
      const Pose2 e = Compose(lp, {b.range * std::cos(b.bearing),
                                    b.range * std::sin(b.bearing), 0.0});
      endpoints_.push_back(e.x);
      endpoints_.push_back(e.y);
    }
  }

  double HitTerm(double d) const {
    return z_hit_ * std::exp(-(d * d) / hit_denom_);
  }

  // Cell index of a grid-frame point, or -1 off the map.
  std::ptrdiff_t CellIndex(double gx, double gy) const {
    const double fi = gx * inv_resolution_, fj = gy * inv_resolution_;
    if (!(fi >= 0.0 && fj >= 0.0 && fi < width_ && fj < height_)) return -1;
    return static_cast<std::ptrdiff_t>(fj) * width_ +
           static_cast<std::ptrdiff_t>(fi);
  }

  // Calls visit(beam index, cell index or -1) for every end point of a
  // particle.  Inlined into the models' loops.
  template <typename Visit>
  void ForEachEndpoint(const Pose2& particle, Visit&& visit) const {
    const Pose2 g = map_->WorldToGridFrame(particle);
    const double c = std::cos(g.yaw), s = std::sin(g.yaw);
    const size_t nb = endpoints_.size() / 2;
    for (size_t b = 0; b < nb; ++b) {
      const double bx = endpoints_[2 * b], by = endpoints_[2 * b + 1];
      visit(b, CellIndex(g.x + c * bx - s * by, g.y + s * bx + c * by));
    }
  }

  size_t endpoint_count() const { return endpoints_.size() / 2; }
  double Term(std::ptrdiff_t idx) const {
    return idx < 0 ? off_map_term_ : table_[idx];
  }

  std::shared_ptr<const MapModel> map_;

 private:
  double z_hit_;
  double z_rand_;
  double hit_denom_;
  double inv_resolution_;
  int width_;
  int height_;
  std::vector<double> table_;
  double table_rand_term_ = std::numeric_limits<double>::quiet_NaN();
  double off_map_term_ = 0.0;
  std::vector<double> endpoints_;  // x0, y0, x1, y1, ...
};

class LikelihoodFieldModel : public LikelihoodFieldBase {
 public:
  using LikelihoodFieldBase::LikelihoodFieldBase;

  void ComputeLogLikelihoods(const PreparedScan& scan,
                             const std::vector<Particle>& particles,
                             bool /*filter_converged*/,
                             std::vector<double>* log_likelihoods) override {
    PrepareScanTables(scan);
    log_likelihoods->resize(particles.size());
    for (size_t k = 0; k < particles.size(); ++k) {
      double p = 1.0;
      ForEachEndpoint(particles[k].pose,
                      [&](size_t, std::ptrdiff_t idx) { p += Term(idx); });
      (*log_likelihoods)[k] = std::log(p);
    }
  }

  std::string name() const override { return "likelihood_field"; }

 protected:
  double BeamTerm(double pz) const override { return pz * pz * pz; }
};

class LikelihoodFieldProbModel : public LikelihoodFieldBase {
 public:
  LikelihoodFieldProbModel(const AmclOptions& o,
                           std::shared_ptr<const MapModel> map)
      : LikelihoodFieldBase(o, std::move(map)),
        do_beamskip_(o.do_beamskip),
        beam_skip_distance_(o.beam_skip_distance),
        beam_skip_threshold_(o.beam_skip_threshold),
        beam_skip_error_threshold_(o.beam_skip_error_threshold),
        independent_beams_(o.laser_independent_beams) {}

  void ComputeLogLikelihoods(const PreparedScan& scan,
                             const std::vector<Particle>& particles,
                             bool filter_converged,
                             std::vector<double>* log_likelihoods) override {
    PrepareScanTables(scan);
    const size_t nb = endpoint_count();
    const size_t np = particles.size();
    log_likelihoods->resize(np);
    // Beam skipping only makes sense once the particles agree on the pose;
    // before that "most particles disagree" says nothing about the beam.
    const bool skip = do_beamskip_ && filter_converged && np > 0 && nb > 0;
    if (!skip) {
      const double scale = Tempering(nb);
      for (size_t k = 0; k < np; ++k) {
        double log_p = 0.0;
        ForEachEndpoint(particles[k].pose, [&](size_t, std::ptrdiff_t idx) {
          log_p += Term(idx);
        });
        (*log_likelihoods)[k] = scale * log_p;
      }
      return;
    }

    // First pass: keep every log pz and count, per beam, the particles whose
    // end point lies within beam_skip_distance of a mapped obstacle.
    log_pz_.resize(np * nb);
    agree_count_.assign(nb, 0);
    const int width = map_->width();
    for (size_t k = 0; k < np; ++k) {
      double* row = &log_pz_[k * nb];
      ForEachEndpoint(particles[k].pose, [&](size_t b, std::ptrdiff_t idx) {
        row[b] = Term(idx);
        if (idx >= 0 && map_->Distance(static_cast<int>(idx % width),
                                       static_cast<int>(idx / width)) <
                            beam_skip_distance_) {
          ++agree_count_[b];
        }
      });
    }
    use_beam_.assign(nb, 0);
    size_t skipped = 0;
    for (size_t b = 0; b < nb; ++b) {
      if (agree_count_[b] / static_cast<double>(np) > beam_skip_threshold_) {
        use_beam_[b] = 1;
      } else {
        ++skipped;
      }
    }
    // Too many beams disagree with the map for every particle: more likely a
    // wrong convergence than a crowd of unmapped obstacles, so integrate all.
    // (Unlike amcl, max-range readings do not count as skipped beams here,
    // so open space cannot trigger this by itself.)
    const bool use_all = skipped >= nb * beam_skip_error_threshold_;
    const double scale = Tempering(use_all ? nb : nb - skipped);
    for (size_t k = 0; k < np; ++k) {
      const double* row = &log_pz_[k * nb];
      double log_p = 0.0;
      for (size_t b = 0; b < nb; ++b) {
        if (use_all || use_beam_[b]) log_p += row[b];
      }
      (*log_likelihoods)[k] = scale * log_p;
    }
  }

  std::string name() const override { return "likelihood_field_prob"; }

  size_t MemoryBytes() const override {
    return LikelihoodFieldBase::MemoryBytes() +
           log_pz_.capacity() * sizeof(double) +
           agree_count_.capacity() * sizeof(int) + use_beam_.capacity();
  }

 protected:
  double BeamTerm(double pz) const override { return std::log(pz); }

 private:
  // The factor on the sum of log pz over `used` beams: the scan counts as
  // laser_independent_beams independent beams (1 when that is 0, or when
  // fewer beams than that are used).
  double Tempering(size_t used) const {
    if (independent_beams_ <= 0.0 || used == 0) return 1.0;
    return std::min(1.0, independent_beams_ / static_cast<double>(used));
  }

  bool do_beamskip_;
  double beam_skip_distance_;
  double beam_skip_threshold_;
  double beam_skip_error_threshold_;
  double independent_beams_;
  std::vector<double> log_pz_;  // particle-major scratch for beam skipping
  std::vector<int> agree_count_;
  std::vector<char> use_beam_;
};

class BeamModel : public SensorModel {
 public:
  BeamModel(const AmclOptions& o, std::shared_ptr<const MapModel> map)
      : map_(std::move(map)),
        z_hit_(o.laser_z_hit),
        z_short_(o.laser_z_short),
        z_max_(o.laser_z_max),
        z_rand_(o.laser_z_rand),
        hit_denom_(2.0 * o.laser_sigma_hit * o.laser_sigma_hit),
        lambda_short_(o.laser_lambda_short) {}

  void ComputeLogLikelihoods(const PreparedScan& scan,
                             const std::vector<Particle>& particles,
                             bool /*filter_converged*/,
                             std::vector<double>* log_likelihoods) override {
    const double range_max = scan.range_max;
    log_likelihoods->resize(particles.size());
    for (size_t k = 0; k < particles.size(); ++k) {
      const Pose2 laser_world = Compose(particles[k].pose, scan.sensor_in_base);
      const Pose2 g = map_->WorldToGridFrame(laser_world);
      double p = 1.0;
      for (const auto& b : scan.beams) {
        const double expected =
            map_->CalcRangeGrid(g.x, g.y, g.yaw + b.bearing, range_max);
        const double z = b.range - expected;
        double pz = z_hit_ * std::exp(-(z * z) / hit_denom_);
        if (z < 0.0) {
          pz += z_short_ * lambda_short_ * std::exp(-lambda_short_ * b.range);
        }
        if (b.is_max) {
          pz += z_max_;
        } else {
          pz += z_rand_ / range_max;
        }
        p += pz * pz * pz;
      }
      (*log_likelihoods)[k] = std::log(p);
    }
  }

  int UsableBeamCount(const PreparedScan& scan) const override {
    return static_cast<int>(scan.beams.size());
  }
  std::string name() const override { return "beam"; }
  size_t MemoryBytes() const override { return 0; }

 private:
  std::shared_ptr<const MapModel> map_;
  double z_hit_;
  double z_short_;
  double z_max_;
  double z_rand_;
  double hit_denom_;
  double lambda_short_;
};

}  // namespace

std::unique_ptr<SensorModel> CreateSensorModel(
    const AmclOptions& options, std::shared_ptr<const MapModel> map) {
  if (map == nullptr) {
    throw std::invalid_argument("CreateSensorModel: map is null");
  }
  ValidateAmclOptions(options);  // names every bad laser_* parameter
  const std::string& type = options.laser_model_type;
  if (type == "likelihood_field") {
    return std::make_unique<LikelihoodFieldModel>(options, std::move(map));
  }
  if (type == "likelihood_field_prob") {
    return std::make_unique<LikelihoodFieldProbModel>(options, std::move(map));
  }
  if (type == "beam") {
    return std::make_unique<BeamModel>(options, std::move(map));
  }
  throw std::invalid_argument("laser_model_type='" + type + "' is unknown");
}

}  // namespace amcl
}  // namespace minibot3d_navigation
