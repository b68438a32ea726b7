// Laser measurement models: the correction step of Monte Carlo localization.
//
// Three models with ROS amcl's laser_model_type names and parameters
// (Thrun, Burgard & Fox, "Probabilistic Robotics", ch. 6):
//
//  * "likelihood_field" (sec. 6.4): the end point of every used beam is
//    projected into the map; with d the distance from it to the nearest
//    obstacle (MapModel's precomputed field, off-map = max distance),
//      pz = z_hit * exp(-d^2 / (2 sigma_hit^2)) + z_rand / range_max
//    and, as amcl does, the beams are combined by the ad-hoc
//      p = 1 + sum pz^3
//    instead of the product, which keeps a few unexplained beams (people,
//    furniture) from zeroing a good particle.  Max-range readings are skipped.
//  * "likelihood_field_prob": same pz, combined as a true product
//    (sum of log pz), or, with laser_independent_beams = k > 0, as a
//    tempered product: the sum of log pz over the n used beams times
//    min(1, k / n), so the scan weighs as much as k independent beams.
//    Neighbouring beams are not independent (the same wall, the same map
//    error), and the full product makes the weight of a whole cloud hinge on
//    how well its best few particles happen to line up (the book's ch. 6
//    warns of this overconfidence of the independence assumption).
//    Unlike 1 + sum pz^3, which saturates, the geometric mean still tells a
//    look-alike that misses a few beams from the true place.
//    Plus optional beam skipping (do_beamskip): once the
//    filter has converged, a beam is only integrated if more than
//    beam_skip_threshold of the particles see its end point within
//    beam_skip_distance of an obstacle; if the fraction of skipped beams
//    reaches beam_skip_error_threshold the filter has probably converged to a
//    wrong pose and all beams are integrated again.
//  * "beam" (sec. 6.3): the expected range is ray-cast in the map for every
//    beam and particle; pz mixes z_hit (Gaussian around the expected range),
//    z_short (exponential, lambda_short, only for readings shorter than
//    expected), z_max (reading at range_max) and z_rand (uniform), combined
//    as p = 1 + sum pz^3 like amcl.
//
// Scan preprocessing (PrepareScan) mirrors amcl_node: the effective range_min
// is max(scan.range_min, laser_min_range) and range_max is
// min(scan.range_max, laser_max_range) when those options are > 0; readings
// <= range_min (including -inf) are treated as max-range readings ("no
// return"), readings >= range_max (including +inf) are max-range readings,
// NaN readings are dropped by every model.  laser_max_beams beams are used,
// evenly spaced over the scan (stride (n-1)/(max_beams-1) as amcl).
#ifndef MINIBOT3D_NAVIGATION_AMCL_SENSOR_MODEL_H_
#define MINIBOT3D_NAVIGATION_AMCL_SENSOR_MODEL_H_

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "minibot3d_navigation/amcl/amcl_options.h"
#include "minibot3d_navigation/amcl/occupancy_map.h"
#include "minibot3d_navigation/amcl/types.h"

namespace minibot3d_navigation {
namespace amcl {

// A scan after preprocessing and beam subsampling.
struct PreparedScan {
  struct Beam {
    double range;    // metres; == range_max for max-range readings
    double bearing;  // in the laser frame
    bool is_max;     // max-range (or below range_min) reading
  };
  std::vector<Beam> beams;  // subsampled, NaN readings already dropped
  double range_max = 0.0;   // effective
  double range_min = 0.0;   // effective
  Pose2 sensor_in_base;        // in the base frame
  int subsampled_count = 0;  // beams selected by laser_max_beams (incl. NaN)
  int nan_count = 0;         // of those, dropped as NaN
};

// Validates and preprocesses a scan (see the header comment).  Returns false
// and sets *error (state of *out unspecified) if the scan is unusable as a
// whole: no beams, ranges/angles size mismatch, non-finite angle or laser
// pose, effective range_max not finite and > 0, range_min >= range_max.
bool PrepareScan(const LaserScan& scan, const AmclOptions& options,
                 PreparedScan* out, std::string* error);

class SensorModel {
 public:
  virtual ~SensorModel() = default;

  // Sets (*log_likelihoods)[k] to log p(scan | particles[k]) up to an
  // additive constant shared by all particles (the filter only needs ratios,
  // and the per-update average likelihood for augmented MCL).
  // filter_converged enables beam skipping (likelihood_field_prob).
  virtual void ComputeLogLikelihoods(const PreparedScan& scan,
                                     const std::vector<Particle>& particles,
                                     bool filter_converged,
                                     std::vector<double>* log_likelihoods) = 0;

  // Number of beams of `scan` this model will actually use.  0 means the
  // scan carries no information for this model (e.g. all max-range readings
  // for a likelihood field) and the filter skips the correction.
  virtual int UsableBeamCount(const PreparedScan& scan) const = 0;

  // The laser_model_type name.
  virtual std::string name() const = 0;

  // Heap bytes held by the model (lookup tables, scratch buffers).
  virtual size_t MemoryBytes() const = 0;
};

// Creates the model named by options.laser_model_type, using the map's
// distance field / ray caster.  Throws std::invalid_argument for an unknown
// type or invalid laser parameters (the names and values are in the message).
std::unique_ptr<SensorModel> CreateSensorModel(
    const AmclOptions& options, std::shared_ptr<const MapModel> map);

}  // namespace amcl
}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_AMCL_SENSOR_MODEL_H_
