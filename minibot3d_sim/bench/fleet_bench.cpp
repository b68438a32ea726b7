// fleet_bench: real-time factor of the simulator core (no ROS) with N copies of one robot in a
// world, each wandering and scanning with its lasers at their rates (each scan sees the world,
// the other robots and the pedestrians), and the wall time per robot per sim second.
//
//   fleet_bench URDF_FILE WORLD_FILE --robots N [--actors M] [--physics kinematic|bullet]
//               [--seconds S] [--spacing M]
//
// The robots stand on a grid of --spacing metres over the world's bounds, on the spots where a
// robot's body has 0.1 m of room, picked evenly from the spots found, all facing +x. Each runs a
// wander controller at 20 Hz on its first laser, as Stage's wander example does: arcs (0.2 m/s at
// +-0.6 rad/s, alternating between robots) while nothing is within 0.35 m ahead (+-60 degrees),
// else a turn in place towards the side that was freer when it began; after a contact it backs
// off straight for 0.5 s. In a small world the robots still meet walls and each other often, as
// a crowd would; the robots' mean speed, their share of time in contact and the pedestrians' mean
// speed are printed, so a fleet or a crowd that jams shows. --actors adds M pedestrians of the
// social force model on a grid twice as fine, each walking to and fro between its spot and the
// furthest spot it can reach in a straight line that no other pedestrian starts at or walks to.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "minibot3d_sim/simulator.h"
#include "minibot3d_sim/world_loader.h"
#include "minibot3d_sim/world_slice.h"

using minibot3d_sim::Pose2;

namespace {

int Usage() {
  std::fprintf(stderr, "usage: fleet_bench URDF_FILE WORLD_FILE --robots N [--physics NAME] "
                       "[--seconds S] [--spacing M]\n");
  return 2;
}

// A spot keeps this much room around a robot's body (m): none starts boxed in under a table.
constexpr double kSpotClearance = 0.1;

// A pedestrian's straight walk is at least this long (m).
constexpr double kMinWalk = 1.5;

// The wander controller turns in place when something is nearer than this ahead (m).
constexpr double kAhead = 0.35;

// From a scan: the nearest return within 60 degrees either side of the sensor's +x, and +1 when
// the left half (beams at positive angles) is on the whole further away than the right, else -1.
void Look(const minibot3d_sim::LaserSpec& spec, double increment, const std::vector<float>& ranges,
          double* ahead, double* freer_side) {
  constexpr double kSector = 60.0 * M_PI / 180.0;
  *ahead = std::numeric_limits<double>::infinity();
  double left = 0.0, right = 0.0;
  for (size_t i = 0; i < ranges.size(); ++i) {
    const double a = spec.min_angle + static_cast<double>(i) * increment;
    const double r = std::isfinite(ranges[i]) ? ranges[i] : (ranges[i] > 0 ? spec.max_range : 0.0);
    if (std::abs(a) <= kSector) *ahead = std::min(*ahead, r);
    (a > 0.0 ? left : right) += std::min(r, 2.0);
  }
  *freer_side = left >= right ? 1.0 : -1.0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return Usage();
  const std::string urdf_path = argv[1], world_path = argv[2];
  minibot3d_sim::SimulatorOptions options;
  options.physics = "kinematic";
  double seconds = 60.0, spacing = 0.8;
  int robots = 0, actors = 0;
  for (int i = 3; i < argc; i += 2) {
    const std::string k = argv[i];
    if (i + 1 >= argc) return Usage();
    const char* v = argv[i + 1];
    if (k == "--physics") options.physics = v;
    else if (k == "--seconds") seconds = std::atof(v);
    else if (k == "--robots") robots = std::atoi(v);
    else if (k == "--actors") actors = std::atoi(v);
    else if (k == "--spacing") spacing = std::atof(v);
    else {
      std::fprintf(stderr, "fleet_bench: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  if (robots < 1 || actors < 0 || !(seconds > 0) || !(spacing > 0)) {
    std::fprintf(stderr, "fleet_bench: --robots must be >= 1, --actors >= 0, --seconds and "
                         "--spacing > 0\n");
    return 2;
  }
  std::ifstream in(urdf_path);
  if (!in) {
    std::fprintf(stderr, "fleet_bench: cannot read %s\n", urdf_path.c_str());
    return 1;
  }
  std::stringstream xml;
  xml << in.rdbuf();
  try {
    const auto model = minibot3d_sim::ParseRobotModel(xml.str(), {});
    minibot3d_sim::WorldLoadOptions load;

    // Free spots: a lone robot's body with room around it.
    std::vector<Pose2> spots;
    double x0 = std::numeric_limits<double>::max(), y0 = x0, x1 = -x0, y1 = -x0;  // world bounds
    {
      minibot3d_sim::Simulator probe(model, minibot3d_sim::LoadWorld(world_path, load, nullptr),
                                     options);
      const minibot3d_sim::WorldSlice slice(probe.world(), 0.1);
      for (const auto& s : slice.segments()) {
        for (const auto& p : {s.a, s.b}) {
          x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x());
          y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
        }
      }
      std::string what;
      for (double y = y0 + spacing / 2; y < y1; y += spacing) {
        for (double x = x0 + spacing / 2; x < x1; x += spacing) {
          const Pose2 p{x, y, 0.0};
          if (probe.at(0).PoseCollides(p, &what)) continue;
          probe.at(0).SetPose(p);
          if (probe.at(0).Clearance() >= kSpotClearance) spots.push_back(p);
        }
      }
    }
    if (static_cast<int>(spots.size()) < robots + actors) {
      std::fprintf(stderr, "fleet_bench: %zu free spots %.2f m apart in %s, %d robots and %d "
                   "actors asked\n", spots.size(), spacing, world_path.c_str(), robots, actors);
      return 1;
    }
    // Robots on spots picked evenly from the list.
    std::vector<Pose2> robot_spots;
    std::vector<char> taken(spots.size(), 0);
    for (int k = 0; k < robots; ++k) {
      const size_t i = static_cast<size_t>(k) * spots.size() / robots;
      robot_spots.push_back(spots[i]);
      taken[i] = 1;
    }
    std::vector<minibot3d_sim::RobotEntry> entries;
    for (int k = 0; k < robots; ++k) {
      minibot3d_sim::RobotEntry e;
      e.model = model;
      e.options.name = "robot" + std::to_string(k + 1);
      e.options.spawn = robot_spots[k];
      entries.push_back(std::move(e));
    }
    minibot3d_sim::World world = minibot3d_sim::LoadWorld(world_path, load, nullptr);
    if (actors > 0) {
      // Each pedestrian walks to and fro between two free spots joined by a straight walk (the
      // social force model steers round people, not round rooms): the segment (sampled every
      // 0.1 m) keeps a person's radius and 5 cm off the world at knee height.
      const minibot3d_sim::WorldSlice knee(world, 0.3);
      const double room = minibot3d_sim::SimulatorOptions().actor_radius + 0.05;
      const auto walkable = [&](const Pose2& a, const Pose2& b) {
        const double len = std::hypot(b.x - a.x, b.y - a.y);
        const int steps = static_cast<int>(std::ceil(len / 0.1));
        for (int i = 0; i <= steps; ++i) {
          const double t = steps > 0 ? static_cast<double>(i) / steps : 0.0;
          const Eigen::Vector2d p(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
          if (knee.Distance(p) < room) return false;
        }
        return true;
      };
      // Pedestrians' spots: a grid twice as fine as the robots', a person's radius and 5 cm off
      // the world and 0.5 m from every robot.
      std::vector<Pose2> people;
      for (double y = y0 + spacing / 4; y < y1; y += spacing / 2) {
        for (double x = x0 + spacing / 4; x < x1; x += spacing / 2) {
          bool clear = knee.Distance(Eigen::Vector2d(x, y)) >= room;
          for (const Pose2& r : robot_spots) clear &= std::hypot(r.x - x, r.y - y) >= 0.5;
          if (clear) people.push_back(Pose2{x, y, 0.0});
        }
      }
      std::vector<char> used(people.size(), 0);
      // Starts: spread evenly over the spots, each the first unused spot from its share on with
      // a straight walk of at least kMinWalk; then, in turn, each pedestrian's far end: the
      // furthest spot it can walk to that no other pedestrian starts at or walks to (a crowd all
      // heading for one spot would only jam there).
      const auto has_walk = [&](size_t i) {
        for (const Pose2& p : people) {
          if (std::hypot(p.x - people[i].x, p.y - people[i].y) >= kMinWalk &&
              walkable(people[i], p)) {
            return true;
          }
        }
        return false;
      };
      std::vector<size_t> picked;
      for (int k = 0; k < actors; ++k) {
        size_t i = static_cast<size_t>(k) * people.size() / actors;
        while (i < people.size() && (used[i] || !has_walk(i))) ++i;
        if (i == people.size()) {
          std::fprintf(stderr, "fleet_bench: no free spot with a straight walk of %.1f m left in "
                       "%s for person%d of %d\n", kMinWalk, world_path.c_str(), k + 1, actors);
          return 1;
        }
        picked.push_back(i);
        used[i] = 1;
      }
      for (int k = 0; k < actors; ++k) {
        const Pose2& from = people[picked[k]];
        size_t far = people.size();
        double best = 0.0;
        for (size_t i = 0; i < people.size(); ++i) {
          const double d = std::hypot(people[i].x - from.x, people[i].y - from.y);
          if (!used[i] && d > best && walkable(from, people[i])) best = d, far = i;
        }
        if (far == people.size()) {
          std::fprintf(stderr, "fleet_bench: person%d at (%.2f, %.2f) has no free spot to walk "
                       "to\n", k + 1, from.x, from.y);
          return 1;
        }
        used[far] = 1;
        minibot3d_sim::Actor a;
        a.name = "person" + std::to_string(k + 1);
        a.x = from.x, a.y = from.y;
        a.social_force = true;
        a.social.goals = {Eigen::Vector2d(people[far].x, people[far].y),
                          Eigen::Vector2d(a.x, a.y)};
        world.actors.push_back(a);
      }
    }
    minibot3d_sim::Simulator sim(std::move(entries), std::move(world), options);
    std::vector<float> ranges;
    std::vector<double> backing_until(sim.robot_count(), -1.0);  // sim time the bumper ends
    // Per robot, from its first laser's last scan: the nearest return ahead and which side is
    // freer.
    std::vector<double> ahead(sim.robot_count(), std::numeric_limits<double>::infinity());
    std::vector<double> freer_side(sim.robot_count(), 1.0);
    std::vector<double> turning(sim.robot_count(), 0.0);  // rad/s while turning in place, else 0
    long scans = 0, rays = 0;
    long contact_steps = 0;  // robot-steps in contact
    double driven = 0.0;     // metres the robots' centres moved, all together
    double walked = 0.0;     // metres the actors moved, all together
    std::vector<Eigen::Vector2d> actor_last;
    for (size_t k = 0; k < sim.actor_count(); ++k) {
      actor_last.emplace_back(sim.actor_state(k).x, sim.actor_state(k).y);
    }
    std::vector<Pose2> last(sim.robot_count());
    for (size_t r = 0; r < sim.robot_count(); ++r) last[r] = sim.at(r).true_pose();
    const auto steps = static_cast<long>(seconds / sim.physics_step());
    const auto t0 = std::chrono::steady_clock::now();
    for (long i = 0; i < steps; ++i) {
      for (size_t r = 0; r < sim.robot_count(); ++r) {
        minibot3d_sim::SimRobot& robot = sim.at(r);
        if (robot.in_contact()) {
          backing_until[r] = sim.time() + 0.5;
          ++contact_steps;
        }
        const Pose2 now = robot.true_pose();
        driven += std::hypot(now.x - last[r].x, now.y - last[r].y);
        last[r] = now;
        if (i % 50 == 0) {  // a 20 Hz controller
          const double arc = r % 2 ? -0.6 : 0.6;
          // A turn keeps its direction until the way ahead is clear.
          if (ahead[r] >= kAhead) turning[r] = 0.0;
          else if (turning[r] == 0.0) turning[r] = freer_side[r];
          if (sim.time() < backing_until[r]) robot.Command({-0.1, 0.0, 0.0});
          else if (turning[r] != 0.0) robot.Command({0.0, 0.0, turning[r]});
          else robot.Command({0.2, 0.0, arc});
        }
        for (size_t l = 0; l < robot.laser_count(); ++l) {
          if (!robot.ScanDue(l)) continue;
          robot.TakeScan(l, &ranges);
          ++scans;
          rays += static_cast<long>(ranges.size());
          if (l == 0) Look(robot.lidar(0).spec(), robot.lidar(0).angle_increment(), ranges,
                           &ahead[r], &freer_side[r]);
        }
      }
      sim.Step();
      if (i % 100 == 99) {  // the actors' progress every 0.1 s
        for (size_t k = 0; k < sim.actor_count(); ++k) {
          const Eigen::Vector2d at(sim.actor_state(k).x, sim.actor_state(k).y);
          walked += (at - actor_last[k]).norm();
          actor_last[k] = at;
        }
      }
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::uint64_t collisions = 0;
    for (size_t r = 0; r < sim.robot_count(); ++r) collisions += sim.at(r).collision_count();
    std::printf("robots=%d actors=%d physics=%s sim_seconds=%.1f wall_seconds=%.3f real_time_factor=%.1f "
                "wall_ms_per_robot_per_sim_second=%.3f scans=%ld rays=%ld collisions=%llu "
                "mean_speed=%.3f in_contact=%.1f%% actor_mean_speed=%.3f\n",
                robots, actors, options.physics.c_str(), sim.time(), wall, sim.time() / wall,
                1e3 * wall / (robots * sim.time()), scans, rays,
                static_cast<unsigned long long>(collisions), driven / (robots * sim.time()),
                100.0 * contact_steps / (static_cast<double>(robots) * steps),
                actors > 0 ? walked / (actors * sim.time()) : 0.0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fleet_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
