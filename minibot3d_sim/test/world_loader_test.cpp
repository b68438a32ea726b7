// World loading: SDF geometry and pose composition, model:// includes and built-ins, warnings, error
// messages, meshes, map_server floor plans, and the shipped worlds.
#include "minibot3d_sim/world_loader.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace minibot3d_sim {
namespace {

namespace fs = std::filesystem;

// A fresh directory under the system temp dir, removed with everything in it afterwards.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "world_loader_test.XXXXXX").string();
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

void WriteFile(const std::string& path, const std::string& content) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream out(path, std::ios::binary);
  out << content;
  ASSERT_TRUE(out.good()) << path;
}

std::string Sdf(const std::string& world_body) {
  return "<?xml version=\"1.0\"?>\n<sdf version=\"1.6\">\n<world name=\"w\">\n" + world_body +
         "\n</world>\n</sdf>\n";
}

// One static model holding one collision with the given geometry.
std::string Model(const std::string& name, const std::string& geometry,
                  const std::string& pose = "0 0 0 0 0 0") {
  return "<model name=\"" + name + "\"><static>true</static><pose>" + pose +
         "</pose><link name=\"l\"><collision name=\"c\"><geometry>" + geometry +
         "</geometry></collision></link></model>\n";
}

const char kTriangleObj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";

// Model folder with model.config naming `sdf_name`, holding one box (1 2 3) at z = 1.5 and a mesh.
void WriteModelFolder(const std::string& dir, const std::string& name,
                      const std::string& sdf_name) {
  WriteFile(dir + "/model.config", "<?xml version=\"1.0\"?><model><name>" + name +
                                       "</name><sdf version=\"1.5\">old.sdf</sdf><sdf version=\"1.6\">" +
                                       sdf_name + "</sdf></model>");
  WriteFile(dir + "/" + sdf_name,
            "<?xml version=\"1.0\"?><sdf version=\"1.6\"><model name=\"" + name +
                "\"><static>true</static><pose>5 5 0 0 0 0</pose><link name=\"link\">"
                "<collision name=\"box\"><pose>0 0 1.5 0 0 0</pose><geometry><box><size>1 2 3"
                "</size></box></geometry></collision>"
                "<collision name=\"mesh\"><geometry><mesh><uri>model://" +
                name + "/meshes/tri.obj</uri></mesh></geometry></collision>"
                       "</link></model></sdf>");
  WriteFile(dir + "/meshes/tri.obj", kTriangleObj);
}

const Shape* Find(const World& world, const std::string& name) {
  for (const Shape& s : world.shapes) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

WorldLoadOptions NoEnv() {
  WorldLoadOptions o;
  o.use_gazebo_model_path_env = false;
  return o;
}

// Expects `f` to throw WorldError whose message contains every one of `parts`.
template <typename F>
void ExpectWorldError(F f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no WorldError thrown";
  } catch (const WorldError& e) {
    const std::string msg = e.what();
    for (const std::string& p : parts) {
      EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    }
  }
}

Eigen::Matrix3d Rpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

TEST(WorldLoaderTest, EveryGeometryTypeWithComposedPoses) {
  TempDir dir;
  WriteFile(dir / "meshes/tri.obj", kTriangleObj);
  const std::string world = Sdf(
      "<model name=\"m\"><static>true</static><pose>1 2 0 0 0 1.5707963267948966</pose>"
      "<link name=\"l\"><pose>1 0 0 0 0 0</pose>"
      "<collision name=\"box\"><pose>0 0 0.5 0 0 0</pose>"
      "<geometry><box><size>1 2 3</size></box></geometry></collision>"
      "<collision name=\"cyl\"><pose>0 0 0 0.3 0.2 0.1</pose>"
      "<geometry><cylinder><radius>0.25</radius><length>2</length></cylinder></geometry>"
      "</collision>"
      "<collision name=\"ball\"><geometry><sphere><radius>0.4</radius></sphere></geometry>"
      "</collision>"
      "<collision name=\"wall\"><geometry><plane><normal>0 1 0</normal><size>3 4</size></plane>"
      "</geometry></collision>"
      "<collision name=\"tri\"><geometry><mesh><uri>meshes/tri.obj</uri><scale>2 3 4</scale>"
      "</mesh></geometry></collision>"
      "<visual name=\"v\"><geometry><box><size>9 9 9</size></box></geometry></visual>"
      "</link></model>");
  WriteFile(dir / "w.world", world);
  std::vector<std::string> warnings;
  const World w = LoadWorld(dir / "w.world", NoEnv(), &warnings);
  EXPECT_EQ(w.source, dir / "w.world");
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  ASSERT_EQ(w.shapes.size(), 5u);  // the <visual> is not a shape

  // world ← model (1, 2, yaw 90°) ← link (1, 0, 0) ← collision (0, 0, 0.5): link at (1, 3, 0).
  const Shape* box = Find(w, "m::l::box");
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(box->type, ShapeType::kBox);
  EXPECT_TRUE(box->size.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE(box->pose.translation().isApprox(Eigen::Vector3d(1, 3, 0.5), 1e-12));
  EXPECT_TRUE(box->pose.linear().isApprox(Rpy(0, 0, M_PI / 2), 1e-12));

  const Shape* cyl = Find(w, "m::l::cyl");
  ASSERT_NE(cyl, nullptr);
  EXPECT_EQ(cyl->type, ShapeType::kCylinder);
  EXPECT_TRUE(cyl->size.isApprox(Eigen::Vector3d(0.25, 0.25, 2)));
  // Fixed-axis roll-pitch-yaw: R = Rz(yaw)·Ry(pitch)·Rx(roll), composed under the model's yaw.
  EXPECT_TRUE(cyl->pose.linear().isApprox(Rpy(0, 0, M_PI / 2) * Rpy(0.3, 0.2, 0.1), 1e-12));
  EXPECT_TRUE(cyl->pose.translation().isApprox(Eigen::Vector3d(1, 3, 0), 1e-12));

  const Shape* ball = Find(w, "m::l::ball");
  ASSERT_NE(ball, nullptr);
  EXPECT_EQ(ball->type, ShapeType::kSphere);
  EXPECT_DOUBLE_EQ(ball->size.x(), 0.4);

  const Shape* wall = Find(w, "m::l::wall");
  ASSERT_NE(wall, nullptr);
  EXPECT_EQ(wall->type, ShapeType::kPlane);
  EXPECT_TRUE(wall->normal.isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_DOUBLE_EQ(wall->size.x(), 3.0);
  EXPECT_DOUBLE_EQ(wall->size.y(), 4.0);

  const Shape* tri = Find(w, "m::l::tri");
  ASSERT_NE(tri, nullptr);
  EXPECT_EQ(tri->type, ShapeType::kMesh);
  ASSERT_TRUE(tri->mesh);
  EXPECT_EQ(tri->mesh->triangles.size(), 2u);
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(-1e9f);
  for (const Eigen::Vector3f& v : tri->mesh->vertices) hi = hi.cwiseMax(v);
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3f(2, 3, 4)));  // scaled
}

TEST(WorldLoaderTest, NestedModelsComposeAndPrefixNames) {
  TempDir dir;
  WriteFile(dir / "w.sdf",
            Sdf("<model name=\"outer\"><static>1</static><pose>10 0 0 0 0 0</pose>"
                "<model name=\"inner\"><pose>0 2 0 0 0 0</pose><link name=\"l\">"
                "<collision name=\"c\"><pose>0 0 0.5 0 0 0</pose>"
                "<geometry><box><size>1 1 1</size></box></geometry></collision></link></model>"
                "</model>"));
  std::vector<std::string> warnings;
  const World w = LoadWorld(dir / "w.sdf", NoEnv(), &warnings);
  ASSERT_EQ(w.shapes.size(), 1u);
  EXPECT_EQ(w.shapes[0].name, "outer::inner::l::c");
  EXPECT_TRUE(w.shapes[0].pose.translation().isApprox(Eigen::Vector3d(10, 2, 0.5)));
  EXPECT_TRUE(warnings.empty());  // the static parent makes the nested model static too
}

TEST(WorldLoaderTest, IncludeFromModelsFolderNextToTheWorld) {
  TempDir dir;
  WriteModelFolder(dir / "models/crate", "crate", "crate.sdf");
  WriteFile(dir / "w.world",
            Sdf("<include><uri>model://crate</uri></include>\n"
                "<include><uri>model://crate</uri><name>crate2</name>"
                "<pose>1 0 0 0 0 3.141592653589793</pose></include>"));
  const World w = LoadWorld(dir / "w.world", NoEnv(), nullptr);
  ASSERT_EQ(w.shapes.size(), 4u);
  const Shape* own_pose = Find(w, "crate::link::box");
  ASSERT_NE(own_pose, nullptr);
  EXPECT_TRUE(own_pose->pose.translation().isApprox(Eigen::Vector3d(5, 5, 1.5)));
  // The include's <pose> replaces the model's own.
  const Shape* moved = Find(w, "crate2::link::box");
  ASSERT_NE(moved, nullptr);
  EXPECT_TRUE(moved->pose.translation().isApprox(Eigen::Vector3d(1, 0, 1.5)));
  EXPECT_TRUE(moved->pose.linear().isApprox(Rpy(0, 0, M_PI), 1e-12));
  const Shape* mesh = Find(w, "crate2::link::mesh");
  ASSERT_NE(mesh, nullptr);
  ASSERT_TRUE(mesh->mesh);
  // Both includes share one loaded mesh.
  EXPECT_EQ(mesh->mesh, Find(w, "crate::link::mesh")->mesh);
}

TEST(WorldLoaderTest, IncludeThroughOptionsAndGazeboModelPath) {
  TempDir dir;
  WriteModelFolder(dir / "lib/crate", "crate", "model.sdf");
  WriteFile(dir / "worlds/w.world", Sdf("<include><uri>model://crate</uri></include>"));
  WorldLoadOptions options = NoEnv();
  options.model_paths = {dir / "lib"};
  EXPECT_EQ(LoadWorld(dir / "worlds/w.world", options, nullptr).shapes.size(), 2u);

  // GAZEBO_MODEL_PATH, colon-separated, only when enabled.
  ::setenv("GAZEBO_MODEL_PATH", ("/nonexistent:" + (dir / "lib")).c_str(), 1);
  WorldLoadOptions env;
  env.use_gazebo_model_path_env = true;
  EXPECT_EQ(LoadWorld(dir / "worlds/w.world", env, nullptr).shapes.size(), 2u);
  ExpectWorldError([&] { LoadWorld(dir / "worlds/w.world", NoEnv(), nullptr); },
                   {dir / "worlds/w.world", "model://crate", dir / "worlds/models"});
  ::unsetenv("GAZEBO_MODEL_PATH");
}

TEST(WorldLoaderTest, GroundPlaneAndSunAreBuiltIn) {
  TempDir dir;  // no models/ folder anywhere
  WriteFile(dir / "w.world", Sdf("<include><uri>model://ground_plane</uri></include>"
                                 "<include><uri>model://sun</uri></include>"
                                 "<light name=\"l\" type=\"point\"/><gui/><scene/>"
                                 "<physics type=\"ode\"/>"));
  std::vector<std::string> warnings;
  const World w = LoadWorld(dir / "w.world", NoEnv(), &warnings);
  ASSERT_EQ(w.shapes.size(), 1u);
  EXPECT_EQ(w.shapes[0].type, ShapeType::kPlane);
  EXPECT_TRUE(w.shapes[0].normal.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(w.shapes[0].pose.translation().norm(), 0.0, 1e-12);
  EXPECT_TRUE(warnings.empty());
}

TEST(WorldLoaderTest, ColoursComeFromTheVisualOfTheSameLink) {
  TempDir dir;
  const std::string box = "<geometry><box><size>1 1 1</size></box></geometry>";
  const std::string world = Sdf(
      // Explicit diffuse wins over the script, as in Gazebo.
      "<model name=\"diffuse\"><static>true</static><link name=\"l\">"
      "<collision name=\"c\">" + box + "</collision>"
      "<visual name=\"v\">" + box + "<material><script><name>Gazebo/Blue</name></script>"
      "<diffuse>0.2 0.4 0.6 1</diffuse></material></visual></link></model>"
      // Ambient alone, and a value out of [0, 1] clamped.
      "<model name=\"ambient\"><static>true</static><link name=\"l\">"
      "<collision name=\"c\">" + box + "</collision>"
      "<visual name=\"v\">" + box + "<material><ambient>1.5 0.5 0</ambient></material></visual>"
      "</link></model>"
      // A script name Gazebo ships.
      "<model name=\"script\"><static>true</static><link name=\"l\">"
      "<collision name=\"c\">" + box + "</collision>"
      "<visual name=\"v\">" + box + "<material><script>"
      "<uri>file://media/materials/scripts/gazebo.material</uri><name>Gazebo/Orange</name>"
      "</script></material></visual></link></model>"
      // Two collisions, two visuals: matched by name ("wall_collision" ↔ "wall_visual", "post").
      "<model name=\"pair\"><static>true</static><link name=\"l\">"
      "<collision name=\"wall_collision\">" + box + "</collision>"
      "<collision name=\"post\">" + box + "</collision>"
      "<visual name=\"post\">" + box + "<material><diffuse>0 1 0 1</diffuse></material></visual>"
      "<visual name=\"wall_visual\">" + box +
      "<material><script><name>Gazebo/Wood</name></script></material></visual>"
      "</link></model>"
      // No visual, and an unknown script: the default grey (the latter with a warning).
      "<model name=\"bare\"><static>true</static><link name=\"l\">"
      "<collision name=\"c\">" + box + "</collision></link></model>"
      "<model name=\"custom\"><static>true</static><link name=\"l\">"
      "<collision name=\"c\">" + box + "</collision>"
      "<visual name=\"v\">" + box + "<material><script><name>My/Paint</name></script>"
      "</material></visual></link></model>"
      "<include><uri>model://ground_plane</uri></include>");
  WriteFile(dir / "w.world", world);
  std::vector<std::string> warnings;
  const World w = LoadWorld(dir / "w.world", NoEnv(), &warnings);
  const auto color = [&](const std::string& name) {
    const Shape* s = Find(w, name);
    EXPECT_NE(s, nullptr) << name;
    return s == nullptr ? Eigen::Vector3f(-1, -1, -1) : s->color;
  };
  EXPECT_TRUE(color("diffuse::l::c").isApprox(Eigen::Vector3f(0.2f, 0.4f, 0.6f)));
  EXPECT_TRUE(color("ambient::l::c").isApprox(Eigen::Vector3f(1.0f, 0.5f, 0.0f)));
  EXPECT_TRUE(color("script::l::c").isApprox(Eigen::Vector3f(1.0f, 0.5088f, 0.0468f)));
  EXPECT_TRUE(color("pair::l::post").isApprox(Eigen::Vector3f(0.0f, 1.0f, 0.0f)));
  const Eigen::Vector3f wood = color("pair::l::wall_collision");
  EXPECT_GT(wood.x(), wood.y());  // brown
  EXPECT_GT(wood.y(), wood.z());
  EXPECT_TRUE(color("bare::l::c").isApprox(DefaultShapeColor()));
  EXPECT_TRUE(color("custom::l::c").isApprox(DefaultShapeColor()));
  EXPECT_TRUE(color("ground_plane::link::collision").isApprox(Eigen::Vector3f(0.7f, 0.7f, 0.7f)));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("My/Paint"), std::string::npos) << warnings[0];
}

TEST(WorldLoaderTest, DynamicModelIsLoadedStaticWithWarning) {
  TempDir dir;
  WriteFile(dir / "w.world",
            Sdf("<model name=\"rolling_ball\"><link name=\"l\"><collision name=\"c\"><geometry>"
                "<sphere><radius>0.2</radius></sphere></geometry></collision></link></model>"));
  std::vector<std::string> warnings;
  const World w = LoadWorld(dir / "w.world", NoEnv(), &warnings);
  EXPECT_EQ(w.shapes.size(), 1u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("rolling_ball"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("static"), std::string::npos) << warnings[0];
}

TEST(WorldLoaderTest, UnsupportedGeometryIsNamedInAWarning) {
  TempDir dir;
  WriteFile(dir / "w.world",
            Sdf(Model("m", "<polyline><point>0 0</point><height>1</height></polyline>") +
                "<population name=\"crowd\"/>"));
  std::vector<std::string> warnings;
  const World w = LoadWorld(dir / "w.world", NoEnv(), &warnings);
  EXPECT_TRUE(w.shapes.empty());
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("<polyline>"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("<population>"), std::string::npos) << warnings[1];
}

TEST(WorldLoaderTest, ErrorsNameTheFile) {
  TempDir dir;
  ExpectWorldError([&] { LoadWorld(dir / "missing.world", NoEnv(), nullptr); },
                   {dir / "missing.world", "not found"});

  WriteFile(dir / "bad.world", "<?xml version=\"1.0\"?>\n<sdf>\n<world>\n<model>\n</sdf>\n");
  ExpectWorldError([&] { LoadWorld(dir / "bad.world", NoEnv(), nullptr); },
                   {dir / "bad.world", "XML parse error"});

  WriteFile(dir / "noworld.world", "<?xml version=\"1.0\"?><sdf version=\"1.6\"></sdf>");
  ExpectWorldError([&] { LoadWorld(dir / "noworld.world", NoEnv(), nullptr); },
                   {dir / "noworld.world", "<world>"});

  WriteFile(dir / "size.world", Sdf(Model("crate", "<box><size>1 -2 3</size></box>")));
  ExpectWorldError([&] { LoadWorld(dir / "size.world", NoEnv(), nullptr); },
                   {dir / "size.world", "crate::l::c", "<size>", "positive"});

  WriteFile(dir / "short.world", Sdf(Model("crate", "<box><size>1 2</size></box>")));
  ExpectWorldError([&] { LoadWorld(dir / "short.world", NoEnv(), nullptr); },
                   {dir / "short.world", "<size>", "3 number"});

  WriteFile(dir / "radius.world", Sdf(Model("can", "<cylinder><length>1</length></cylinder>")));
  ExpectWorldError([&] { LoadWorld(dir / "radius.world", NoEnv(), nullptr); },
                   {dir / "radius.world", "can::l::c", "<radius>"});

  WriteFile(dir / "include.world", Sdf("<include><uri>model://no_such_model</uri></include>"));
  WorldLoadOptions options = NoEnv();
  options.model_paths = {dir / "extra"};
  ExpectWorldError([&] { LoadWorld(dir / "include.world", options, nullptr); },
                   {dir / "include.world", "model://no_such_model", dir / "extra",
                    dir / "models"});

  WriteFile(dir / "mesh.world", Sdf(Model("statue", "<mesh><uri>meshes/gone.stl</uri></mesh>")));
  ExpectWorldError([&] { LoadWorld(dir / "mesh.world", NoEnv(), nullptr); },
                   {dir / "mesh.world", dir / "meshes/gone.stl"});

  WriteFile(dir / "meshes/broken.dae", "<COLLADA><this is not collada");
  WriteFile(dir / "garbled.world",
            Sdf(Model("statue", "<mesh><uri>file://meshes/broken.dae</uri></mesh>")));
  ExpectWorldError([&] { LoadWorld(dir / "garbled.world", NoEnv(), nullptr); },
                   {dir / "garbled.world", dir / "meshes/broken.dae", "assimp"});

  WriteFile(dir / "w.txt", "");
  ExpectWorldError([&] { LoadWorld(dir / "w.txt", NoEnv(), nullptr); }, {dir / "w.txt"});
}

TEST(WorldLoaderTest, MalformedXmlReportsTheLine) {
  TempDir dir;
  WriteFile(dir / "bad.world", "<?xml version=\"1.0\"?>\n<sdf>\n<world>\n<model name=\"a\">\n"
                               "<static>true</stat>\n</model></world></sdf>\n");
  ExpectWorldError([&] { LoadWorld(dir / "bad.world", NoEnv(), nullptr); },
                   {dir / "bad.world:5"});
}

TEST(WorldLoaderTest, MeshFormatsAndColladaUpAxis) {
  TempDir dir;
  // ASCII STL.
  WriteFile(dir / "t.stl",
            "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
            "endloop\nendfacet\nendsolid t\n");
  const TriangleMesh stl = LoadMesh(dir / "t.stl", Eigen::Vector3d(2, 2, 2));
  ASSERT_EQ(stl.triangles.size(), 1u);
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(-1e9f);
  for (const Eigen::Vector3f& v : stl.vertices) hi = hi.cwiseMax(v);
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3f(2, 2, 0)));

  // A Z_UP Collada triangle standing in the x-z plane stays standing (as in Gazebo), and the
  // node transform (a 1 m lift) is applied.
  WriteFile(dir / "t.dae", R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 0 2</float_array>
      <technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/>
      <param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common>
    </source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n">
    <translate>0 0 1</translate><instance_geometry url="#g"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)");
  const TriangleMesh dae = LoadMesh(dir / "t.dae", Eigen::Vector3d::Ones());
  ASSERT_EQ(dae.triangles.size(), 1u);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f);
  hi = Eigen::Vector3f::Constant(-1e9f);
  for (const Eigen::Vector3f& v : dae.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3f(0, 0, 1))) << lo.transpose();
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3f(1, 0, 3))) << hi.transpose();

  ExpectWorldError([&] { LoadMesh(dir / "none.obj", Eigen::Vector3d::Ones()); },
                   {dir / "none.obj"});
}

// Writes a binary PGM, row 0 first (the top of the map).
void WritePgm(const std::string& path, int w, int h, const std::vector<int>& pixels) {
  std::string data = "P5\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
  for (int p : pixels) data.push_back(static_cast<char>(p));
  WriteFile(path, data);
}

std::string MapYaml(const std::string& image, int negate = 0) {
  return "image: " + image +
         "\nresolution: 0.1\norigin: [-1.0, -2.0, 0.0]\nnegate: " + std::to_string(negate) +
         "\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
}

TEST(WorldLoaderTest, FloorPlanBecomesMergedBoxes) {
  TempDir dir;
  // 10 × 8 pixels: a 3 × 2 block of black (rows 1–2, columns 2–4), one dark-grey pixel (value 80,
  // p = 0.69 > 0.65: occupied) at row 6, column 8, and a mid-grey one (value 100, p = 0.61: free).
  constexpr int kW = 10, kH = 8;
  std::vector<int> px(kW * kH, 254);
  for (int r = 1; r <= 2; ++r) {
    for (int c = 2; c <= 4; ++c) px[r * kW + c] = 0;
  }
  px[6 * kW + 8] = 80;
  px[4 * kW + 1] = 100;
  WritePgm(dir / "map.pgm", kW, kH, px);
  WriteFile(dir / "map.yaml", MapYaml("map.pgm"));
  WorldLoadOptions options = NoEnv();
  options.floorplan_wall_height = 0.7;
  const World w = LoadWorld(dir / "map.yaml", options, nullptr);
  ASSERT_EQ(w.shapes.size(), 2u);
  const Shape* block = nullptr;
  const Shape* dot = nullptr;
  for (const Shape& s : w.shapes) {
    EXPECT_EQ(s.type, ShapeType::kBox);
    EXPECT_NEAR(s.size.z(), 0.7, 1e-12);
    EXPECT_NEAR(s.pose.translation().z(), 0.35, 1e-12);
    (s.size.x() > 0.15 ? block : dot) = &s;
  }
  ASSERT_NE(block, nullptr);
  ASSERT_NE(dot, nullptr);
  // Columns 2–4 → x ∈ [−0.8, −0.5]; rows 1–2 from the top of 8 → y ∈ [−2 + 0.5, −2 + 0.7].
  EXPECT_TRUE(block->size.head<2>().isApprox(Eigen::Vector2d(0.3, 0.2)));
  EXPECT_TRUE(block->pose.translation().head<2>().isApprox(Eigen::Vector2d(-0.65, -1.4)));
  EXPECT_TRUE(dot->pose.translation().head<2>().isApprox(Eigen::Vector2d(-0.15, -1.85)));

  // negate: 1 flips the meaning: now the white pixels are the walls.
  WriteFile(dir / "neg.yaml", MapYaml("map.pgm", 1));
  const World neg = LoadWorld(dir / "neg.yaml", options, nullptr);
  double area = 0.0;
  for (const Shape& s : neg.shapes) area += s.size.x() * s.size.y();
  // p = value/255 > 0.65: only the 254-valued pixels (all but 8).
  EXPECT_NEAR(area, (kW * kH - 8) * 0.01, 1e-9);
}

TEST(WorldLoaderTest, FloorPlanMergesRowsIntoRectangles) {
  TempDir dir;
  // 400 × 400, a 2-pixel-thick frame: 4 rectangles, not thousands of boxes.
  constexpr int kN = 400;
  std::vector<int> px(kN * kN, 254);
  for (int r = 0; r < kN; ++r) {
    for (int c = 0; c < kN; ++c) {
      if (r < 2 || r >= kN - 2 || c < 2 || c >= kN - 2) px[r * kN + c] = 0;
    }
  }
  WritePgm(dir / "frame.pgm", kN, kN, px);
  WriteFile(dir / "frame.yaml", MapYaml("frame.pgm"));
  const World w = LoadWorld(dir / "frame.yaml", NoEnv(), nullptr);
  EXPECT_EQ(w.shapes.size(), 4u);
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const Shape& s : w.shapes) {
    lo = lo.cwiseMin(s.pose.translation().head<2>() - 0.5 * s.size.head<2>());
    hi = hi.cwiseMax(s.pose.translation().head<2>() + 0.5 * s.size.head<2>());
  }
  EXPECT_TRUE(lo.isApprox(Eigen::Vector2d(-1.0, -2.0)));
  EXPECT_TRUE(hi.isApprox(Eigen::Vector2d(39.0, 38.0)));
}

TEST(WorldLoaderTest, FloorPlanErrorsNameTheKey) {
  TempDir dir;
  WritePgm(dir / "map.pgm", 2, 2, {0, 254, 254, 254});
  WriteFile(dir / "nores.yaml", "image: map.pgm\norigin: [0, 0, 0]\nnegate: 0\n"
                                "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  ExpectWorldError([&] { LoadWorld(dir / "nores.yaml", NoEnv(), nullptr); },
                   {dir / "nores.yaml", "resolution", "missing"});
  WriteFile(dir / "badres.yaml", "image: map.pgm\nresolution: fine\norigin: [0, 0, 0]\n"
                                 "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  ExpectWorldError([&] { LoadWorld(dir / "badres.yaml", NoEnv(), nullptr); },
                   {dir / "badres.yaml", "resolution"});
  WriteFile(dir / "noimg.yaml", MapYaml("gone.pgm"));
  ExpectWorldError([&] { LoadWorld(dir / "noimg.yaml", NoEnv(), nullptr); },
                   {dir / "noimg.yaml", "image", "gone.pgm"});
  WriteFile(dir / "origin.yaml", "image: map.pgm\nresolution: 0.1\norigin: [0, 0]\nnegate: 0\n"
                                 "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  ExpectWorldError([&] { LoadWorld(dir / "origin.yaml", NoEnv(), nullptr); },
                   {dir / "origin.yaml", "origin"});
}

#ifdef MINIBOT3D_SIM_SOURCE_DIR
TEST(WorldLoaderTest, ShippedWorldsLoad) {
  const std::string worlds = std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/worlds/";
  std::vector<std::string> warnings;
  const World apartment = LoadWorld(worlds + "default.world", NoEnv(), &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  int boxes = 0, cylinders = 0, meshes = 0, planes = 0;
  for (const Shape& s : apartment.shapes) {
    boxes += s.type == ShapeType::kBox;
    cylinders += s.type == ShapeType::kCylinder;
    planes += s.type == ShapeType::kPlane;
    if (s.type == ShapeType::kMesh) {
      ++meshes;
      ASSERT_TRUE(s.mesh);
      EXPECT_GT(s.mesh->triangles.size(), 100u);
    }
  }
  EXPECT_GT(boxes, 20);
  EXPECT_GE(cylinders, 5);
  EXPECT_EQ(meshes, 1);
  EXPECT_EQ(planes, 1);

  warnings.clear();
  const World arena = LoadWorld(worlds + "arena.world", NoEnv(), &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_GE(arena.shapes.size(), 8u);
}
#endif

}  // namespace
}  // namespace minibot3d_sim
