// correlative_search: branch and bound finds exactly the brute-force maximum; a scan is found
// anywhere in a building; look-alike places are all reported; bad options are named.
#include "minibot3d_scan_matching/correlative_search.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "minibot3d_testing/synthetic_building.h"
#include "minibot3d_testing/synthetic_world.h"

namespace minibot3d_scan_matching {
namespace {

using minibot3d_common::LaserScan;
using minibot3d_testing::FullScan;
using minibot3d_testing::OfficeBuilding;
using minibot3d_testing::Rasterize;
using minibot3d_testing::TwinRooms;
using minibot3d_testing::World;

// A small random map: unknown, free and occupied cells and some grey levels, in blobs.
GridMap RandomMap(std::mt19937* rng, int width, int height) {
  std::uniform_int_distribution<int> kind(0, 9), level(0, 100);
  GridMap map;
  map.resolution = 0.05;
  map.width = width;
  map.height = height;
  map.origin_x = std::uniform_real_distribution<double>(-2.0, 2.0)(*rng);
  map.origin_y = std::uniform_real_distribution<double>(-2.0, 2.0)(*rng);
  map.origin_theta = kind(*rng) < 3 ? std::uniform_real_distribution<double>(-1.0, 1.0)(*rng) : 0.0;
  map.data.resize(static_cast<std::size_t>(width) * height);
  for (auto& v : map.data) {
    const int k = kind(*rng);
    v = k == 0 ? -1 : k < 5 ? 0 : k < 8 ? static_cast<std::int8_t>(level(*rng)) : 100;
  }
  return map;
}

TEST(CorrelativeSearchTest, BranchAndBoundEqualsBruteForce) {
  std::mt19937 rng(20160516);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0, same_pose = 0;
  for (int trial = 0; trial < 150; ++trial) {
    const GridMap map = RandomMap(&rng, 20 + static_cast<int>(40 * unit(rng)),
                                  20 + static_cast<int>(40 * unit(rng)));
    CorrelativeSearchOptions options;
    options.branch_and_bound_depth = 1 + trial % 6;
    options.unknown_probability = unit(rng) < 0.5 ? 0.1 : 0.0;
    options.blur_sigma = unit(rng) < 0.5 ? 0.05 : 0.0;
    const CorrelativeSearch search(map, options);
    std::vector<Eigen::Vector2d> points(3 + static_cast<int>(30 * unit(rng)));
    for (auto& p : points) p = Eigen::Vector2d(3.0 * unit(rng) - 1.5, 3.0 * unit(rng) - 1.5);
    const Pose2 corner = Compose(Pose2{map.origin_x, map.origin_y, map.origin_theta},
                                 Pose2{map.width * map.resolution * unit(rng),
                                       map.height * map.resolution * unit(rng), 0.0});
    const Pose2 initial{corner.x, corner.y, 2 * M_PI * unit(rng) - M_PI};
    options.linear_search_window =
        trial % 3 == 0 ? CorrelativeSearchOptions::kWholeMap : 0.2 + 0.8 * unit(rng);
    options.angular_search_window = trial % 4 == 0 ? M_PI : 0.4 * unit(rng);
    options.angular_step = trial % 5 == 0 ? 0.0 : 0.05 + 0.1 * unit(rng);
    options.min_score = trial % 2 == 0 ? 0.0 : 0.5 * unit(rng);
    options.branch_and_bound_depth =
        1 + static_cast<int>(unit(rng) * options.branch_and_bound_depth);

    const auto brute = search.BruteForceSearch(points, initial, options);
    const auto bnb = search.Search(points, initial, options);
    ASSERT_EQ(brute.has_value(), bnb.has_value()) << "trial " << trial;
    if (!brute) continue;
    ++compared;
    // Exact: both are integer sums of per-cent probabilities over the same lattice.
    EXPECT_EQ(bnb->score, brute->score) << "trial " << trial;
    EXPECT_GE(bnb->score, options.min_score);
    // The pose found has that score (ties may pick another lattice pose than brute force).
    EXPECT_EQ(search.Score(points, bnb->pose), bnb->score) << "trial " << trial;
    if (std::hypot(bnb->pose.x - brute->pose.x, bnb->pose.y - brute->pose.y) < 1e-9 &&
        std::fabs(NormalizeAngle(bnb->pose.yaw - brute->pose.yaw)) < 1e-9) {
      ++same_pose;
    }
    // SearchAll's first candidate is Search's result.
    options.max_candidates = 1 + trial % 4;
    options.min_relative_score = trial % 2 == 0 ? 0.0 : 0.8;
    const auto all = search.SearchAll(points, initial, options);
    ASSERT_FALSE(all.empty());
    EXPECT_LE(static_cast<int>(all.size()), options.max_candidates);
    EXPECT_EQ(all.front().score, bnb->score);
    EXPECT_NEAR(all.front().pose.x, bnb->pose.x, 1e-12);
    EXPECT_NEAR(all.front().pose.y, bnb->pose.y, 1e-12);
    for (std::size_t k = 1; k < all.size(); ++k) {
      EXPECT_LE(all[k].score, all[k - 1].score);
      EXPECT_GE(all[k].score, options.min_relative_score * all[0].score - 1e-9);
    }
  }
  EXPECT_GT(compared, 120);
  EXPECT_GT(same_pose, compared / 2);  // most maxima are unique
}

// The scan's frame can be anywhere on the robot: ScanToPoints applies sensor_in_base.
TEST(CorrelativeSearchTest, ScanToPointsKeepsReturnsInTheBaseFrame) {
  LaserScan scan;
  scan.range_min = 0.1;
  scan.range_max = 10.0;
  scan.sensor_in_base = Pose2{0.2, 0.0, M_PI / 2};
  scan.angles = {0.0, 0.1, 0.2, 0.3, 0.4};
  scan.ranges = {1.0, std::nan(""), 0.05, 10.0, 2.0};
  const auto points = ScanToPoints(scan);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_NEAR(points[0].x(), 0.2, 1e-12);
  EXPECT_NEAR(points[0].y(), 1.0, 1e-12);
  EXPECT_EQ(ScanToPoints(scan, 1.5).size(), 1u);
}

// Checks that a pose is within a cell and an angular step of the truth.
void ExpectNear(const Pose2& found, const Pose2& truth, double resolution, double step,
                const std::string& what) {
  EXPECT_LE(std::fabs(found.x - truth.x), resolution) << what;
  EXPECT_LE(std::fabs(found.y - truth.y), resolution) << what;
  EXPECT_LE(std::fabs(NormalizeAngle(found.yaw - truth.yaw)), step) << what;
}

double DefaultStep(const std::vector<Eigen::Vector2d>& points, double resolution) {
  double d = 0.0;
  for (const auto& p : points) d = std::max(d, p.norm());
  return std::acos(1.0 - resolution * resolution / (2.0 * d * d));
}

TEST(CorrelativeSearchTest, FindsAScanAnywhereInABuilding) {
  std::vector<Pose2> spots;
  const World world = OfficeBuilding(30.0, 20.0, 7, &spots);
  const GridMap map = Rasterize(world, 0.0, 0.0, 30.0, 20.0);
  CorrelativeSearchOptions options;
  options.linear_search_window = CorrelativeSearchOptions::kWholeMap;
  options.angular_search_window = M_PI;
  options.max_candidates = 3;
  const CorrelativeSearch search(map, options);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(-1.0, 31.0), uy(-1.0, 21.0), ua(-M_PI, M_PI);
  ASSERT_GE(spots.size(), 6u);
  for (std::size_t s = 0; s < spots.size(); s += spots.size() / 4) {
    const Pose2 truth{spots[s].x, spots[s].y, ua(rng)};
    const auto points = ScanToPoints(FullScan(world, truth));
    const double step = DefaultStep(points, map.resolution);
    for (int guess = 0; guess < 2; ++guess) {
      const Pose2 initial{ux(rng), uy(rng), ua(rng)};
      const std::string what = "spot " + std::to_string(s) + " guess " + std::to_string(guess);
      const auto found = search.Search(points, initial, options);
      ASSERT_TRUE(found) << what;
      ExpectNear(found->pose, truth, map.resolution, step, what);
      EXPECT_GT(found->score, 0.85) << what;
      // One winner: the runner-up elsewhere (rooms of the same depth along a corridor look much
      // alike, so it is not far behind) scores clearly lower.
      const auto all = search.SearchAll(points, initial, options);
      ASSERT_FALSE(all.empty());
      EXPECT_EQ(all[0].score, found->score) << what;
      if (all.size() > 1) {
        EXPECT_LT(all[1].score, all[0].score - 0.05) << what;
      }
    }
  }
}

TEST(CorrelativeSearchTest, LocalWindowForLoopClosure) {
  const World world = minibot3d_testing::Office();
  const GridMap map = Rasterize(world, -6.0, -4.0, 6.0, 4.0);
  CorrelativeSearchOptions options;  // defaults: ±7 m, ±30°
  const CorrelativeSearch search(map, options);
  const Pose2 truth{-3.3, 2.4, 0.4};
  const auto points = ScanToPoints(FullScan(world, truth, 360, 12.0));
  const Pose2 initial{truth.x + 1.1, truth.y - 0.7, truth.yaw - 0.3};
  const auto found = search.Search(points, initial, options);
  ASSERT_TRUE(found);
  ExpectNear(found->pose, truth, map.resolution, DefaultStep(points, map.resolution), "office");
  // Brute force over ±7 m takes seconds; ±1.5 m still holds the truth.
  options.linear_search_window = 1.5;
  EXPECT_EQ(search.BruteForceSearch(points, initial, options)->score, found->score);
  EXPECT_EQ(search.Search(points, initial, options)->score, found->score);
  // Out of the window: 0.5 m and 0.1 rad do not reach the truth, so the best is elsewhere.
  options.linear_search_window = 0.5;
  options.angular_search_window = 0.1;
  const auto narrow = search.Search(points, initial, options);
  if (narrow) {
    EXPECT_LT(narrow->score, found->score);
  }
}

TEST(CorrelativeSearchTest, SearchAllReportsLookAlikeRooms) {
  const double shift = 10.0;
  const World world = TwinRooms(shift);
  const GridMap map = Rasterize(world, 0.0, 0.0, 16.0, 4.0);
  CorrelativeSearchOptions options;
  options.linear_search_window = CorrelativeSearchOptions::kWholeMap;
  options.angular_search_window = M_PI;
  options.max_candidates = 4;
  options.min_separation_angular = M_PI;  // one candidate per place
  const CorrelativeSearch search(map, options);
  const Pose2 truth{2.9, 1.6, 0.7};
  const auto points = ScanToPoints(FullScan(world, truth));
  const double step = DefaultStep(points, map.resolution);
  for (const Pose2& initial : {Pose2{8.0, 2.0, 0.0}, Pose2{15.0, 0.5, -2.5}}) {
    const auto all = search.SearchAll(points, initial, options);
    ASSERT_GE(all.size(), 2u);
    EXPECT_GT(all[0].score, 0.85);
    EXPECT_NEAR(all[1].score, all[0].score, 0.02);
    const Pose2 a = all[0].pose.x < all[1].pose.x ? all[0].pose : all[1].pose;
    const Pose2 b = all[0].pose.x < all[1].pose.x ? all[1].pose : all[0].pose;
    ExpectNear(a, truth, map.resolution, step, "room A");
    ExpectNear(b, Pose2{truth.x + shift, truth.y, truth.yaw}, map.resolution, step, "room B");
    for (std::size_t k = 2; k < all.size(); ++k) EXPECT_LT(all[k].score, 0.8 * all[1].score);
    // Candidates are mutually separated.
    for (std::size_t i = 0; i < all.size(); ++i) {
      for (std::size_t j = i + 1; j < all.size(); ++j) {
        EXPECT_GE(std::hypot(all[i].pose.x - all[j].pose.x, all[i].pose.y - all[j].pose.y),
                  options.min_separation_linear);
      }
    }
  }
}

// Calls f with a copy of good options, expects std::invalid_argument naming `name`.
template <typename F>
void ExpectRejected(const std::string& name, F change) {
  GridMap map;
  map.width = map.height = 4;
  map.data.assign(16, 0);
  CorrelativeSearchOptions options;
  change(&options);
  try {
    CorrelativeSearch search(map, options);
    ADD_FAILURE() << name << ": accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
  EXPECT_THROW(CheckCorrelativeSearchOptions(options), std::invalid_argument) << name;
}

TEST(CorrelativeSearchTest, BadOptionsAreNamed) {
  using O = CorrelativeSearchOptions;
  ExpectRejected("linear_search_window", [](O* o) { o->linear_search_window = 0.0; });
  ExpectRejected("linear_search_window", [](O* o) { o->linear_search_window = std::nan(""); });
  ExpectRejected("angular_search_window", [](O* o) { o->angular_search_window = -0.1; });
  ExpectRejected("angular_step", [](O* o) { o->angular_step = -0.01; });
  ExpectRejected("angular_step", [](O* o) { o->angular_step = 4.0; });
  ExpectRejected("branch_and_bound_depth", [](O* o) { o->branch_and_bound_depth = 0; });
  ExpectRejected("branch_and_bound_depth", [](O* o) { o->branch_and_bound_depth = 17; });
  ExpectRejected("min_score", [](O* o) { o->min_score = 1.5; });
  ExpectRejected("max_candidates", [](O* o) { o->max_candidates = 0; });
  ExpectRejected("min_separation_linear", [](O* o) { o->min_separation_linear = -1.0; });
  ExpectRejected("min_separation_angular", [](O* o) { o->min_separation_angular = -1.0; });
  ExpectRejected("unknown_probability", [](O* o) { o->unknown_probability = 2.0; });
  ExpectRejected("blur_sigma", [](O* o) { o->blur_sigma = -0.05; });
  ExpectRejected("min_relative_score", [](O* o) { o->min_relative_score = 1.1; });

  // Accepted: the whole map, the full circle, the default step.
  O whole;
  whole.linear_search_window = O::kWholeMap;
  whole.angular_search_window = M_PI;
  EXPECT_NO_THROW(CheckCorrelativeSearchOptions(whole));

  // A search cannot use more levels than were built.
  GridMap map;
  map.width = map.height = 8;
  map.data.assign(64, 0);
  O built;
  built.branch_and_bound_depth = 3;
  const CorrelativeSearch search(map, built);
  O deeper = built;
  deeper.branch_and_bound_depth = 4;
  try {
    search.Search({Eigen::Vector2d(0.1, 0.0)}, Pose2{}, deeper);
    ADD_FAILURE() << "deeper search accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("branch_and_bound_depth"), std::string::npos);
  }
  // An empty map is an error; an empty scan is no result.
  EXPECT_THROW(CorrelativeSearch(GridMap{}, built), std::invalid_argument);
  EXPECT_FALSE(search.Search({}, Pose2{}, built));
  EXPECT_TRUE(search.SearchAll({}, Pose2{}, built).empty());
}

}  // namespace
}  // namespace minibot3d_scan_matching
