// Whether a transform's stamp can give the robot's pose now, and if not, why, in words that name
// the frames and say what to do. ROS-free so that it is tested without a master
// (test/transform_age_test.cpp).
//
// The case that used to mislead: move_base started before /use_sim_time was set runs on the wall
// clock (~1.7e9 s since 1970) while the simulator stamps tf with sim time (from 0), so the
// transform looked 1.7e9 s old and the warning blamed the localizer. Clocks more than a minute
// apart, one of them past 1e9 s (2001) and the other not, are reported as wall time against sim
// time, in the direction they disagree.
#ifndef MINIBOT3D_NAVIGATION_TRANSFORM_AGE_H_
#define MINIBOT3D_NAVIGATION_TRANSFORM_AGE_H_

#include <cmath>
#include <cstdio>
#include <string>

namespace minibot3d_navigation {

struct TransformAge {
  bool ok = true;
  bool clocks_disagree = false;  // wall time against sim time: no tf publisher is to blame
  std::string why;               // empty when ok
};

constexpr double kClockDisagreement = 60.0;  // s
constexpr double kWallClockAfter = 1e9;      // s since 1970 (2001): a wall clock reads more

// `now`: the node's clock; `stamp`: the transform's (0 = static, always fine); both in seconds.
inline TransformAge CheckTransformAge(double now, double stamp, const std::string& target,
                                      const std::string& source, double tolerance,
                                      const std::string& node = "move_base") {
  TransformAge r;
  if (stamp == 0.0) return r;
  const double age = now - stamp;
  const std::string pair = "the transform " + target + " <- " + source;
  char buf[768];
  const bool node_wall = now >= kWallClockAfter, tf_wall = stamp >= kWallClockAfter;
  if (std::abs(age) > kClockDisagreement && node_wall != tf_wall) {
    r.ok = false;
    r.clocks_disagree = true;
    if (node_wall) {
      std::snprintf(buf, sizeof(buf),
                    "%s's clock reads %.3f s but %s is stamped %.3f s: %s runs on wall time "
                    "while tf is stamped with sim time. /use_sim_time was not true when %s "
                    "started: set it first (every launch file does, arg use_sim_time, default "
                    "true) and restart %s",
                    node.c_str(), now, pair.c_str(), stamp, node.c_str(), node.c_str(),
                    node.c_str());
    } else {
      std::snprintf(buf, sizeof(buf),
                    "%s's clock reads %.3f s but %s is stamped %.3f s: %s runs on sim time "
                    "while tf is stamped with wall time. The node publishing %s -> %s (or a "
                    "link between them) is not on sim time: set /use_sim_time true before "
                    "starting it and restart it",
                    node.c_str(), now, pair.c_str(), stamp, node.c_str(), target.c_str(),
                    source.c_str());
    }
    r.why = buf;
    return r;
  }
  if (age < -kClockDisagreement) {
    r.ok = false;
    std::snprintf(buf, sizeof(buf),
                  "%s is stamped %.3f s ahead of %s's clock: do its publisher and %s run on "
                  "the same clock?",
                  pair.c_str(), -age, node.c_str(), node.c_str());
    r.why = buf;
  } else if (age > tolerance) {
    r.ok = false;
    std::snprintf(buf, sizeof(buf), "%s is %.3f s old (transform_tolerance %.3f s)", pair.c_str(),
                  age, tolerance);
    r.why = buf;
  }
  return r;
}

}  // namespace minibot3d_navigation

#endif  // MINIBOT3D_NAVIGATION_TRANSFORM_AGE_H_
