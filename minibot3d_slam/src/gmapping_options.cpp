// The gmapping options' table (names, parsing, documentation) and their validation
// (gmapping_options.h).
#include "minibot3d_slam/gmapping_options.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace minibot3d_slam {

namespace options = minibot3d_common::options;

const options::OptionTable<GmappingOptions>& GmappingOptionTable() {
  using options::Field;
  using O = GmappingOptions;
  static const options::OptionTable<O> table(
      "gmapping",
      {Field("particles", &O::particles,
             "Particles of the filter; each carries its own trajectory and map."),
       Field("resampleThreshold", &O::resampleThreshold,
             "Resample when the effective number of particles N_eff falls below this fraction "
             "of particles, in (0, 1]."),
       Field("srr", &O::srr,
             "Odometry noise: standard deviation of translation per metre translated (m/m), and "
             "0.3 x this sideways."),
       Field("srt", &O::srt,
             "Odometry noise: standard deviation of translation per radian turned (m/rad)."),
       Field("str", &O::str,
             "Odometry noise: standard deviation of rotation per metre translated (rad/m)."),
       Field("stt", &O::stt,
             "Odometry noise: standard deviation of rotation per radian turned (rad/rad)."),
       Field("linearUpdate", &O::linearUpdate,
             "Process a scan once the odometry has travelled this far (m, path length) since the "
             "last processed scan."),
       Field("angularUpdate", &O::angularUpdate,
             "Process a scan once the odometry has turned this much (rad, summed) since the last "
             "processed scan."),
       Field("temporalUpdate", &O::temporalUpdate,
             "Process a scan once more than this time (s) has passed since the last processed "
             "scan, even without motion; < 0 disables."),
       Field("stopUpdate", &O::stopUpdate,
             "Also process the scan at which the robot comes to rest (its odometry moved less than "
             "1 mm and 0.001 rad since the scan before) after moving 2 cm or 0.02 rad since the last "
             "processed scan: the map then holds the view from wherever the robot stopped."),
       Field("sigma", &O::sigma,
             "Width of the scan matcher's score: an endpoint at distance d (m) from its matched "
             "obstacle scores exp(-d^2 / sigma)."),
       Field("kernelSize", &O::kernelSize,
             "Half-width (cells) of the window around each endpoint searched for its matching "
             "obstacle; 0: the endpoint's cell only."),
       Field("lstep", &O::lstep, "Initial translation step (m) of the scan matcher's hill climb."),
       Field("astep", &O::astep, "Initial rotation step (rad) of the scan matcher's hill climb."),
       Field("iterations", &O::iterations,
             "Step halvings of the hill climb: when no step improves the score, both steps are "
             "halved, at most this many times, then the climb stops."),
       Field("lsigma", &O::lsigma,
             "Width of the likelihood that weights a particle: each matched endpoint adds "
             "-d^2 / lsigma to its log-likelihood (d in m), an unmatched one -0.5 / lsigma."),
       Field("ogain", &O::ogain,
             "Smoothing of the weights: a particle's weight is exp((l - l_max) / (ogain x "
             "particles)), l its log-likelihood summed since the last resampling."),
       Field("lskip", &O::lskip,
             "Beams skipped between two matched ones: every (lskip+1)-th beam is matched; all "
             "beams update the map."),
       Field("minimumScore", &O::minimumScore,
             "Scan-match score (sum of exp(-d^2 / sigma) over the endpoints) the match must "
             "exceed to be trusted; otherwise the particle keeps its odometry pose."),
       Field("turnSlip", &O::turnSlip,
             "Wheel slip in turns: when the match from a particle's predicted pose is poor after "
             "a turn, the scan matcher also starts from the prediction turned back by this "
             "fraction of the odometry's turn since the last processed scan and keeps that match "
             "when it scores at least 10 % higher; 0: the prediction only. Not in gmapping."),
       Field("subcellMatch", &O::subcellMatch,
             "1: each matched pose is refined below the cell size (point-to-line least squares); "
             "0: the hill climb's pose as is. Not in gmapping."),
       Field("sampleProposal", &O::sampleProposal,
             "1: the improved proposal as published (a pose drawn from a Gaussian fitted to the "
             "likelihood around the match, weighted by the mean likelihood there); 0: as "
             "gmapping's code (the matched pose, weighted by its likelihood). Not in gmapping."),
       Field("llsamplerange", &O::llsamplerange,
             "Half-width (m) in x and y of the poses sampled around the match (sampleProposal "
             "1)."),
       Field("llsamplestep", &O::llsamplestep,
             "Step (m) in x and y of the poses sampled around the match (sampleProposal 1)."),
       Field("lasamplerange", &O::lasamplerange,
             "Half-width (rad) in heading of the poses sampled around the match (sampleProposal "
             "1)."),
       Field("lasamplestep", &O::lasamplestep,
             "Step (rad) in heading of the poses sampled around the match (sampleProposal 1)."),
       Field("delta", &O::delta, "Map resolution (m per cell)."),
       Field("maxUrange", &O::maxUrange,
             "Readings up to this range (m) mark their endpoint and are matched; longer ones are "
             "cut to it and only clear free space."),
       Field("maxRange", &O::maxRange,
             "Readings at or beyond this range (m), or the scan's range_max if smaller, are "
             "no-returns and update nothing (see clearMaxRange); 0: the scan's range_max."),
       Field("clearMaxRange", &O::clearMaxRange,
             "1: a reading of +inf or at or beyond the maximum range clears free space out to "
             "maxUrange and marks nothing (slam_toolbox's clear_max_range); 0: it updates "
             "nothing, as in gmapping. Not in gmapping."),
       Field("xmin", &O::xmin,
             "Initial map extent, smallest x (m, map frame); the map grows beyond it as needed."),
       Field("ymin", &O::ymin,
             "Initial map extent, smallest y (m, map frame); the map grows beyond it as needed."),
       Field("xmax", &O::xmax,
             "Initial map extent, largest x (m, map frame); the map grows beyond it as needed."),
       Field("ymax", &O::ymax,
             "Initial map extent, largest y (m, map frame); the map grows beyond it as needed."),
       Field("occ_thresh", &O::occ_thresh,
             "A seen cell is published occupied (100) when more than this fraction of the beams "
             "that reached it ended in it, free (0) otherwise; unseen cells are -1."),
       Field("loopClosure", &O::loopClosure,
             "1: loop closure (the best particle's submaps searched for revisits, its trajectory "
             "optimised as a pose graph and the map rebuilt from it); 0: the plain filter. Not "
             "in gmapping."),
       Field("loopSearchWindow", &O::loopSearchWindow,
             "Smallest half-width (m) of the square searched for a revisit; a submap is searched "
             "when a pose of it lies within the window of the estimate."),
       Field("loopDriftRate", &O::loopDriftRate,
             "Growth of the search window (m per m of path since the submap ended or the last "
             "loop constraint), also the disagreement per m of path allowed between two "
             "constraints that confirm each other; 0: a fixed loopSearchWindow."),
       Field("loopMaxSearchWindow", &O::loopMaxSearchWindow,
             "Largest half-width (m) of the loop-closure search window."),
       Field("loopCorridors", &O::loopCorridors,
             "1: a match in a corridor seen along its axis still constrains the pose across it "
             "and the heading (weakly along it); 0: such matches are dropped as ambiguous."),
       Field("loopSearchAngle", &O::loopSearchAngle,
             "Half-width (rad) of the headings searched for a revisit."),
       Field("loopMinScore", &O::loopMinScore,
             "Lowest score of a revisit match (mean blurred occupancy of the submap at the "
             "scan's endpoints, 0 to 1)."),
       Field("loopMaxConflict", &O::loopMaxConflict,
             "Largest share of a revisit match's scan endpoints that may fall where the submap "
             "saw free space with no wall within two cells (0 to 1; 1: no such check)."),
       Field("loopSubmapScans", &O::loopSubmapScans, "Processed scans per submap."),
       Field("loopMinTravel", &O::loopMinTravel,
             "Path (m) driven since a submap ended before scans are matched against it."),
       Field("threads", &O::threads,
             "Threads matching the particles' scans (and slam_offline's second pass); 0: one per "
             "CPU core. Any count gives the same result."),
       Field("seed", &O::seed,
             "Seed of the filter's random draws: the same seed and input give the same map and "
             "trajectory.")});
  return table;
}

void SetOption(GmappingOptions* o, const std::string& name, const std::string& value) {
  const auto& table = GmappingOptionTable();
  GmappingOptions set = *o;
  table.Set(name, value, &set);
  // A YAML's .inf or .nan is no usable gmapping number; say so where it is written.
  for (const auto& f : table.fields()) {
    if (f.double_field != nullptr && name == f.name && !std::isfinite(set.*(f.double_field))) {
      throw std::invalid_argument("gmapping parameter " + name + ": cannot use '" + value +
                                  "' (not a finite number)");
    }
  }
  *o = set;
}

void ValidateOptions(const GmappingOptions& o) {
  options::Problems p("gmapping");
  const auto finite = [](double v) { return std::isfinite(v); };
  p.Check(o.particles >= 1, "particles", o.particles, ">= 1");
  p.Check(o.resampleThreshold > 0.0 && o.resampleThreshold <= 1.0, "resampleThreshold",
          o.resampleThreshold, "in (0, 1]");
  p.NonNegative("srr", o.srr);
  p.NonNegative("srt", o.srt);
  p.NonNegative("str", o.str);
  p.NonNegative("stt", o.stt);
  p.NonNegative("linearUpdate", o.linearUpdate);
  p.NonNegative("angularUpdate", o.angularUpdate);
  p.Check(finite(o.temporalUpdate), "temporalUpdate", o.temporalUpdate, "finite (< 0 disables)");
  p.Positive("sigma", o.sigma);
  p.Check(o.kernelSize >= 0 && o.kernelSize <= 100, "kernelSize", o.kernelSize, "in [0, 100]");
  p.NonNegative("lstep", o.lstep);
  p.NonNegative("astep", o.astep);
  p.Check(o.iterations >= 0 && o.iterations <= 100, "iterations", o.iterations, "in [0, 100]");
  p.Positive("lsigma", o.lsigma);
  p.Positive("ogain", o.ogain);
  p.Check(o.lskip >= 0, "lskip", o.lskip, ">= 0");
  p.Check(o.subcellMatch == 0 || o.subcellMatch == 1, "subcellMatch", o.subcellMatch, "0 or 1");
  p.Check(o.sampleProposal == 0 || o.sampleProposal == 1, "sampleProposal", o.sampleProposal,
          "0 or 1");
  p.Finite("minimumScore", o.minimumScore);
  p.InUnitInterval("turnSlip", o.turnSlip);
  p.NonNegative("llsamplerange", o.llsamplerange);
  p.NonNegative("lasamplerange", o.lasamplerange);
  // A step must be positive when it is used, and small enough that the sampled grid stays small.
  p.Check(o.llsamplerange == 0.0 || (o.llsamplestep > 0.0 && o.llsamplerange / o.llsamplestep <= 50.0),
          "llsamplestep", o.llsamplestep, "> 0 and >= llsamplerange / 50");
  p.Check(o.lasamplerange == 0.0 || (o.lasamplestep > 0.0 && o.lasamplerange / o.lasamplestep <= 50.0),
          "lasamplestep", o.lasamplestep, "> 0 and >= lasamplerange / 50");
  p.Positive("delta", o.delta);
  p.Positive("maxUrange", o.maxUrange);
  p.Check(o.maxRange == 0.0 || (o.maxRange >= o.maxUrange && finite(o.maxRange)), "maxRange",
          o.maxRange, "0 (the sensor's range_max) or >= maxUrange");
  p.Check(o.clearMaxRange == 0 || o.clearMaxRange == 1, "clearMaxRange", o.clearMaxRange, "0 or 1");
  const bool x_ok = finite(o.xmin) && finite(o.xmax) && o.xmin < o.xmax;
  const bool y_ok = finite(o.ymin) && finite(o.ymax) && o.ymin < o.ymax;
  p.Check(x_ok, "xmin", o.xmin, "< xmax");
  p.Check(x_ok, "xmax", o.xmax, "> xmin");
  p.Check(y_ok, "ymin", o.ymin, "< ymax");
  p.Check(y_ok, "ymax", o.ymax, "> ymin");
  if (o.delta > 0.0 && finite(o.delta) && o.xmin < o.xmax && o.ymin < o.ymax &&
      finite(o.xmax - o.xmin) && finite(o.ymax - o.ymin)) {
    // The initial extent is what Map() returns at least; keep it allocatable.
    const double cells = (o.xmax - o.xmin) / o.delta * ((o.ymax - o.ymin) / o.delta);
    p.Check(cells <= 4e8, "delta", o.delta,
            "large enough that (xmax-xmin)·(ymax-ymin)/delta² <= 4e8 cells");
  }
  p.Check(o.loopClosure == 0 || o.loopClosure == 1, "loopClosure", o.loopClosure, "0 or 1");
  p.Check(o.loopSearchWindow > 0.0 && o.loopSearchWindow <= 50.0, "loopSearchWindow",
          o.loopSearchWindow, "in (0, 50] m");
  p.Check(o.loopDriftRate >= 0.0 && o.loopDriftRate <= 1.0, "loopDriftRate", o.loopDriftRate,
          "in [0, 1] m per m");
  p.Check(o.loopMaxSearchWindow >= o.loopSearchWindow && o.loopMaxSearchWindow <= 100.0,
          "loopMaxSearchWindow", o.loopMaxSearchWindow, "in [loopSearchWindow, 100] m");
  p.Check(o.loopCorridors == 0 || o.loopCorridors == 1, "loopCorridors", o.loopCorridors, "0 or 1");
  p.Check(o.loopSearchAngle > 0.0 && o.loopSearchAngle <= M_PI, "loopSearchAngle",
          o.loopSearchAngle, "in (0, pi] rad");
  p.Check(o.loopMinScore > 0.0 && o.loopMinScore <= 1.0, "loopMinScore", o.loopMinScore,
          "in (0, 1]");
  p.InUnitInterval("loopMaxConflict", o.loopMaxConflict);
  p.Check(o.loopSubmapScans >= 2 && o.loopSubmapScans <= 1000, "loopSubmapScans",
          o.loopSubmapScans, "in [2, 1000]");
  p.Check(o.loopMinTravel >= 0.0 && finite(o.loopMinTravel), "loopMinTravel", o.loopMinTravel,
          ">= 0 m");
  p.InUnitInterval("occ_thresh", o.occ_thresh);
  p.Check(o.threads >= 0 && o.threads <= 256, "threads", o.threads,
          "in [0, 256] (0: one per CPU core)");
  p.ThrowIfAny();
}

}  // namespace minibot3d_slam
