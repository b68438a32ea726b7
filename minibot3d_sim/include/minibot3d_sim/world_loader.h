// Loading worlds from disk.
//
// Two formats:
//  * Gazebo SDF (.world / .sdf), the subset a 2-D navigation world uses: <model> with <static>,
//    <pose>, <link><collision><geometry> of box, cylinder, sphere, plane and mesh (Collada .dae,
//    .stl, .obj through assimp, kept as static triangle meshes), nested <include> of model://NAME
//    resolved through GAZEBO_MODEL_PATH and a models/ folder next to the world. ground_plane and sun
//    are known built-ins. Non-static models are loaded as static, with a warning. A shape's colour
//    is the <material> of a <visual> in its link (<diffuse>, <ambient>, or the name of a material
//    Gazebo ships, e.g. Gazebo/Red, Gazebo/Wood), for the cameras' flat-shaded images. <actor>s
//    with their <script> trajectories go to World::actors (actor.h).
//  * A map_server floor plan (.yaml + image): occupied pixels are extruded into walls of
//    `floorplan_wall_height`.
#ifndef MINIBOT3D_SIM_WORLD_LOADER_H_
#define MINIBOT3D_SIM_WORLD_LOADER_H_

#include <string>
#include <vector>

#include "minibot3d_sim/world.h"

namespace minibot3d_sim {

struct WorldLoadOptions {
  // Extra directories searched for model://NAME, before GAZEBO_MODEL_PATH.
  std::vector<std::string> model_paths;
  // Whether to read GAZEBO_MODEL_PATH from the environment.
  bool use_gazebo_model_path_env = true;
  // Height of walls extruded from a floor-plan image (m).
  double floorplan_wall_height = 1.0;
};

// Loads a world by file extension (.world/.sdf → SDF, .yaml → floor plan). Throws WorldError
// naming the file and the element or key at fault. Non-fatal oddities (unknown tags, dynamic models
// made static) are appended to *warnings when it is not null.
World LoadWorld(const std::string& path, const WorldLoadOptions& options,
                std::vector<std::string>* warnings);

World LoadSdfWorld(const std::string& path, const WorldLoadOptions& options,
                   std::vector<std::string>* warnings);
World LoadFloorPlanWorld(const std::string& yaml_path, const WorldLoadOptions& options,
                         std::vector<std::string>* warnings);

// Loads a mesh file with assimp, scaled by `scale`. Throws WorldError naming the file.
TriangleMesh LoadMesh(const std::string& path, const Eigen::Vector3d& scale);

}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_WORLD_LOADER_H_
