// Cost of one 1 ms physics step per backend, in an apartment-like world of ~40 static boxes and
// cylinders: the robot driving a circle in a room (the common case) and pushing into a wall
// (contacts every step). One core; the simulator's budget at 100x real time with a 10 Hz lidar is
// ~5 us per step for physics.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "minibot3d_sim/physics_backend.h"
#include "naive_bullet_backend.h"
#include "sim_test_fixtures.h"

namespace minibot3d_sim {
namespace {

using testing::MakePhysicsRobot;

// "bullet" and "kinematic" from the factory; "bullet_naive", the yardstick, from this directory.
std::unique_ptr<PhysicsBackend> MakeBackend(const std::string& name, const World& world) {
  if (name == "bullet_naive") return std::make_unique<NaiveBulletBackend>(MakePhysicsRobot(), world);
  return MakePhysicsBackend(name, MakePhysicsRobot(), world);
}

void AddBox(World* w, double x, double y, double sx, double sy, double h, double yaw = 0.0) {
  Shape s;
  s.type = ShapeType::kBox;
  s.name = "box" + std::to_string(w->shapes.size());
  s.pose = Eigen::Translation3d(x, y, h / 2) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
  s.size = Eigen::Vector3d(sx, sy, h);
  w->shapes.push_back(s);
}

void AddCylinder(World* w, double x, double y, double r, double h) {
  Shape s;
  s.type = ShapeType::kCylinder;
  s.name = "cylinder" + std::to_string(w->shapes.size());
  s.pose = Eigen::Isometry3d(Eigen::Translation3d(x, y, h / 2));
  s.size = Eigen::Vector3d(r, r, h);
  w->shapes.push_back(s);
}

// A 10 x 8 m flat: outer walls, four rooms with door gaps, furniture and table legs (38 shapes
// plus the floor).
World MakeApartment() {
  World w;
  Shape floor;
  floor.type = ShapeType::kPlane;
  floor.name = "ground_plane";
  w.shapes.push_back(floor);
  const double t = 0.1, h = 1.0;
  AddBox(&w, 5, 0, 10, t, h);   // outer walls
  AddBox(&w, 5, 8, 10, t, h);
  AddBox(&w, 0, 4, t, 8, h);
  AddBox(&w, 10, 4, t, 8, h);
  AddBox(&w, 5, 1.5, t, 3, h);  // inner walls with 1 m doors
  AddBox(&w, 5, 6.5, t, 3, h);
  AddBox(&w, 1.5, 4, 3, t, h);
  AddBox(&w, 4.0, 4, 1.0, t, h);
  AddBox(&w, 6.5, 4, 3, t, h);
  AddBox(&w, 9.25, 4, 1.5, t, h);
  AddBox(&w, 0.4, 1.5, 0.6, 2.0, 0.8);  // beds, sofas, shelves, tables
  AddBox(&w, 3.0, 0.35, 1.6, 0.5, 1.8);
  AddBox(&w, 8.0, 7.6, 2.0, 0.6, 0.9);
  AddBox(&w, 9.6, 6.0, 0.6, 1.2, 0.9);
  AddBox(&w, 6.0, 0.3, 1.2, 0.4, 0.45);
  AddBox(&w, 1.0, 7.5, 1.2, 0.8, 0.8, 0.3);
  AddBox(&w, 3.5, 6.0, 0.8, 0.8, 0.75, 0.8);
  AddBox(&w, 9.5, 2.0, 0.5, 0.5, 0.5);
  AddBox(&w, 8.8, 1.0, 0.4, 0.9, 1.2);
  AddBox(&w, 2.2, 5.2, 0.3, 0.3, 0.4);
  for (double cx : {7.0, 8.0}) {  // two tables on legs
    for (double cy : {5.3, 6.1}) AddCylinder(&w, cx, cy, 0.025, 0.7);
  }
  for (double cx : {1.8, 2.6}) {
    for (double cy : {2.2, 2.8}) AddCylinder(&w, cx, cy, 0.025, 0.7);
  }
  AddCylinder(&w, 4.5, 7.5, 0.2, 1.0);  // plant pots, bins, a pillar
  AddCylinder(&w, 9.5, 0.5, 0.15, 0.4);
  AddCylinder(&w, 0.5, 4.6, 0.12, 0.3);
  AddCylinder(&w, 5.5, 4.6, 0.15, 2.5);
  AddCylinder(&w, 2.5, 7.0, 0.2, 0.5);
  AddCylinder(&w, 6.2, 7.0, 0.1, 0.6);
  AddCylinder(&w, 9.0, 3.0, 0.25, 0.8);
  AddBox(&w, 4.6, 2.9, 0.5, 0.3, 0.6);
  AddBox(&w, 1.2, 0.6, 0.5, 0.5, 0.5);
  AddBox(&w, 8.5, 4.4, 0.8, 0.3, 0.9);
  return w;
}

// Driving circles in the lower right room, clear of the furniture (0.2 m/s, 0.6 rad/s commanded;
// "bullet" and "bullet_naive" slip to a wider circle, all of it inside the room). `contacts`
// reports how many the last step had: 0 here.
void BM_StepArc(benchmark::State& state, const std::string& backend) {
  const World world = MakeApartment();
  auto b = MakeBackend(backend, world);
  b->SetPose(Pose2{7.0, 1.5, 0.0});
  b->SetTargets(testing::SkidTargets(0.2, 0.6));
  std::vector<Contact> contacts;
  for (int i = 0; i < 2000; ++i) b->Step(0.001, &contacts);  // past the start-up transient
  for (auto _ : state) {
    contacts.clear();
    b->Step(0.001, &contacts);
    benchmark::DoNotOptimize(contacts.data());
  }
  state.counters["contacts"] = static_cast<double>(contacts.size());
}

// Pushing into the outer wall at a 0.5 m/s command: the contact path every step.
void BM_StepPushingWall(benchmark::State& state, const std::string& backend) {
  const World world = MakeApartment();
  auto b = MakeBackend(backend, world);
  b->SetPose(Pose2{7.0, 0.6, -M_PI / 2});
  b->SetTargets(testing::SkidTargets(0.5, 0.0));
  std::vector<Contact> contacts;
  for (int i = 0; i < 3000; ++i) b->Step(0.001, &contacts);
  for (auto _ : state) {
    contacts.clear();
    b->Step(0.001, &contacts);
    benchmark::DoNotOptimize(contacts.data());
  }
  state.counters["contacts"] = static_cast<double>(contacts.size());
}

BENCHMARK_CAPTURE(BM_StepArc, kinematic, std::string("kinematic"));
BENCHMARK_CAPTURE(BM_StepArc, bullet, std::string("bullet"));
BENCHMARK_CAPTURE(BM_StepArc, bullet_naive, std::string("bullet_naive"));
BENCHMARK_CAPTURE(BM_StepPushingWall, kinematic, std::string("kinematic"));
BENCHMARK_CAPTURE(BM_StepPushingWall, bullet, std::string("bullet"));
BENCHMARK_CAPTURE(BM_StepPushingWall, bullet_naive, std::string("bullet_naive"));

}  // namespace
}  // namespace minibot3d_sim

BENCHMARK_MAIN();
