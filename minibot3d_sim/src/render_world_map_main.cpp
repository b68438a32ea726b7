// render_world_map: the ground-truth occupancy map of a world, cut at the lidar's height, written
// as a map_server map (OUT.pgm + OUT.yaml).
//
//   render_world_map WORLD OUT_BASENAME [--resolution 0.05] [--height 0.11] [--margin 0.5]
//
// Exit status: 0 written, 1 the world could not be loaded or the map not written, 2 bad arguments.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "minibot3d_sim/world_loader.h"
#include "minibot3d_sim/world_map.h"
#include "minibot3d_sim/world_slice.h"

namespace {

constexpr const char kUsage[] =
    "usage: render_world_map WORLD OUT_BASENAME [--resolution 0.05] [--height 0.11] "
    "[--margin 0.5]\n"
    "  WORLD         a Gazebo SDF world (.world/.sdf) or a map_server floor plan (.yaml)\n"
    "  OUT_BASENAME  writes OUT_BASENAME.pgm and OUT_BASENAME.yaml\n"
    "  --resolution  cell size in metres (> 0)\n"
    "  --height      height of the horizontal cut in metres\n"
    "  --margin      free border around the geometry in metres (>= 0)\n";

int UsageError(const std::string& message) {
  std::cerr << "render_world_map: " << message << "\n" << kUsage;
  return 2;
}

bool ParseDouble(const std::string& text, double* out) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> positional;
  double resolution = 0.05, height = 0.11, margin = 0.5;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      return 0;
    }
    if (arg == "--resolution" || arg == "--height" || arg == "--margin") {
      if (i + 1 >= argc) return UsageError(arg + " needs a value");
      double* target = arg == "--resolution" ? &resolution : arg == "--height" ? &height : &margin;
      if (!ParseDouble(argv[++i], target)) {
        return UsageError(arg + ": '" + argv[i] + "' is not a number");
      }
    } else if (arg.size() > 1 && arg[0] == '-') {
      return UsageError("unknown option " + arg);
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() != 2) return UsageError("expected WORLD and OUT_BASENAME");
  if (!(resolution > 0.0)) return UsageError("--resolution must be positive");
  if (!(margin >= 0.0)) return UsageError("--margin must be non-negative");

  try {
    std::vector<std::string> warnings;
    const minibot3d_sim::World world =
        minibot3d_sim::LoadWorld(positional[0], minibot3d_sim::WorldLoadOptions(), &warnings);
    for (const std::string& w : warnings) std::cerr << "warning: " << w << "\n";
    const minibot3d_sim::WorldSlice slice(world, height);
    const minibot3d_sim::OccupancyImage image =
        minibot3d_sim::RenderSlice(slice, resolution, margin);
    minibot3d_sim::WriteMapServerFiles(image, positional[1]);
    int occupied = 0;
    for (std::uint8_t c : image.occupied) occupied += c;
    std::cout << "wrote " << positional[1] << ".pgm/.yaml: " << image.width << " x "
              << image.height << " cells of " << resolution << " m, origin ("
              << image.origin.x() << ", " << image.origin.y() << "), " << occupied
              << " occupied, from " << world.shapes.size() << " shapes cut at z = " << height
              << "\n";
  } catch (const std::exception& e) {
    std::cerr << "render_world_map: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
