#include "minibot3d_sim/physics_backend.h"

#include <stdexcept>

#include "bullet_backend.h"
#include "kinematic_backend.h"

namespace minibot3d_sim {

std::unique_ptr<PhysicsBackend> MakePhysicsBackend(const std::string& name,
                                                   const RobotModel& robot, const World& world,
                                                   SliceCache* slices) {
  if (name == "bullet") return std::make_unique<BulletBackend>(robot, world);
  if (name == "kinematic") return std::make_unique<KinematicBackend>(robot, world, slices);
  throw std::invalid_argument("unknown physics backend '" + name + "' (valid: bullet, kinematic)");
}

}  // namespace minibot3d_sim
