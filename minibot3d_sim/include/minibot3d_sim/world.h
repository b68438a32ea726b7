// The world the simulator drives in: a flat list of static collision shapes in the `world` frame
// and the actors that move on their scripts, loaded from a Gazebo SDF world or from a map_server
// floor plan (see world_loader.h).
#ifndef MINIBOT3D_SIM_WORLD_H_
#define MINIBOT3D_SIM_WORLD_H_

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "minibot3d_sim/actor.h"

namespace minibot3d_sim {

// Raised for any world that cannot be loaded; the message names the file (and element) at fault.
class WorldError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A static triangle mesh, vertices already scaled and expressed in the owning shape's frame.
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// The colour of a shape whose world names none: a neutral grey, darker than a camera's default
// background (Gazebo's 0.7 grey), so that a face never blends into the sky.
inline Eigen::Vector3f DefaultShapeColor() { return Eigen::Vector3f(0.5f, 0.5f, 0.5f); }

enum class ShapeType { kBox, kCylinder, kSphere, kPlane, kMesh };

struct Shape {
  ShapeType type = ShapeType::kBox;
  // "model::link::collision", used in collision reports and error messages.
  std::string name;
  // Pose of the shape's frame in the world frame. Box, cylinder and sphere are centred on it; a
  // cylinder's axis is the frame's z axis; a plane passes through its origin.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // kBox: full extents (x, y, z). kCylinder: (radius, radius, length). kSphere: (r, r, r).
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  // kPlane: unit normal in the shape frame.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  // kMesh only.
  std::shared_ptr<const TriangleMesh> mesh;
  // Flat RGB colour in [0, 1] for camera images, from the SDF <visual> material of the same link
  // (see world_loader.h); a neutral grey when the world says nothing.
  Eigen::Vector3f color = DefaultShapeColor();
};

struct World {
  std::string source;  // the file it was loaded from
  std::vector<Shape> shapes;
  std::vector<Actor> actors;  // things that move on a script (see actor.h)
};

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_WORLD_H_
