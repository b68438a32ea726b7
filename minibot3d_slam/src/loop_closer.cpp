// Loop closure for the RBPF (see loop_closer.h for the design).
#include "loop_closer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace minibot3d_slam {

namespace {

constexpr int kSubmapCacheSize = 4;

// Whether the places of an ambiguous match (the best first) all lie on one line through the best,
// at its heading: a corridor seen along its axis. *axis gets the line's direction.
bool OnOneLine(const std::vector<CorrelativeMatch>& found, Eigen::Vector2d* axis) {
  const CorrelativeMatch& match = found.front();
  *axis = Eigen::Vector2d(found[1].pose.x - match.pose.x, found[1].pose.y - match.pose.y).normalized();
  bool line = true;
  for (const CorrelativeMatch& other : found) {
    const Eigen::Vector2d d(other.pose.x - match.pose.x, other.pose.y - match.pose.y);
    line = line && std::fabs(axis->x() * d.y() - axis->y() * d.x()) <= LoopCloser::kAxisOffLine &&
           std::fabs(NormalizeAngle(other.pose.yaw - match.pose.yaw)) <= LoopCloser::kAxisTurn;
  }
  return line;
}

}  // namespace

LoopCloser::LoopCloser(const GmappingOptions& options, const ScanMatcher* matcher)
    : options_(options), matcher_(matcher) {
  search_options_.linear_search_window = options.loopSearchWindow;
  search_options_.angular_search_window = options.loopSearchAngle;
  search_options_.min_score = options.loopMinScore;
  search_options_.branch_and_bound_depth = 7;
  search_options_.unknown_probability = 0.1;
  search_options_.blur_sigma = options.delta;
  // Angular step: one cell of motion at kAngularStepRange metres (the default, one cell at the
  // farthest endpoint, makes hundreds of angles for a long-range laser).
  search_options_.angular_step = std::acos(1.0 - options.delta * options.delta /
                                                     (2.0 * kAngularStepRange * kAngularStepRange));
  // Two candidates tell an ambiguous match from a clear one; telling a corridor from other
  // look-alikes takes a third (which also slows the search down).
  search_options_.max_candidates = options.loopCorridors != 0 ? kMaxCandidates : 2;
  search_options_.min_relative_score = kAmbiguityRatio;
  search_options_.min_separation_linear = kAmbiguitySeparation;
  search_options_.min_separation_angular = M_PI;  // any heading at another place is another place
  CheckCorrelativeSearchOptions(search_options_);
}

void LoopCloser::AddNode(const PreparedScan& scan) {
  StoredScan s;
  s.sensor_in_base = scan.sensor_in_base;
  const std::size_t n = scan.map_range.size();
  if (scan.map_beam.size() != n || scan.map_hit.size() != n || scan.map_cos.size() != n || scan.map_sin.size() != n) {
    throw std::invalid_argument("LoopCloser::AddNode: inconsistent PreparedScan");
  }
  // The directions go into the current table when they agree with it (a new table when the laser
  // geometry changed: another beam count or angles).
  const auto fits = [&](const Directions& d) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t b = scan.map_beam[i];
      if (b >= d.cos.size() || std::isnan(d.cos[b])) continue;
      if (d.cos[b] != static_cast<float>(scan.map_cos[i]) || d.sin[b] != static_cast<float>(scan.map_sin[i])) {
        return false;
      }
    }
    return true;
  };
  if (!directions_ || !fits(*directions_)) {
    directions_ = std::make_shared<Directions>();
    ++direction_tables_;
  }
  Directions& d = *directions_;
  const std::size_t before = d.cos.capacity();
  s.range.resize(n);
  s.beam_hit.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t b = scan.map_beam[i];
    if (b > (std::numeric_limits<std::uint32_t>::max() >> 1)) {
      throw std::invalid_argument("LoopCloser::AddNode: more than 2^31 beams in a scan");
    }
    if (b >= d.cos.size()) {
      d.cos.resize(b + 1, std::numeric_limits<float>::quiet_NaN());
      d.sin.resize(b + 1, std::numeric_limits<float>::quiet_NaN());
    }
    d.cos[b] = static_cast<float>(scan.map_cos[i]);
    d.sin[b] = static_cast<float>(scan.map_sin[i]);
    s.range[i] = static_cast<float>(scan.map_range[i]);
    s.beam_hit[i] = static_cast<std::uint32_t>(b << 1) | (scan.map_hit[i] != 0 ? 1u : 0u);
  }
  direction_bytes_ += (d.cos.capacity() - before) * 2 * sizeof(float);
  s.directions = directions_;
  const double c = std::cos(scan.sensor_in_base.yaw), si = std::sin(scan.sensor_in_base.yaw);
  newest_points_.clear();
  for (std::size_t i = 0; i < scan.match_range.size(); ++i) {
    const double lx = scan.match_range[i] * scan.match_cos[i], ly = scan.match_range[i] * scan.match_sin[i];
    newest_points_.emplace_back(static_cast<float>(scan.sensor_in_base.x + c * lx - si * ly),
                                static_cast<float>(scan.sensor_in_base.y + si * lx + c * ly));
  }
  scans_.push_back(std::move(s));
  path_.push_back(0.0);  // filled in by Detect, which sees the poses
}

std::size_t LoopCloser::ScanBytes() const {
  std::size_t bytes = 0;
  for (const StoredScan& s : scans_) {
    bytes += sizeof(StoredScan) + s.range.capacity() * sizeof(float) + s.beam_hit.capacity() * sizeof(std::uint32_t);
  }
  return bytes + direction_bytes_ + direction_tables_ * sizeof(Directions) +
         newest_points_.capacity() * sizeof(Eigen::Vector2f);
}

void LoopCloser::Render(const StoredScan& s, const Pose2& pose, Grid* grid) const {
  const Pose2 lp = Compose(pose, s.sensor_in_base);
  const double c = std::cos(lp.yaw), sn = std::sin(lp.yaw);
  for (std::size_t i = 0; i < s.range.size(); ++i) {
    const double dx = c * s.Cos(i) - sn * s.Sin(i);
    const double dy = sn * s.Cos(i) + c * s.Sin(i);
    const double r = s.range[i];
    grid->TraceRay(lp.x, lp.y, lp.x + r * dx, lp.y + r * dy, s.Hit(i));
  }
}

void LoopCloser::RenderMap(const std::vector<Pose2>& trajectory, Grid* grid) const {
  const std::size_t n = std::min(trajectory.size(), scans_.size());
  for (std::size_t i = 0; i < n; ++i) Render(scans_[i], trajectory[i], grid);
}

LoopCloser::RenderedSubmap* LoopCloser::Submap(int index, const std::vector<Pose2>& trajectory) {
  const int first = index * options_.loopSubmapScans;
  const int last = std::min(first + options_.loopSubmapScans, size());
  const auto at_current_poses = [&](const RenderedSubmap& r) {
    for (int i = first; i < last; ++i) {
      const Pose2& a = r.poses[static_cast<std::size_t>(i - first)];
      if (a.x != trajectory[i].x || a.y != trajectory[i].y || a.yaw != trajectory[i].yaw) return false;
    }
    return true;
  };
  for (auto it = cache_.begin(); it != cache_.end(); ++it) {
    if ((*it)->index != index) continue;
    if (!at_current_poses(**it)) {  // rendered from another history: render again
      cache_.erase(it);
      break;
    }
    cache_.splice(cache_.begin(), cache_, it);
    return cache_.front().get();
  }
  auto submap = std::make_unique<RenderedSubmap>(options_.delta);
  submap->index = index;
  for (int i = first; i < last; ++i) {
    Render(scans_[i], trajectory[i], &submap->grid);
    submap->poses.push_back(trajectory[i]);
  }
  int ix0, iy0, ix1, iy1;
  if (!submap->grid.AllocatedBounds(&ix0, &iy0, &ix1, &iy1)) return nullptr;
  GridMap map;
  map.resolution = options_.delta;
  map.origin_x = ix0 * options_.delta;
  map.origin_y = iy0 * options_.delta;
  map.width = ix1 - ix0 + 1;
  map.height = iy1 - iy0 + 1;
  map.data.assign(static_cast<std::size_t>(map.width) * map.height, -1);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const GridCell& c = submap->grid.At(ix0 + x, iy0 + y);
      if (c.visits == 0) continue;
      map.data[static_cast<std::size_t>(y) * map.width + x] =
          static_cast<std::int8_t>(std::lround(100.0 * c.hits / c.visits));
    }
  }
  submap->search = std::make_unique<CorrelativeSearch>(map, search_options_);
  cache_.push_front(std::move(submap));
  while (static_cast<int>(cache_.size()) > kSubmapCacheSize) cache_.pop_back();
  return cache_.front().get();
}

double LoopCloser::SearchWindow(double path) const {
  return std::min(options_.loopMaxSearchWindow, std::max(options_.loopSearchWindow, options_.loopDriftRate * path));
}

std::vector<LoopCloser::SubmapCandidate> LoopCloser::Candidates(
    const std::vector<Pose2>& trajectory) const {
  const int cur = size() - 1;
  const Pose2& here = trajectory[cur];
  const int per = options_.loopSubmapScans;
  const int finished = size() / per;  // submaps [k·per, (k+1)·per) with every node present
  std::vector<SubmapCandidate> candidates;
  for (int k = 0; k < finished; ++k) {
    const int last = (k + 1) * per - 1;
    if (last >= cur || path_[cur] - path_[last] < options_.loopMinTravel) continue;
    // The drift to expect is the path since the submap ended or, when a loop constraint has tied
    // the trajectory to the map since, the path since that constraint.
    const double window = SearchWindow(path_[cur] - std::max(path_[last], anchored_path_));
    double best = std::numeric_limits<double>::infinity();
    for (int i = k * per; i <= last; ++i) {
      best = std::min(best, std::hypot(trajectory[i].x - here.x, trajectory[i].y - here.y));
    }
    if (best <= window) candidates.push_back({best, k, window});
  }
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

PreparedScan LoopCloser::MatchingBeams(const StoredScan& s) {
  PreparedScan prepared;
  prepared.sensor_in_base = s.sensor_in_base;
  for (std::size_t i = 0; i < s.range.size(); ++i) {
    if (!s.Hit(i)) continue;
    prepared.match_range.push_back(s.range[i]);
    prepared.match_cos.push_back(s.Cos(i));
    prepared.match_sin.push_back(s.Sin(i));
  }
  return prepared;
}

bool LoopCloser::Detect(const std::vector<Pose2>& trajectory) {
  if (trajectory.size() != scans_.size()) {
    throw std::invalid_argument("LoopCloser::Detect: " + std::to_string(trajectory.size()) + " poses for " +
                                std::to_string(scans_.size()) + " nodes");
  }
  const int cur = size() - 1;
  if (cur <= 0) return false;
  const Pose2& here = trajectory[cur];
  path_[cur] = path_[cur - 1] + std::hypot(here.x - trajectory[cur - 1].x, here.y - trajectory[cur - 1].y);
  if (cur % kSearchEvery != 0) return false;
  const std::vector<SubmapCandidate> candidates = Candidates(trajectory);

  std::vector<Eigen::Vector2d> points;
  points.reserve(newest_points_.size());
  for (const Eigen::Vector2f& p : newest_points_) points.push_back(p.cast<double>());
  if (points.empty()) return false;
  // The matching beams, for the refinement on the submap's grid.
  const PreparedScan prepared = MatchingBeams(scans_[cur]);
  for (std::size_t searched = 0; searched < candidates.size() && searched < kMaxSearchesPerScan; ++searched) {
    LoopConstraint c;
    Pose2 refined;
    if (Match(candidates[searched], trajectory, points, prepared, &c, &refined)) {
      AddConstraint(c, refined, candidates[searched].window, trajectory);
    }
  }
  // Tentative constraints expire after kTentativeNodes processed scans.
  tentative_.erase(std::remove_if(tentative_.begin(), tentative_.end(),
                                  [&](const LoopConstraint& t) { return cur - t.to > kTentativeNodes; }),
                   tentative_.end());
  return pending_ > 0 && (big_pending_ || size() - last_optimized_ >= kOptimizeEvery);
}

double LoopCloser::Conflict(const StoredScan& s, const Pose2& pose, const Grid& grid) {
  const Pose2 lp = Compose(pose, s.sensor_in_base);
  const double c = std::cos(lp.yaw), sn = std::sin(lp.yaw);
  int observed = 0, conflicts = 0;
  for (std::size_t i = 0; i < s.range.size(); ++i) {
    if (!s.Hit(i)) continue;
    const double dx = c * s.Cos(i) - sn * s.Sin(i);
    const double dy = sn * s.Cos(i) + c * s.Sin(i);
    const int ix = grid.CellX(lp.x + s.range[i] * dx), iy = grid.CellY(lp.y + s.range[i] * dy);
    const GridCell& cell = grid.At(ix, iy);
    if (cell.visits == 0) continue;  // the submap did not see there: no opinion
    ++observed;
    // A wall, or free space seen by one beam only (too little to call a contradiction).
    if (cell.Occupied() || cell.visits < 2) continue;
    bool wall_near = false;
    for (int y = iy - kConflictCells; y <= iy + kConflictCells && !wall_near; ++y) {
      for (int x = ix - kConflictCells; x <= ix + kConflictCells && !wall_near; ++x) {
        const GridCell& n = grid.At(x, y);
        wall_near = n.visits > 0 && n.Occupied();
      }
    }
    if (!wall_near) ++conflicts;
  }
  return observed > 0 ? static_cast<double>(conflicts) / observed : 0.0;
}

bool LoopCloser::Match(const SubmapCandidate& cand, const std::vector<Pose2>& trajectory,
                       const std::vector<Eigen::Vector2d>& points, const PreparedScan& prepared,
                       LoopConstraint* c, Pose2* refined_pose) {
  const int cur = size() - 1;
  const Pose2& here = trajectory[cur];
  RenderedSubmap* submap = Submap(cand.submap, trajectory);
  if (submap == nullptr) return false;
  ++searches_;
  // The two best places at least kAmbiguitySeparation apart: a second one scoring nearly as well
  // (a corridor seen along its axis, twin rooms) makes the match ambiguous, and it is dropped.
  CorrelativeSearchOptions search = search_options_;
  search.linear_search_window = cand.window;
  const std::vector<CorrelativeMatch> found = submap->search->SearchAll(points, here, search);
  if (found.empty()) return false;
  const CorrelativeMatch& match = found.front();
  // Several places: a corridor seen along its axis when they are all on one line at one heading.
  Eigen::Vector2d axis(1.0, 0.0);
  const bool along_axis = found.size() > 1;
  if (along_axis && (options_.loopCorridors == 0 || !OnOneLine(found, &axis))) {
    ++ambiguous_;
    return false;
  }
  // The part of a displacement the match measures: all of it, or across the corridor.
  const auto measured = [&](double dx, double dy) {
    if (!along_axis) return std::hypot(dx, dy);
    return std::fabs(axis.x() * dy - axis.y() * dx);
  };
  // Polish the lattice pose on the submap's own grid (the RBPF's matcher: hill climber from the
  // lattice pose, then sub-cell refinement); a refinement that wanders off means the match was
  // not a clear one.
  Pose2 climbed;
  matcher_->Optimize(submap->grid, prepared, match.pose, &climbed);
  Pose2 refined = matcher_->Refine(submap->grid, prepared, climbed);
  if (measured(refined.x - match.pose.x, refined.y - match.pose.y) > 3.0 * options_.delta ||
      std::fabs(NormalizeAngle(refined.yaw - match.pose.yaw)) > 0.05) {
    return false;
  }
  // Free-space check: a look-alike place scores well on its walls but has part of this scan end
  // where it saw through.
  if (Conflict(scans_[cur], refined, submap->grid) > options_.loopMaxConflict) {
    ++conflicting_;
    return false;
  }
  if (along_axis) {
    // Along the corridor the match says nothing: keep the estimate's position there.
    const double t = axis.x() * (here.x - refined.x) + axis.y() * (here.y - refined.y);
    refined.x += t * axis.x();
    refined.y += t * axis.y();
  }
  const int anchor = cand.submap * options_.loopSubmapScans;
  c->from = anchor;
  c->to = cur;
  c->measurement = Between(trajectory[anchor], refined);
  c->score = match.score;
  c->correction = Compose(refined, Between(here, Pose2{}));
  c->along_axis = along_axis;
  c->axis = NormalizeAngle(std::atan2(axis.y(), axis.x()) - trajectory[anchor].yaw);
  *refined_pose = refined;
  return true;
}

// The rigid correction of the map t implies puts this scan within a third of kBigCorrection of
// where its own match puts it, plus the drift the front-end may have made between the two scans
// and between the two submaps (loopDriftRate per metre of path, a tenth of that in radians). A
// corridor constraint measures only across its corridor (and the heading): compared with a full
// one, only that component counts, and it vouches for no other constraint — a large correction
// always has a full match behind it (two corridor constraints agreeing across parallel corridors
// would leave the claim along them unchecked).
LoopCloser::Agreement LoopCloser::Agree(const LoopConstraint& c, const Pose2& refined,
                                        const LoopConstraint& t,
                                        const std::vector<Pose2>& trajectory) const {
  Agreement r;
  const auto corridor = [&](const LoopConstraint& k) { return k.axis + trajectory[k.from].yaw; };
  r.vouches_for_t = !c.along_axis;
  r.t_vouches = !t.along_axis;
  if (!r.vouches_for_t && !r.t_vouches) return r;
  const Pose2 predicted = Compose(t.correction, trajectory[c.to]);  // where t puts this scan
  const double apart = std::fabs(path_[c.to] - path_[t.to]) + std::fabs(path_[c.from] - path_[t.from]);
  const double drift = options_.loopDriftRate * apart;
  const double dx = predicted.x - refined.x, dy = predicted.y - refined.y;
  double off = std::hypot(dx, dy);
  if (c.along_axis || t.along_axis) {
    const double a = corridor(c.along_axis ? c : t);
    off = std::fabs(std::cos(a) * dy - std::sin(a) * dx);
  }
  r.agree = off < kBigCorrection / 3.0 + drift &&
            std::fabs(NormalizeAngle(predicted.yaw - refined.yaw)) < kBigCorrection / 30.0 + drift / 10.0;
  return r;
}

bool LoopCloser::SmallCorrection(const LoopConstraint& c, const Pose2& refined,
                                 const std::vector<Pose2>& trajectory) const {
  const Pose2& here = trajectory[c.to];
  bool small = std::hypot(refined.x - here.x, refined.y - here.y) <= kBigCorrection &&
               std::fabs(NormalizeAngle(refined.yaw - here.yaw)) <= kBigCorrection / 10.0;
  // A correction just under kBigCorrection that repeats a large one still waiting for
  // confirmation, from the same submap, is that same claim, not a small one: it waits too.
  for (const LoopConstraint& t : tentative_) {
    if (!small || t.confirmed || t.from != c.from || t.to == c.to) continue;
    const Agreement a = Agree(c, refined, t, trajectory);
    if (a.agree && a.vouches_for_t) small = false;
  }
  return small;
}

void LoopCloser::AddConstraint(LoopConstraint c, const Pose2& refined, double window,
                               const std::vector<Pose2>& trajectory) {
  const int cur = c.to;
  if (SmallCorrection(c, refined, trajectory)) {
    if (!c.along_axis) anchored_path_ = path_[cur];
    constraints_.push_back(c);
    ++pending_;
    return;
  }
  // A constraint that says the estimate is far off enters the graph only once a constraint of
  // another scan in another submap that can vouch for it agrees with it: a graph cannot check a
  // lone loop edge — the chain of odometry edges bends to fit any one — so one look-alike place
  // must not be able to move the trajectory by metres.
  bool confirmed = false;
  for (LoopConstraint& t : tentative_) {
    // Another scan, and another submap: scans matched against the same submap share its
    // errors (a submap slightly bent inside, a place it aliases), so they are not two opinions —
    // except on the way back from a long stretch nothing has anchored (the window has grown
    // past loopSearchWindow with the drift), when two scans kSameSubmapApart of path apart saw
    // different stretches of it: the first corridor of a return may be the only submap the
    // robot passes before it leaves the old track again.
    if (t.to == cur) continue;
    if (t.from == c.from && !(path_[cur] - path_[t.to] >= kSameSubmapApart &&
                              window > options_.loopSearchWindow)) {
      continue;
    }
    const Agreement a = Agree(c, refined, t, trajectory);
    if (!a.agree) continue;
    if (a.vouches_for_t && !t.confirmed) {
      t.confirmed = true;
      constraints_.push_back(t);
      ++pending_;
      big_pending_ = true;
      if (!t.along_axis) anchored_path_ = std::max(anchored_path_, path_[t.to]);
    }
    confirmed = confirmed || a.t_vouches;
  }
  if (confirmed) {
    if (!c.along_axis) anchored_path_ = path_[cur];
    c.confirmed = true;
    constraints_.push_back(c);
    ++pending_;
    big_pending_ = true;
  }
  tentative_.push_back(c);
}

std::vector<Pose2> LoopCloser::Optimize(const std::vector<Pose2>& trajectory) {
  if (trajectory.size() != scans_.size()) {
    throw std::invalid_argument("LoopCloser::Optimize: " + std::to_string(trajectory.size()) + " poses for " +
                                std::to_string(scans_.size()) + " nodes");
  }
  std::vector<PoseGraphEdge> edges;
  edges.reserve(trajectory.size() + constraints_.size());
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    PoseGraphEdge e;
    e.from = static_cast<int>(i - 1);
    e.to = static_cast<int>(i);
    e.measurement = Between(trajectory[i - 1], trajectory[i]);
    e.sigma_xy = kSequentialSigmaXy;
    e.sigma_theta = kSequentialSigmaTheta;
    edges.push_back(e);
  }
  const std::size_t first_loop = edges.size();
  for (const LoopConstraint& c : constraints_) {
    PoseGraphEdge e;
    e.from = c.from;
    e.to = c.to;
    e.measurement = c.measurement;
    e.sigma_xy = kLoopSigmaXy;
    e.sigma_theta = kLoopSigmaTheta;
    if (c.along_axis) {
      e.axis = c.axis;
      e.sigma_along = kAlongSigma;
    }
    e.robust = true;
    edges.push_back(e);
  }
  const PoseGraphResult result = OptimizePoseGraph(trajectory, edges);
  // Constraints the optimum rejects are forgotten, so they do not come back at the next solve.
  std::vector<LoopConstraint> kept;
  for (std::size_t k = 0; k < constraints_.size(); ++k) {
    if (result.edge_inlier[first_loop + k]) kept.push_back(constraints_[k]);
  }
  outliers_ += static_cast<int>(constraints_.size() - kept.size());
  constraints_ = std::move(kept);
  // The trajectory is tied to the map where a kept constraint says so (one dropped as an outlier
  // tied nothing).
  anchored_path_ = 0.0;
  for (const LoopConstraint& c : constraints_) {
    if (!c.along_axis) anchored_path_ = std::max(anchored_path_, path_[c.to]);
  }
  pending_ = 0;
  big_pending_ = false;
  last_optimized_ = size();
  ++optimizations_;
  // The cached renderings stay: a correction the RBPF does not apply moves no node, and Submap
  // renders again any submap whose nodes have moved.
  return result.poses;
}

}  // namespace minibot3d_slam
