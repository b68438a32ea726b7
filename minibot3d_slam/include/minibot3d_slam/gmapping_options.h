// Options of the RBPF SLAM core, named and defaulted as ROS gmapping's slam_gmapping parameters so
// existing YAML files work. One option table (GmappingOptionTable) reads them by name and
// documents them (docs/parameters/slam.md); ValidateOptions checks them in one place.
#ifndef MINIBOT3D_SLAM_GMAPPING_OPTIONS_H_
#define MINIBOT3D_SLAM_GMAPPING_OPTIONS_H_

#include <string>

#include "minibot3d_common/options.h"

namespace minibot3d_slam {

struct GmappingOptions {
  // Filter.
  int particles = 30;
  double resampleThreshold = 0.5;  // resample when N_eff < resampleThreshold · particles
  // Motion model (odometry noise: srr range from range, srt range from rotation, str rotation from
  // range, stt rotation from rotation).
  double srr = 0.1, srt = 0.2, str = 0.1, stt = 0.2;
  // When to process a scan.
  double linearUpdate = 1.0;    // m travelled
  double angularUpdate = 0.5;   // rad turned
  double temporalUpdate = -1.0;  // s since the last processed scan; < 0 disables
  bool stopUpdate = false;       // also the scan where the robot comes to rest
  // Scan matcher (the improved proposal).
  double sigma = 0.05;        // endpoint matching standard deviation (m)
  int kernelSize = 1;         // search window for the correspondence of an endpoint (cells)
  double lstep = 0.05;        // initial linear step of the hill climber (m)
  double astep = 0.05;        // initial angular step (rad)
  int iterations = 5;         // step halvings
  double lsigma = 0.075;      // likelihood sigma (m)
  double ogain = 3.0;         // gain smoothing the likelihood
  int lskip = 0;              // use every (lskip+1)-th beam for the likelihood
  double minimumScore = 0.0;  // below it, the scan match is not trusted (odometry used)
  // Wheel slip in turns: after a turn, when the match from the prediction is poor, the matcher
  // also climbs from the prediction turned back by this fraction of the odometry's turn since the
  // last processed scan (rbpf_slam.cpp); 0: from the prediction only. Not a gmapping parameter.
  double turnSlip = 0.5;
  // Sub-cell refinement of each matched pose (1) or the hill climber's pose as is (0); see
  // scan_matcher.h. Not a gmapping parameter.
  int subcellMatch = 1;
  // The improved proposal as the paper describes it (1): the new pose is drawn from a Gaussian
  // fitted to the likelihood around the match, weighted by the mean likelihood there. 0: as
  // gmapping's code does it — the matched pose itself, weighted by its likelihood. Not a gmapping
  // parameter.
  int sampleProposal = 0;
  // Sampling around the matched pose (sampleProposal = 1).
  double llsamplerange = 0.01, llsamplestep = 0.01;
  double lasamplerange = 0.005, lasamplestep = 0.005;
  // Map.
  double delta = 0.05;        // resolution (m)
  double maxUrange = 80.0;    // readings used to update the map are cut to this range (m)
  double maxRange = 0.0;      // beyond it a reading is a no-return; 0: the sensor's range_max
  // 1: a reading of +inf or at or beyond the maximum range (REP 117: nothing within the sensor's
  // reach along the beam) clears free space out to min(maxUrange, maximum range) and marks
  // nothing. That is what gmapping's documented recipe "maxUrange < range of the sensor <=
  // maxRange" is for, but gmapping's code drops such readings, and a lidar that reports no-returns
  // as +inf (as REP 117 says, and the simulator does) then leaves everything it sees no end of
  // unknown: down a corridor longer than its range the map stays unknown up to a metre or two
  // ahead of the robot, and frontier exploration creeps along in short hops. NaN, -inf and
  // readings at or below range_min still update nothing. 0: gmapping's behaviour. Not a gmapping
  // parameter (slam_toolbox's clear_max_range).
  int clearMaxRange = 0;
  double xmin = -100.0, ymin = -100.0, xmax = 100.0, ymax = 100.0;  // initial map extent
  double occ_thresh = 0.25;   // occupancy probability above which a cell is published occupied
  // Loop closure (loop_closer.h; not gmapping parameters): a pose graph of the best particle's
  // trajectory, revisits of older submaps found by a correlative search around the current
  // estimate, Ceres optimisation, the map rebuilt from the corrected trajectory.
  int loopClosure = 1;             // 1 on, 0 off (the plain RBPF)
  double loopSearchWindow = 4.0;   // m: half-width of the search square; also how close a submap must be
  // The window grows with the path driven since the submap ended (the front-end's drift grows
  // with it: round a building-sized loop the estimate comes back metres off): the half-width is
  // max(loopSearchWindow, loopDriftRate · path), at most loopMaxSearchWindow. Two constraints
  // confirming each other may likewise differ by loopDriftRate · the path between them.
  double loopDriftRate = 0.03;     // m of window per m of path (0: a fixed loopSearchWindow)
  double loopMaxSearchWindow = 20.0;  // m
  // 1: a match in a corridor seen along its axis (look-alike places on one line) still constrains
  // the pose across the corridor and the heading, with a weak constraint along it; 0: such
  // matches are dropped as ambiguous. Off by default: such a match cannot tell where along the
  // corridor the robot is, and on building-sized loops the weak constraints along it add more
  // error than they remove.
  int loopCorridors = 0;
  double loopSearchAngle = 0.35;   // rad: half-width of the heading window
  double loopMinScore = 0.6;       // correlative score (mean blurred occupancy at the endpoints) to accept
  // Largest share of a revisit match's scan endpoints that may fall where the submap saw free space
  // with no wall within two cells (1: no such check). A look-alike room or corridor bay that is
  // not the one the robot is in scores well on its walls but puts part of the scan inside its free
  // space.
  double loopMaxConflict = 0.1;
  int loopSubmapScans = 20;        // processed scans per submap
  double loopMinTravel = 10.0;     // m of path since a submap ended before the scan is matched against it
  // Random seed of the particle filter (for reproducible runs).
  unsigned seed = 0;
  // Threads matching the particles' scans (and slam_offline's second pass); 0: one per CPU core.
  // The result is the same for any count: each particle is matched on its own, and the random
  // draws are made afterwards in particle order. Not a gmapping parameter.
  int threads = 0;
};

// Throws std::invalid_argument naming each offending parameter and its value.
void ValidateOptions(const GmappingOptions& options);

// Sets one option from its gmapping name and a textual value ("particles", "30"). Throws
// std::invalid_argument naming an unknown parameter or a value that does not parse (a number
// must be finite).
void SetOption(GmappingOptions* options, const std::string& name, const std::string& value);

// The table behind SetOption: every option by its gmapping name, with its documentation.
const minibot3d_common::options::OptionTable<GmappingOptions>& GmappingOptionTable();

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_GMAPPING_OPTIONS_H_
