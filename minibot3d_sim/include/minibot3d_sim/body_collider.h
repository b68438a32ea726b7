// BodyCollider: whether a robot's body overlaps the static world, part by part and height by
// height (the kinematic backend's contact test, the spawn check, the clearance the simulator
// reports), and BodyOverlap: whether two robots' bodies overlap.
//
// Each body part (BodyParts: one collision shape's outline from above over its height band) is
// tested against the world's horizontal cross-sections (WorldSlice) at the heights it spans: its
// band's ends, every 5 cm between, and the heights where a world shape begins or ends within it,
// so a table top above the robot or a low step under its body count where they are. Cross-
// sections come from a SliceCache, so robots of one model (and lasers at one height) share them;
// a part tests each distinct cross-section once (walls extruded from the floor cut the same lines
// at every height), at the lowest of its heights that has it.
#ifndef MINIBOT3D_SIM_BODY_COLLIDER_H_
#define MINIBOT3D_SIM_BODY_COLLIDER_H_

#include <map>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "minibot3d_common/geometry2d.h"
#include "minibot3d_sim/robot_model.h"
#include "minibot3d_sim/world.h"
#include "minibot3d_sim/world_slice.h"

namespace minibot3d_sim {

using minibot3d_common::Pose2;

// Cross-sections of one world, made on first use and kept (keyed by the height in µm).
class SliceCache {
 public:
  explicit SliceCache(const World* world) : world_(world) {}
  const WorldSlice* At(double height);

 private:
  const World* world_;
  std::map<long long, std::unique_ptr<WorldSlice>> slices_;  // NOLINT(runtime/int)
};

class BodyCollider {
 public:
  // `cache` (of `world`) must outlive the collider.
  BodyCollider(const RobotModel& robot, const World& world, SliceCache* cache);

  struct Hit {
    int shape = -1;  // World::shapes index
    int part = -1;   // parts() index
    double height = 0.0;
    const WorldSlice* slice = nullptr;
  };
  // Whether a part overlaps the world with the robot's root at `pose`; *hit says where.
  bool Collides(const Pose2& pose, Hit* hit) const;
  // Whether every part, grown by `margin` (> 0) all round, is clear of the world with the robot's
  // root at `pose`: then nothing is within `margin` of the body. Conservative: a part is grown by
  // moving its edges out (corners grow a little more than `margin`).
  bool Clear(const Pose2& pose, double margin) const;
  // Distance from p to the nearest geometry in any of the cross-sections.
  double Distance(const Eigen::Vector2d& p) const;
  // Largest distance of a part's vertex from the root frame's origin.
  double radius() const { return radius_; }

  struct Part {
    std::vector<Eigen::Vector2d> outline;  // root frame, counter-clockwise
    double z_min = 0.0, z_max = 0.0;
    // Per vertex, the direction and rate at which it moves when each edge is moved out by a unit
    // distance (the miter); empty for an outline of fewer than three vertices.
    std::vector<Eigen::Vector2d> miter;
    // The outline's bounding circle (root frame).
    Eigen::Vector2d center = Eigen::Vector2d::Zero();
    double radius = 0.0;
    // Distinct cross-sections the part meets, each with the lowest of its heights that cuts it.
    std::vector<const WorldSlice*> slices;
    std::vector<double> heights;
  };
  const std::vector<Part>& parts() const { return parts_; }

 private:
  std::vector<Part> parts_;
  std::vector<const WorldSlice*> all_slices_;
  double radius_ = 0.0;
  mutable std::vector<Eigen::Vector2d> scratch_;
};

// Two robots' bodies at their poses: whether a part of one overlaps a part of the other in plan
// and in height (separating axis test of the convex outlines). *normal, when not null, gets the
// unit direction in which `a` leaves `b` fastest (the axis of least overlap).
bool BodyOverlap(const BodyCollider& a, const Pose2& pose_a, const BodyCollider& b,
                 const Pose2& pose_b, Eigen::Vector2d* normal = nullptr);

// A robot's body at `pose` against an upright cylinder (an actor): whether a part whose height band
// meets [z_min, z_max] comes within `radius` of `center` in plan. *normal, when not null, gets the
// unit direction from the cylinder's axis towards the body.
bool BodyTouchesDisc(const BodyCollider& body, const Pose2& pose, const Eigen::Vector2d& center,
                     double radius, double z_min, double z_max, Eigen::Vector2d* normal = nullptr);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_BODY_COLLIDER_H_
