// RenderSlice (exact per-cell occupancy) and WriteMapServerFiles (PGM + YAML, read back).
#include "minibot3d_sim/world_map.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "minibot3d_map_io/map_io.h"
#include "minibot3d_sim/world_loader.h"

namespace minibot3d_sim {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "world_map_test.XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string operator/(const std::string& rel) const { return (fs::path(path_) / rel).string(); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

Shape Box(double x, double y, double yaw, double sx, double sy) {
  Shape s;
  s.type = ShapeType::kBox;
  s.pose = Eigen::Isometry3d::Identity();
  s.pose.translation() = Eigen::Vector3d(x, y, 0.5);
  s.pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  s.size = Eigen::Vector3d(sx, sy, 1.0);
  return s;
}

World WorldOf(std::vector<Shape> shapes) {
  World w;
  w.shapes = std::move(shapes);
  return w;
}

int CountOccupied(const OccupancyImage& im) {
  int n = 0;
  for (std::uint8_t c : im.occupied) n += c;
  return n;
}

TEST(WorldMapTest, AlignedBoxFillsExactlyItsCells) {
  // x, y ∈ [0, 0.2]: exactly cells 2–3 of a map starting at −0.2, none of the neighbours.
  const WorldSlice slice(WorldOf({Box(0.1, 0.1, 0.0, 0.2, 0.2)}), 0.11);
  const OccupancyImage im = RenderSlice(slice, 0.1, 0.2);
  EXPECT_NEAR(im.origin.x(), -0.2, 1e-12);
  EXPECT_NEAR(im.origin.y(), -0.2, 1e-12);
  EXPECT_EQ(im.width, 6);
  EXPECT_EQ(im.height, 6);
  for (int j = 0; j < im.height; ++j) {
    for (int i = 0; i < im.width; ++i) {
      EXPECT_EQ(im.at(i, j), i >= 2 && i <= 3 && j >= 2 && j <= 3) << i << "," << j;
    }
  }
}

TEST(WorldMapTest, LargeBoxInteriorIsFilled) {
  const WorldSlice slice(WorldOf({Box(0.5, 0.5, 0.0, 1.0, 1.0)}), 0.11);
  const OccupancyImage im = RenderSlice(slice, 0.1, 0.0);
  EXPECT_EQ(im.width, 10);
  EXPECT_EQ(im.height, 10);
  EXPECT_EQ(CountOccupied(im), 100);
}

TEST(WorldMapTest, DiamondTouchingCellCornersIsExact) {
  // A square turned 45°, vertices (±1, 0), (0, ±1), on a 0.5 m grid. A cell is occupied iff its
  // open square meets |x| + |y| ≤ 1, i.e. iff the L1 distance from the origin to the cell is < 1.
  // Cells merely touching a vertex or an edge at a corner must stay free.
  const WorldSlice slice(WorldOf({Box(0.0, 0.0, M_PI / 4, std::sqrt(2.0), std::sqrt(2.0))}),
                         0.11);
  const OccupancyImage im = RenderSlice(slice, 0.5, 0.5);
  EXPECT_NEAR(im.origin.x(), -1.5, 1e-12);
  ASSERT_EQ(im.width, 6);
  ASSERT_EQ(im.height, 6);
  int expected_count = 0;
  for (int j = 0; j < im.height; ++j) {
    for (int i = 0; i < im.width; ++i) {
      const double x0 = im.origin.x() + 0.5 * i, y0 = im.origin.y() + 0.5 * j;
      const double mx = (x0 < 0 && x0 + 0.5 > 0) ? 0.0 : std::min(std::abs(x0), std::abs(x0 + 0.5));
      const double my = (y0 < 0 && y0 + 0.5 > 0) ? 0.0 : std::min(std::abs(y0), std::abs(y0 + 0.5));
      const bool expected = mx + my < 1.0 - 1e-9;
      expected_count += expected;
      EXPECT_EQ(im.at(i, j), expected) << "cell " << i << "," << j;
    }
  }
  EXPECT_EQ(expected_count, 12);
}

TEST(WorldMapTest, CircleCellsAreThoseItOverlaps) {
  // r = 0.13 at (1, 0) on a 0.1 m grid: the 4 × 4 block around it minus the corners, whose nearest
  // points are 0.141 m away.
  Shape can;
  can.type = ShapeType::kCylinder;
  can.pose = Eigen::Isometry3d::Identity();
  can.pose.translation() = Eigen::Vector3d(1.0, 0.0, 0.5);
  can.size = Eigen::Vector3d(0.13, 0.13, 1.0);
  const WorldSlice slice(WorldOf({can}), 0.11);
  const OccupancyImage im = RenderSlice(slice, 0.1, 0.0);
  ASSERT_EQ(im.width, 4);
  ASSERT_EQ(im.height, 4);
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const bool corner = (i == 0 || i == 3) && (j == 0 || j == 3);
      EXPECT_EQ(im.at(i, j), !corner) << i << "," << j;
    }
  }
}

TEST(WorldMapTest, ClosedMeshOutlineIsFilled) {
  // A 1 m cube as a triangle mesh: its cut is a closed square of mesh segments.
  auto mesh = std::make_shared<TriangleMesh>();
  for (int k = 0; k < 8; ++k) {
    mesh->vertices.emplace_back((k & 1) ? 1.0f : 0.0f, (k & 2) ? 1.0f : 0.0f, (k & 4) ? 1.0f : 0.0f);
  }
  mesh->triangles = {{0, 1, 3}, {0, 3, 2}, {4, 7, 5}, {4, 6, 7}, {0, 5, 1}, {0, 4, 5},
                     {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  Shape s;
  s.type = ShapeType::kMesh;
  s.mesh = mesh;
  const WorldSlice slice(WorldOf({s}), 0.5);
  const OccupancyImage im = RenderSlice(slice, 0.1, 0.1);
  EXPECT_EQ(CountOccupied(im), 100);
  EXPECT_TRUE(im.at(6, 6));   // the centre
  EXPECT_FALSE(im.at(0, 0));  // the margin
}

TEST(WorldMapTest, ZeroThicknessWallOnGridLineKeepsOneColumn) {
  Shape wall;
  wall.type = ShapeType::kPlane;
  wall.pose = Eigen::Isometry3d::Identity();
  wall.normal = Eigen::Vector3d::UnitX();
  wall.size = Eigen::Vector3d(2.0, 1.0, 0.0);  // y ∈ [−0.5, 0.5] at x = 0
  const WorldSlice slice(WorldOf({wall}), 0.11);
  const OccupancyImage im = RenderSlice(slice, 0.1, 0.2);
  EXPECT_EQ(CountOccupied(im), 10);
  const int column = static_cast<int>(std::lround((0.0 - im.origin.x()) / 0.1));
  for (int j = 0; j < im.height; ++j) {
    const double y = im.origin.y() + 0.1 * (j + 0.5);
    EXPECT_EQ(im.at(column, j), std::abs(y) < 0.5) << j;
  }
}

TEST(WorldMapTest, RejectsBadArguments) {
  const WorldSlice slice(WorldOf({Box(0, 0, 0, 1, 1)}), 0.11);
  EXPECT_THROW(RenderSlice(slice, 0.0, 0.5), std::invalid_argument);
  EXPECT_THROW(RenderSlice(slice, 0.05, -1.0), std::invalid_argument);
  const WorldSlice empty(WorldOf({}), 0.11);
  EXPECT_THROW(RenderSlice(empty, 0.05, 0.5), std::invalid_argument);
}

TEST(WorldMapTest, WritesMapServerFilesThatReadBack) {
  TempDir dir;
  // An L of two boxes, so top and bottom rows differ.
  const World world = WorldOf({Box(0.5, 0.1, 0.0, 1.0, 0.2), Box(0.1, 1.0, 0.0, 0.2, 1.6)});
  const WorldSlice slice(world, 0.11);
  const OccupancyImage im = RenderSlice(slice, 0.05, 0.25);
  WriteMapServerFiles(im, dir / "out");

  // Read back as map_server reads it: 0 = occupied (100), 254 = free (0), same row order.
  const minibot3d_map_io::OccupancyGrid grid = minibot3d_map_io::LoadMap(dir / "out.yaml");
  ASSERT_EQ(grid.width, im.width);
  ASSERT_EQ(grid.height, im.height);
  for (int row = 0; row < grid.height; ++row) {
    for (int col = 0; col < grid.width; ++col) {
      EXPECT_EQ(grid.data[static_cast<std::size_t>(row) * grid.width + col],
                im.at(col, row) ? 100 : 0)
          << col << "," << row;
    }
  }
  std::ifstream pgm(dir / "out.pgm", std::ios::binary);
  std::string magic, comment;
  std::getline(pgm, magic);
  std::getline(pgm, comment);
  EXPECT_EQ(magic, "P5");
  EXPECT_EQ(comment, "# minibot3d_sim ground-truth map");

  const YAML::Node yaml = YAML::LoadFile(dir / "out.yaml");
  EXPECT_EQ(yaml["image"].as<std::string>(), "out.pgm");
  EXPECT_DOUBLE_EQ(yaml["resolution"].as<double>(), 0.05);
  const auto origin = yaml["origin"].as<std::vector<double>>();
  ASSERT_EQ(origin.size(), 3u);
  EXPECT_NEAR(origin[0], im.origin.x(), 1e-9);
  EXPECT_NEAR(origin[1], im.origin.y(), 1e-9);
  EXPECT_EQ(origin[2], 0.0);
  EXPECT_EQ(yaml["negate"].as<int>(), 0);
  EXPECT_DOUBLE_EQ(yaml["occupied_thresh"].as<double>(), 0.65);
  EXPECT_DOUBLE_EQ(yaml["free_thresh"].as<double>(), 0.196);

  // Nothing but the two files: the temporaries were renamed into place.
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    ++files;
    EXPECT_TRUE(entry.path().filename() == "out.pgm" || entry.path().filename() == "out.yaml")
        << entry.path();
  }
  EXPECT_EQ(files, 2);

  // Round trip: the map loaded back as a floor plan renders to the same cells.
  WorldLoadOptions options;
  options.use_gazebo_model_path_env = false;
  const World walls = LoadWorld(dir / "out.yaml", options, nullptr);
  const OccupancyImage again = RenderSlice(WorldSlice(walls, 0.11), 0.05, 0.25);
  for (int j = 0; j < im.height; ++j) {
    for (int i = 0; i < im.width; ++i) {
      const Eigen::Vector2d p = im.origin + 0.05 * Eigen::Vector2d(i + 0.5, j + 0.5);
      const Eigen::Vector2d g = (p - again.origin) / 0.05;
      const int ai = static_cast<int>(std::floor(g.x())), aj = static_cast<int>(std::floor(g.y()));
      const bool inside = ai >= 0 && aj >= 0 && ai < again.width && aj < again.height;
      EXPECT_EQ(im.at(i, j), inside && again.at(ai, aj)) << i << "," << j;
    }
  }
}

TEST(WorldMapTest, WriteFailureNamesTheFile) {
  OccupancyImage im;
  im.width = im.height = 1;
  im.occupied = {1};
  try {
    WriteMapServerFiles(im, "/nonexistent_dir_for_test/out");
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir_for_test/out.pgm"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace minibot3d_sim
