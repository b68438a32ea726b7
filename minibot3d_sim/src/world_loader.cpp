// Loading SDF worlds (tinyxml2 + assimp) and map_server floor plans (minibot3d_map_io).
//
// SDF: the world's <model>s and <include>s are walked recursively, composing poses
// world ← model ← (nested model …) ← link ← collision. Only collision geometry is kept; every shape
// becomes a static Shape named "model::link::collision" (nested models give "outer::inner::…").
// Its colour comes from a <visual> of the same link (see VisualColor), since cameras should see what
// Gazebo would draw, not a uniform grey.
// Floor plan: the map is read as map_server reads it (minibot3d_map_io); its occupied cells (100,
// as ROS amcl and costmap_2d's static layer take them) are merged into maximal horizontal runs,
// then identical runs of consecutive rows into rectangles, each of which becomes one box wall.
#include "minibot3d_sim/world_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <utility>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <tinyxml2.h>

#include <sys/stat.h>

#include "minibot3d_map_io/map_io.h"

namespace minibot3d_sim {
namespace {

using tinyxml2::XMLElement;

bool IsDirectory(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool IsRegularFile(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string DirName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string JoinPath(const std::string& dir, const std::string& rel) {
  if (rel.empty()) return dir;
  if (rel.front() == '/' || dir.empty()) return rel;
  if (dir.back() == '/') return dir + rel;
  return dir + "/" + rel;
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string Extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return Lower(path.substr(dot + 1));
}

std::string Trim(const std::string& s) {
  const auto not_space = [](unsigned char c) { return !std::isspace(c); };
  auto b = std::find_if(s.begin(), s.end(), not_space);
  auto e = std::find_if(s.rbegin(), s.rend(), not_space).base();
  return b < e ? std::string(b, e) : std::string();
}

std::vector<std::string> SplitPathList(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ':')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// Parses whitespace-separated finite numbers; false when the text is not exactly that.
bool ParseNumbers(const char* text, std::vector<double>* out) {
  out->clear();
  if (text == nullptr) return false;
  std::istringstream in(text);
  std::string token;
  while (in >> token) {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(v)) return false;
    out->push_back(v);
  }
  return true;
}

// R = Rz(yaw)·Ry(pitch)·Rx(roll): SDF's fixed-axis roll-pitch-yaw.
Eigen::Matrix3d RpyToMatrix(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// State shared by the whole load: the world file, options and the warning sink, plus a mesh cache so
// a model included many times shares one TriangleMesh.
struct LoadContext {
  std::string world_file;
  const WorldLoadOptions* options = nullptr;
  std::vector<std::string>* warnings = nullptr;
  std::vector<Shape>* shapes = nullptr;
  std::map<std::pair<std::string, std::string>, std::shared_ptr<const TriangleMesh>> mesh_cache;
  int include_depth = 0;

  void Warn(const std::string& message) const {
    if (warnings != nullptr) warnings->push_back(message);
  }
};

// Where in which file an element is, for messages: "/path/x.world:42".
std::string Where(const std::string& file, const XMLElement* e) {
  return file + ":" + std::to_string(e->GetLineNum());
}

[[noreturn]] void Fail(const std::string& file, const XMLElement* e, const std::string& what) {
  throw WorldError(Where(file, e) + ": " + what);
}

const char* ChildText(const XMLElement* parent, const char* name) {
  const XMLElement* c = parent->FirstChildElement(name);
  return c == nullptr ? nullptr : c->GetText();
}

// <static>true</static>: SDF booleans are "true"/"false"/"1"/"0".
bool ParseBool(const std::string& file, const XMLElement* e) {
  const std::string v = Lower(Trim(e->GetText() == nullptr ? "" : e->GetText()));
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0") return false;
  Fail(file, e, "<" + std::string(e->Name()) + "> must be true/false, got '" + v + "'");
}

// An element's <pose> child in its parent frame (identity when absent).
Eigen::Isometry3d ParsePose(const std::string& file, const XMLElement* parent,
                            const LoadContext& ctx) {
  const XMLElement* pose = parent->FirstChildElement("pose");
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  if (pose == nullptr) return out;
  const char* relative_to = pose->Attribute("relative_to");
  if (relative_to == nullptr) relative_to = pose->Attribute("frame");
  if (relative_to != nullptr && *relative_to != '\0') {
    ctx.Warn(Where(file, pose) + ": <pose relative_to=\"" + relative_to +
             "\"> is not supported; using the parent frame");
  }
  std::vector<double> v;
  if (!ParseNumbers(pose->GetText() == nullptr ? "" : pose->GetText(), &v)) {
    Fail(file, pose, "<pose> is not a list of numbers");
  }
  if (v.empty()) return out;  // <pose/>: SDF treats it as the identity
  const char* degrees_attr = pose->Attribute("degrees");
  const bool degrees = degrees_attr != nullptr && Lower(degrees_attr) == "true";
  const char* format_attr = pose->Attribute("rotation_format");
  const bool quat = format_attr != nullptr && std::string(format_attr) == "quat_xyzw";
  if (quat) {
    if (v.size() != 7) Fail(file, pose, "<pose rotation_format=\"quat_xyzw\"> needs 7 numbers");
    Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (q.norm() < 1e-9) Fail(file, pose, "<pose> quaternion is zero");
    out.linear() = q.normalized().toRotationMatrix();
  } else {
    if (v.size() != 6) {
      Fail(file, pose, "<pose> needs 6 numbers (x y z roll pitch yaw), got " +
                           std::to_string(v.size()));
    }
    const double k = degrees ? M_PI / 180.0 : 1.0;
    out.linear() = RpyToMatrix(v[3] * k, v[4] * k, v[5] * k);
  }
  out.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return out;
}

// Reads the numbers of `parent`'s child `name`: exactly `count` values, optionally all > 0.
// `fallback` (may be null) is used when the child is absent; otherwise absence is an error.
Eigen::VectorXd ReadVector(const std::string& file, const XMLElement* parent, const char* name,
                           int count, bool positive, const Eigen::VectorXd* fallback,
                           const std::string& what) {
  const XMLElement* e = parent->FirstChildElement(name);
  if (e == nullptr) {
    if (fallback != nullptr) return *fallback;
    Fail(file, parent, what + " has no <" + name + ">");
  }
  std::vector<double> v;
  const char* text = e->GetText();
  if (!ParseNumbers(text, &v) || static_cast<int>(v.size()) != count) {
    Fail(file, e, what + ": <" + std::string(name) + "> must be " + std::to_string(count) +
                      " number(s), got '" + (text == nullptr ? "" : Trim(text)) + "'");
  }
  Eigen::VectorXd out(count);
  for (int i = 0; i < count; ++i) {
    if (positive && !(v[i] > 0.0)) {
      Fail(file, e, what + ": <" + std::string(name) + "> must be positive, got '" + Trim(text) +
                        "'");
    }
    out[i] = v[i];
  }
  return out;
}

// Model folders searched for model://NAME, in order.
std::vector<std::string> ModelSearchDirs(const LoadContext& ctx, const std::string& sdf_file) {
  std::vector<std::string> dirs = ctx.options->model_paths;
  dirs.push_back(JoinPath(DirName(sdf_file), "models"));
  const std::string world_models = JoinPath(DirName(ctx.world_file), "models");
  if (std::find(dirs.begin(), dirs.end(), world_models) == dirs.end()) {
    dirs.push_back(world_models);
  }
  if (ctx.options->use_gazebo_model_path_env) {
    const char* env = std::getenv("GAZEBO_MODEL_PATH");
    if (env != nullptr) {
      for (const std::string& d : SplitPathList(env)) dirs.push_back(d);
    }
  }
  return dirs;
}

// The folder of model NAME, or throws naming every place searched.
std::string FindModelDir(const LoadContext& ctx, const std::string& sdf_file,
                         const XMLElement* where, const std::string& name) {
  const std::vector<std::string> dirs = ModelSearchDirs(ctx, sdf_file);
  for (const std::string& d : dirs) {
    const std::string candidate = JoinPath(d, name);
    if (IsDirectory(candidate)) return candidate;
  }
  std::string searched;
  for (const std::string& d : dirs) searched += (searched.empty() ? "" : ", ") + d;
  Fail(sdf_file, where,
       "cannot resolve model://" + name + " (searched: " + searched +
           (ctx.options->use_gazebo_model_path_env ? "" : "; GAZEBO_MODEL_PATH disabled") + ")");
}

// Resolves a mesh or include URI to a path: model://NAME/rest, file://path, absolute, or relative
// to the SDF file that mentions it.
std::string ResolveUri(const LoadContext& ctx, const std::string& sdf_file,
                       const XMLElement* where, const std::string& uri) {
  const std::string kModel = "model://";
  const std::string kFile = "file://";
  if (uri.compare(0, kModel.size(), kModel) == 0) {
    const std::string rest = uri.substr(kModel.size());
    const std::size_t slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    if (name.empty()) Fail(sdf_file, where, "URI '" + uri + "' has no model name");
    const std::string dir = FindModelDir(ctx, sdf_file, where, name);
    return slash == std::string::npos ? dir : JoinPath(dir, rest.substr(slash + 1));
  }
  if (uri.compare(0, kFile.size(), kFile) == 0) {
    return JoinPath(DirName(sdf_file), uri.substr(kFile.size()));
  }
  if (uri.find("://") != std::string::npos) {
    Fail(sdf_file, where, "unsupported URI scheme in '" + uri + "'");
  }
  return JoinPath(DirName(sdf_file), uri);
}

// The model SDF file named by a model folder's model.config (highest <sdf version>, default
// model.sdf).
std::string ModelSdfFile(const std::string& model_dir, const std::string& including_file,
                         const XMLElement* where) {
  const std::string config = JoinPath(model_dir, "model.config");
  std::string sdf_name = "model.sdf";
  if (IsRegularFile(config)) {
    tinyxml2::XMLDocument doc;
    if (doc.LoadFile(config.c_str()) != tinyxml2::XML_SUCCESS) {
      throw WorldError(config + ":" + std::to_string(doc.ErrorLineNum()) +
                       ": XML parse error: " + doc.ErrorStr());
    }
    const XMLElement* model = doc.FirstChildElement("model");
    double best_version = -1.0;
    for (const XMLElement* s = model == nullptr ? nullptr : model->FirstChildElement("sdf");
         s != nullptr; s = s->NextSiblingElement("sdf")) {
      if (s->GetText() == nullptr) continue;
      const double version = s->DoubleAttribute("version", 0.0);
      if (version > best_version) {
        best_version = version;
        sdf_name = Trim(s->GetText());
      }
    }
  }
  const std::string path = JoinPath(model_dir, sdf_name);
  if (!IsRegularFile(path)) {
    Fail(including_file, where, "model folder " + model_dir + " has no SDF file " + sdf_name);
  }
  return path;
}

// Loads and checks an XML document; errors name the file and line.
void LoadXml(const std::string& path, tinyxml2::XMLDocument* doc) {
  if (!IsRegularFile(path)) throw WorldError(path + ": file not found");
  if (doc->LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) {
    throw WorldError(path + ":" + std::to_string(doc->ErrorLineNum()) +
                     ": XML parse error: " + doc->ErrorStr());
  }
}

// Colours of the materials Gazebo ships in gazebo.material, by <script><name>: the diffuse colour,
// or for a textured material (Wood, Bricks, ...) roughly the mean colour of its texture.
const std::map<std::string, Eigen::Vector3f>& GazeboMaterialColors() {
  static const std::map<std::string, Eigen::Vector3f> colors = {
      {"Gazebo/Grey", {0.7f, 0.7f, 0.7f}},
      {"Gazebo/DarkGrey", {0.175f, 0.175f, 0.175f}},
      {"Gazebo/White", {1.0f, 1.0f, 1.0f}},
      {"Gazebo/FlatBlack", {0.1f, 0.1f, 0.1f}},
      {"Gazebo/Black", {0.0f, 0.0f, 0.0f}},
      {"Gazebo/Red", {1.0f, 0.0f, 0.0f}},
      {"Gazebo/RedBright", {0.87f, 0.26f, 0.07f}},
      {"Gazebo/Green", {0.0f, 1.0f, 0.0f}},
      {"Gazebo/Blue", {0.0f, 0.0f, 1.0f}},
      {"Gazebo/SkyBlue", {0.13f, 0.44f, 0.70f}},
      {"Gazebo/Yellow", {1.0f, 1.0f, 0.0f}},
      {"Gazebo/ZincYellow", {0.9725f, 0.9529f, 0.2078f}},
      {"Gazebo/DarkYellow", {0.7f, 0.7f, 0.0f}},
      {"Gazebo/Purple", {1.0f, 0.0f, 1.0f}},
      {"Gazebo/Turquoise", {0.0f, 1.0f, 1.0f}},
      {"Gazebo/Orange", {1.0f, 0.5088f, 0.0468f}},
      {"Gazebo/Indigo", {0.33f, 0.0f, 0.5f}},
      {"Gazebo/Gold", {0.8f, 0.6487f, 0.1208f}},
      {"Gazebo/WhiteGlow", {1.0f, 1.0f, 1.0f}},
      {"Gazebo/RedGlow", {1.0f, 0.0f, 0.0f}},
      {"Gazebo/GreenGlow", {0.0f, 1.0f, 0.0f}},
      {"Gazebo/BlueGlow", {0.0f, 0.0f, 1.0f}},
      {"Gazebo/YellowGlow", {1.0f, 1.0f, 0.0f}},
      {"Gazebo/PurpleGlow", {1.0f, 0.0f, 1.0f}},
      {"Gazebo/TurquoiseGlow", {0.0f, 1.0f, 1.0f}},
      {"Gazebo/RedTransparent", {1.0f, 0.0f, 0.0f}},
      {"Gazebo/GreenTransparent", {0.0f, 1.0f, 0.0f}},
      {"Gazebo/BlueTransparent", {0.0f, 0.0f, 1.0f}},
      {"Gazebo/GreyTransparent", {0.5f, 0.5f, 0.5f}},
      {"Gazebo/YellowTransparent", {1.0f, 1.0f, 0.0f}},
      {"Gazebo/OrangeTransparent", {1.0f, 0.44f, 0.0f}},
      {"Gazebo/Wood", {0.62f, 0.44f, 0.26f}},
      {"Gazebo/WoodFloor", {0.55f, 0.38f, 0.22f}},
      {"Gazebo/WoodPallet", {0.66f, 0.52f, 0.36f}},
      {"Gazebo/Bricks", {0.58f, 0.30f, 0.22f}},
      {"Gazebo/CeilingTiled", {0.85f, 0.85f, 0.85f}},
      {"Gazebo/PaintedWall", {0.9f, 0.89f, 0.85f}},
      {"Gazebo/Road", {0.3f, 0.3f, 0.3f}},
      {"Gazebo/Residential", {0.45f, 0.45f, 0.45f}},
      {"Gazebo/Pedestrian", {0.6f, 0.6f, 0.6f}},
  };
  return colors;
}

// The colour of a <material>: <diffuse>, else <ambient>, else a known <script><name> (SDF's
// explicit colours override the script's, as in Gazebo). False when it names no usable colour.
bool MaterialColor(const LoadContext& ctx, const std::string& file, const XMLElement* material,
                   Eigen::Vector3f* color) {
  for (const char* tag : {"diffuse", "ambient"}) {
    const XMLElement* e = material->FirstChildElement(tag);
    if (e == nullptr) continue;
    std::vector<double> v;
    if (!ParseNumbers(e->GetText(), &v) || (v.size() != 3 && v.size() != 4)) {
      ctx.Warn(Where(file, e) + ": <" + tag + "> is not 'r g b [a]'; ignored");
      continue;
    }
    for (int i = 0; i < 3; ++i) (*color)[i] = static_cast<float>(std::clamp(v[i], 0.0, 1.0));
    return true;
  }
  const XMLElement* script = material->FirstChildElement("script");
  const char* name_text = script == nullptr ? nullptr : ChildText(script, "name");
  if (name_text == nullptr) return false;
  const std::string name = Trim(name_text);
  const auto& known = GazeboMaterialColors();
  const auto it = known.find(name);
  if (it == known.end()) {
    ctx.Warn(Where(file, script) + ": material script '" + name +
             "' has no known colour; using the default grey");
    return false;
  }
  *color = it->second;
  return true;
}

// The colour Gazebo would draw a <collision> of `link` with. SDF does not tie a visual to a
// collision, so: the visual named like the collision ("x" or "x" with "collision" → "visual"), else
// the link's only visual, else the link's first visual that has a material; the default grey when
// none says.
Eigen::Vector3f VisualColor(const LoadContext& ctx, const std::string& file, const XMLElement* link,
                            const XMLElement* collision) {
  std::vector<const XMLElement*> visuals;
  for (const XMLElement* v = link->FirstChildElement("visual"); v != nullptr;
       v = v->NextSiblingElement("visual")) {
    visuals.push_back(v);
  }
  const char* cname_attr = collision->Attribute("name");
  const std::string cname = cname_attr == nullptr ? "" : cname_attr;
  std::string swapped = cname;
  const std::size_t at = swapped.find("collision");
  if (at != std::string::npos) swapped.replace(at, 9, "visual");

  const XMLElement* chosen = nullptr;
  for (const XMLElement* v : visuals) {
    const char* vname = v->Attribute("name");
    if (vname != nullptr && !cname.empty() && (cname == vname || swapped == vname)) {
      chosen = v;
      break;
    }
  }
  if (chosen == nullptr && visuals.size() == 1) chosen = visuals.front();
  if (chosen == nullptr) {
    for (const XMLElement* v : visuals) {
      if (v->FirstChildElement("material") != nullptr) {
        chosen = v;
        break;
      }
    }
  }
  Eigen::Vector3f color = DefaultShapeColor();
  const XMLElement* material = chosen == nullptr ? nullptr : chosen->FirstChildElement("material");
  if (material != nullptr) MaterialColor(ctx, file, material, &color);
  return color;
}

void AppendShape(LoadContext* ctx, Shape shape) {
  ctx->shapes->push_back(std::move(shape));
}

// One <collision>: appends its shape (or warns and skips an unsupported geometry).
void ParseCollision(LoadContext* ctx, const std::string& file, const XMLElement* collision,
                    const Eigen::Isometry3d& link_pose, const std::string& link_name,
                    const Eigen::Vector3f& color) {
  const char* cname = collision->Attribute("name");
  const std::string name = link_name + "::" + (cname == nullptr ? "collision" : cname);
  const std::string what = "collision '" + name + "'";
  const XMLElement* geometry = collision->FirstChildElement("geometry");
  if (geometry == nullptr) Fail(file, collision, what + " has no <geometry>");

  Shape shape;
  shape.name = name;
  shape.color = color;
  shape.pose = link_pose * ParsePose(file, collision, *ctx);
  bool have = false;
  std::vector<std::string> unknown;
  for (const XMLElement* g = geometry->FirstChildElement(); g != nullptr;
       g = g->NextSiblingElement()) {
    const std::string type = g->Name();
    if (type != "box" && type != "cylinder" && type != "sphere" && type != "plane" &&
        type != "mesh") {
      unknown.push_back("<" + type + ">");
      continue;
    }
    if (have) Fail(file, g, what + " has more than one geometry");
    have = true;
    if (type == "box") {
      shape.type = ShapeType::kBox;
      shape.size = ReadVector(file, g, "size", 3, true, nullptr, what + " <box>");
    } else if (type == "cylinder") {
      shape.type = ShapeType::kCylinder;
      const double r = ReadVector(file, g, "radius", 1, true, nullptr, what + " <cylinder>")[0];
      const double l = ReadVector(file, g, "length", 1, true, nullptr, what + " <cylinder>")[0];
      shape.size = Eigen::Vector3d(r, r, l);
    } else if (type == "sphere") {
      shape.type = ShapeType::kSphere;
      const double r = ReadVector(file, g, "radius", 1, true, nullptr, what + " <sphere>")[0];
      shape.size = Eigen::Vector3d(r, r, r);
    } else if (type == "plane") {
      shape.type = ShapeType::kPlane;
      const Eigen::VectorXd default_normal = Eigen::Vector3d::UnitZ();
      const Eigen::VectorXd default_size = Eigen::Vector2d(1.0, 1.0);
      const Eigen::Vector3d n =
          ReadVector(file, g, "normal", 3, false, &default_normal, what + " <plane>");
      if (n.norm() < 1e-9) Fail(file, g, what + " <plane>: <normal> is zero");
      const Eigen::VectorXd s =
          ReadVector(file, g, "size", 2, true, &default_size, what + " <plane>");
      shape.normal = n.normalized();
      shape.size = Eigen::Vector3d(s[0], s[1], 0.0);
    } else {  // mesh
      shape.type = ShapeType::kMesh;
      const char* uri_text = ChildText(g, "uri");
      const std::string uri = Trim(uri_text == nullptr ? "" : uri_text);
      if (uri.empty()) Fail(file, g, what + " <mesh> has no <uri>");
      const Eigen::VectorXd ones = Eigen::Vector3d::Ones();
      const Eigen::Vector3d scale = ReadVector(file, g, "scale", 3, true, &ones, what + " <mesh>");
      for (const XMLElement* m = g->FirstChildElement(); m != nullptr; m = m->NextSiblingElement()) {
        const std::string mname = m->Name();
        if (mname != "uri" && mname != "scale") {
          ctx->Warn(Where(file, m) + ": " + what + " <mesh>: <" + mname +
                    "> is not supported; using the whole mesh");
        }
      }
      const std::string path = ResolveUri(*ctx, file, g, uri);
      if (!IsRegularFile(path)) {
        Fail(file, g, what + ": mesh file " + path + " (from '" + uri + "') not found");
      }
      std::ostringstream key;
      key.precision(17);
      key << scale.x() << ' ' << scale.y() << ' ' << scale.z();
      auto& cached = ctx->mesh_cache[{path, key.str()}];
      if (!cached) {
        try {
          cached = std::make_shared<TriangleMesh>(LoadMesh(path, scale));
        } catch (const WorldError& e) {
          Fail(file, g, what + ": " + e.what());
        }
      }
      shape.mesh = cached;
    }
  }
  if (!unknown.empty()) {
    std::string list;
    for (const std::string& u : unknown) list += (list.empty() ? "" : ", ") + u;
    ctx->Warn(Where(file, geometry) + ": " + what + ": unsupported geometry " + list +
              (have ? " ignored" : "; collision skipped"));
  }
  if (!have) {
    if (unknown.empty()) Fail(file, geometry, what + " has an empty <geometry>");
    return;
  }
  AppendShape(ctx, std::move(shape));
}

void ParseModel(LoadContext* ctx, const std::string& file, const XMLElement* model,
                const Eigen::Isometry3d& parent_pose, const std::string& prefix,
                bool parent_static, const std::string* name_override,
                const Eigen::Isometry3d* pose_override, const bool* static_override);

// <include>: model://NAME (or a path to a model folder / SDF file), with optional <name>, <pose>,
// <static> overriding the included model's own.
void ParseInclude(LoadContext* ctx, const std::string& file, const XMLElement* include,
                  const Eigen::Isometry3d& parent_pose, const std::string& prefix,
                  bool parent_static) {
  const char* uri_text = ChildText(include, "uri");
  const std::string uri = Trim(uri_text == nullptr ? "" : uri_text);
  if (uri.empty()) Fail(file, include, "<include> has no <uri>");
  const std::string kModel = "model://";
  const std::string bare = uri.compare(0, kModel.size(), kModel) == 0
                               ? uri.substr(kModel.size())
                               : std::string();
  // Built-ins: always available, so a world runs without Gazebo's model database installed.
  if (bare == "sun") return;
  if (bare == "ground_plane") {
    Shape plane;
    plane.type = ShapeType::kPlane;
    const char* n = ChildText(include, "name");
    plane.name = prefix + (n == nullptr ? "ground_plane" : Trim(n)) + "::link::collision";
    plane.pose = parent_pose * ParsePose(file, include, *ctx);
    plane.normal = Eigen::Vector3d::UnitZ();
    plane.size = Eigen::Vector3d(100.0, 100.0, 0.0);
    plane.color = GazeboMaterialColors().at("Gazebo/Grey");  // as Gazebo's ground_plane model
    AppendShape(ctx, std::move(plane));
    return;
  }
  if (ctx->include_depth > 32) Fail(file, include, "includes nested too deeply (a cycle?)");

  std::string path = ResolveUri(*ctx, file, include, uri);
  if (IsDirectory(path)) {
    path = ModelSdfFile(path, file, include);
  } else if (!IsRegularFile(path)) {
    Fail(file, include, "included '" + uri + "' not found at " + path);
  }
  tinyxml2::XMLDocument doc;
  LoadXml(path, &doc);
  const XMLElement* root = doc.FirstChildElement("sdf");
  const XMLElement* model = root == nullptr ? nullptr : root->FirstChildElement("model");
  if (model == nullptr) model = doc.FirstChildElement("model");
  if (model == nullptr) throw WorldError(path + ": no <model> (included from " +
                                         Where(file, include) + ")");

  const char* n = ChildText(include, "name");
  const std::string name_override = n == nullptr ? std::string() : Trim(n);
  const bool has_pose = include->FirstChildElement("pose") != nullptr;
  const Eigen::Isometry3d pose_override = ParsePose(file, include, *ctx);
  const XMLElement* static_element = include->FirstChildElement("static");
  const bool static_override =
      static_element != nullptr ? ParseBool(file, static_element) : false;
  ++ctx->include_depth;
  ParseModel(ctx, path, model, parent_pose, prefix, parent_static,
             n == nullptr ? nullptr : &name_override, has_pose ? &pose_override : nullptr,
             static_element != nullptr ? &static_override : nullptr);
  --ctx->include_depth;
}

void ParseModel(LoadContext* ctx, const std::string& file, const XMLElement* model,
                const Eigen::Isometry3d& parent_pose, const std::string& prefix,
                bool parent_static, const std::string* name_override,
                const Eigen::Isometry3d* pose_override, const bool* static_override) {
  const char* attr_name = model->Attribute("name");
  const std::string name =
      name_override != nullptr ? *name_override : (attr_name == nullptr ? "model" : attr_name);
  const std::string full_name = prefix + name;
  const Eigen::Isometry3d pose =
      parent_pose * (pose_override != nullptr ? *pose_override : ParsePose(file, model, *ctx));

  bool is_static = parent_static;
  if (!is_static) {
    const XMLElement* s = model->FirstChildElement("static");
    is_static = static_override != nullptr ? *static_override
                                           : (s != nullptr && ParseBool(file, s));
    if (!is_static) {
      ctx->Warn(Where(file, model) + ": model '" + full_name +
                "' is not static; loading it as static");
      // Its nested models are part of the same (now static) body; warn once.
      is_static = true;
    }
  }

  for (const XMLElement* c = model->FirstChildElement(); c != nullptr;
       c = c->NextSiblingElement()) {
    const std::string tag = c->Name();
    if (tag == "link") {
      const char* ln = c->Attribute("name");
      const std::string link_name = full_name + "::" + (ln == nullptr ? "link" : ln);
      const Eigen::Isometry3d link_pose = pose * ParsePose(file, c, *ctx);
      for (const XMLElement* col = c->FirstChildElement("collision"); col != nullptr;
           col = col->NextSiblingElement("collision")) {
        ParseCollision(ctx, file, col, link_pose, link_name, VisualColor(*ctx, file, c, col));
      }
    } else if (tag == "model") {
      ParseModel(ctx, file, c, pose, full_name + "::", is_static, nullptr, nullptr, nullptr);
    } else if (tag == "include") {
      ParseInclude(ctx, file, c, pose, full_name + "::", is_static);
    }
    // Everything else (joint, plugin, frame, self_collide, …) has no static collision geometry.
  }
}

}  // namespace

// Reads a number from an element's text; `what` names it in the error.
double ElementNumber(const std::string& file, const XMLElement* e, const std::string& what) {
  std::vector<double> v;
  if (!ParseNumbers(e->GetText() == nullptr ? "" : e->GetText(), &v) || v.size() != 1) {
    Fail(file, e, what + " must be one number");
  }
  return v[0];
}

// An SDF <actor>: its <script> (loop, delay_start, auto_start, trajectories of waypoints) or, with
// none, its <pose>. Skin, animations and plugins are not simulated (a warning names the plugins).
Actor ParseActor(const LoadContext& ctx, const std::string& file, const XMLElement* e) {
  Actor a;
  const char* name = e->Attribute("name");
  a.name = name == nullptr ? "actor" : name;
  const std::string what = "<actor name=\"" + a.name + "\">";
  const Eigen::Isometry3d pose = ParsePose(file, e, ctx);
  a.x = pose.translation().x();
  a.y = pose.translation().y();
  a.yaw = std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
  for (const XMLElement* p = e->FirstChildElement("plugin"); p != nullptr;
       p = p->NextSiblingElement("plugin")) {
    const std::string f = p->Attribute("filename") == nullptr ? "" : p->Attribute("filename");
    if (f != "libminibot3d_social_force.so") {
      ctx.Warn(Where(file, p) + ": " + what + ": plugin '" + f +
               "' is not simulated; the actor follows its <script> (or stands at its <pose>)");
      continue;
    }
    a.social_force = true;
    const std::string where = what + " social force plugin";
    for (const XMLElement* c = p->FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
      const std::string tag = c->Name();
      if (tag == "goal") {
        std::vector<double> v;
        if (!ParseNumbers(c->GetText() == nullptr ? "" : c->GetText(), &v) || v.size() != 2) {
          Fail(file, c, where + ": <goal> must be two numbers, x y (m)");
        }
        a.social.goals.emplace_back(v[0], v[1]);
      } else if (tag == "desired_speed") {
        a.social.desired_speed = ElementNumber(file, c, where + " <desired_speed>");
      } else if (tag == "relaxation_time") {
        a.social.relaxation_time = ElementNumber(file, c, where + " <relaxation_time>");
      } else if (tag == "goal_radius") {
        a.social.goal_radius = ElementNumber(file, c, where + " <goal_radius>");
      } else {
        ctx.Warn(Where(file, c) + ": " + where + ": ignoring unknown element <" + tag + ">");
      }
    }
    try {
      ValidateSocialForceAgent(a.social, where);
    } catch (const std::invalid_argument& ex) {
      Fail(file, p, ex.what());
    }
  }
  const XMLElement* script = e->FirstChildElement("script");
  if (script == nullptr) return a;
  if (a.social_force) {
    ctx.Warn(Where(file, script) + ": " + what + ": walks by the social force model; its <script> "
             "is not used");
    return a;
  }
  for (const XMLElement* c = script->FirstChildElement(); c != nullptr;
       c = c->NextSiblingElement()) {
    const std::string tag = c->Name();
    if (tag == "loop") {
      a.loop = ParseBool(file, c);
    } else if (tag == "auto_start") {
      a.auto_start = ParseBool(file, c);
      if (!a.auto_start) {
        ctx.Warn(Where(file, c) + ": " + what + ": <auto_start>false waits for a trigger, which "
                 "the simulator never sends: the actor stands at its first waypoint");
      }
    } else if (tag == "delay_start") {
      a.delay_start = ElementNumber(file, c, what + " <delay_start>");
      if (!(a.delay_start >= 0.0)) Fail(file, c, what + ": <delay_start> must be >= 0");
    } else if (tag == "trajectory") {
      ActorTrajectory tr;
      const char* id = c->Attribute("id");
      tr.id = id == nullptr ? 0 : std::atoi(id);
      const char* type = c->Attribute("type");
      tr.type = type == nullptr ? "" : type;
      const char* tension = c->Attribute("tension");
      if (tension != nullptr) {
        std::vector<double> v;
        if (!ParseNumbers(tension, &v) || v.size() != 1 || !(v[0] >= 0.0 && v[0] <= 1.0)) {
          Fail(file, c, what + ": <trajectory tension> must be a number in [0, 1]");
        }
        tr.tension = v[0];
      }
      const std::string where_tr = what + " <trajectory id=\"" + std::to_string(tr.id) + "\">";
      for (const XMLElement* w = c->FirstChildElement(); w != nullptr;
           w = w->NextSiblingElement()) {
        if (std::string(w->Name()) != "waypoint") {
          ctx.Warn(Where(file, w) + ": " + where_tr + ": ignoring <" + w->Name() + ">");
          continue;
        }
        const XMLElement* time = w->FirstChildElement("time");
        if (time == nullptr) Fail(file, w, where_tr + ": a <waypoint> has no <time>");
        if (w->FirstChildElement("pose") == nullptr) {
          Fail(file, w, where_tr + ": a <waypoint> has no <pose>");
        }
        ActorWaypoint wp;
        wp.time = ElementNumber(file, time, where_tr + " <waypoint><time>");
        if (!(wp.time >= 0.0)) Fail(file, time, where_tr + ": a waypoint's <time> must be >= 0");
        if (!tr.waypoints.empty() && !(wp.time > tr.waypoints.back().time)) {
          Fail(file, time, where_tr + ": waypoint times must increase (" +
                               std::to_string(wp.time) + " s after " +
                               std::to_string(tr.waypoints.back().time) + " s)");
        }
        const Eigen::Isometry3d wpose = ParsePose(file, w, ctx);
        wp.x = wpose.translation().x();
        wp.y = wpose.translation().y();
        wp.z = wpose.translation().z();
        wp.yaw = std::atan2(wpose.linear()(1, 0), wpose.linear()(0, 0));
        tr.waypoints.push_back(wp);
      }
      if (tr.waypoints.empty()) Fail(file, c, where_tr + " has no <waypoint>");
      a.trajectories.push_back(std::move(tr));
    } else {
      ctx.Warn(Where(file, c) + ": " + what + ": ignoring unknown <script> element <" + tag + ">");
    }
  }
  if (a.trajectories.empty()) {
    ctx.Warn(Where(file, script) + ": " + what + ": a <script> without <trajectory>: the actor "
             "stands at its <pose>");
  }
  return a;
}

World LoadSdfWorld(const std::string& path, const WorldLoadOptions& options,
                   std::vector<std::string>* warnings) {
  tinyxml2::XMLDocument doc;
  LoadXml(path, &doc);
  const XMLElement* sdf = doc.FirstChildElement("sdf");
  if (sdf == nullptr) throw WorldError(path + ": no <sdf> root element");
  const XMLElement* world_element = sdf->FirstChildElement("world");
  if (world_element == nullptr) throw WorldError(path + ": no <world> inside <sdf>");

  World world;
  world.source = path;
  LoadContext ctx;
  ctx.world_file = path;
  ctx.options = &options;
  ctx.warnings = warnings;
  ctx.shapes = &world.shapes;

  // Elements of a world that carry no static collision geometry: ignored without a word.
  static const char* const kQuiet[] = {
      "light", "physics", "scene", "gui", "plugin", "gravity", "magnetic_field", "atmosphere",
      "spherical_coordinates", "state", "wind", "audio", "frame", "pose", "road"};
  std::vector<std::string> unknown;
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  for (const XMLElement* c = world_element->FirstChildElement(); c != nullptr;
       c = c->NextSiblingElement()) {
    const std::string tag = c->Name();
    if (tag == "model") {
      ParseModel(&ctx, path, c, identity, "", false, nullptr, nullptr, nullptr);
    } else if (tag == "include") {
      ParseInclude(&ctx, path, c, identity, "", false);
    } else if (tag == "actor") {
      world.actors.push_back(ParseActor(ctx, path, c));
      for (size_t k = 0; k + 1 < world.actors.size(); ++k) {
        if (world.actors[k].name == world.actors.back().name) {
          Fail(path, c, "two actors named '" + world.actors.back().name + "'");
        }
      }
    } else if (std::find(std::begin(kQuiet), std::end(kQuiet), tag) == std::end(kQuiet) &&
               std::find(unknown.begin(), unknown.end(), "<" + tag + ">") == unknown.end()) {
      unknown.push_back("<" + tag + ">");
    }
  }
  if (!unknown.empty()) {
    std::string list;
    for (const std::string& u : unknown) list += (list.empty() ? "" : ", ") + u;
    ctx.Warn(path + ": ignoring unsupported world elements " + list);
  }
  return world;
}

TriangleMesh LoadMesh(const std::string& path, const Eigen::Vector3d& scale) {
  if (!IsRegularFile(path)) throw WorldError(path + ": mesh file not found");
  Assimp::Importer importer;
  // Only triangles matter; drop points and lines rather than failing on them.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Assimp turns a Collada Z_UP file into its own Y-up convention, which would lay every Gazebo
  // mesh on its side; Gazebo's world is Z-up and takes the vertices as authored, so keep them.
  // The <unit> scale is still applied by assimp.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr) {
    throw WorldError(path + ": assimp cannot read the mesh: " + importer.GetErrorString());
  }
  TriangleMesh mesh;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    const std::uint32_t base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      const aiVector3D& p = am->mVertices[v];
      mesh.vertices.emplace_back(static_cast<float>(p.x * scale.x()),
                                 static_cast<float>(p.y * scale.y()),
                                 static_cast<float>(p.z * scale.z()));
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;
      mesh.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1],
                                base + face.mIndices[2]});
    }
  }
  if (mesh.triangles.empty()) throw WorldError(path + ": mesh has no triangles");
  return mesh;
}

World LoadFloorPlanWorld(const std::string& yaml_path, const WorldLoadOptions& options,
                         std::vector<std::string>* warnings) {
  (void)warnings;  // a floor plan has nothing to warn about that is not an error
  if (!IsRegularFile(yaml_path)) throw WorldError(yaml_path + ": file not found");
  if (!(options.floorplan_wall_height > 0.0)) {
    throw WorldError(yaml_path + ": floorplan_wall_height must be positive");
  }
  minibot3d_map_io::OccupancyGrid grid;
  try {
    grid = minibot3d_map_io::LoadMap(yaml_path);
  } catch (const minibot3d_map_io::MapIoError& e) {
    throw WorldError(e.what());
  }
  const double resolution = grid.resolution;
  const std::vector<double> origin = {grid.origin_x, grid.origin_y, grid.origin_theta};

  // A wall where the cell is 100. Image rows, top first, as the rectangles below are built.
  const int w = grid.width, h = grid.height;
  std::vector<std::uint8_t> occupied(static_cast<std::size_t>(w) * h, 0);
  for (int r = 0; r < h; ++r) {
    const std::int8_t* cells = grid.data.data() + static_cast<std::size_t>(h - 1 - r) * w;
    for (int c = 0; c < w; ++c) occupied[static_cast<std::size_t>(r) * w + c] = cells[c] == 100;
  }

  World world;
  world.source = yaml_path;
  const double wall_h = options.floorplan_wall_height;
  Eigen::Isometry3d map_to_world = Eigen::Isometry3d::Identity();
  map_to_world.translation() = Eigen::Vector3d(origin[0], origin[1], 0.0);
  map_to_world.linear() = Eigen::AngleAxisd(origin[2], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  // A rectangle of pixels: columns [c0, c1), image rows [r0, r1].
  auto emit = [&](int c0, int c1, int r0, int r1) {
    Shape box;
    box.type = ShapeType::kBox;
    box.name = "floorplan::walls::box_" + std::to_string(world.shapes.size());
    box.size = Eigen::Vector3d((c1 - c0) * resolution, (r1 - r0 + 1) * resolution, wall_h);
    // Image row 0 is the top of the map (largest y).
    const double cx = 0.5 * (c0 + c1) * resolution;
    const double cy = (h - 0.5 * (r0 + r1 + 1)) * resolution;
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    local.translation() = Eigen::Vector3d(cx, cy, 0.5 * wall_h);
    box.pose = map_to_world * local;
    world.shapes.push_back(std::move(box));
  };
  // Runs still growing downwards: (c0, c1) → first row.
  std::map<std::pair<int, int>, int> open;
  for (int r = 0; r <= h; ++r) {
    std::map<std::pair<int, int>, int> next;
    if (r < h) {
      const std::uint8_t* row = &occupied[static_cast<std::size_t>(r) * w];
      for (int c = 0; c < w;) {
        if (!row[c]) {
          ++c;
          continue;
        }
        int e = c;
        while (e < w && row[e]) ++e;
        const auto key = std::make_pair(c, e);
        const auto it = open.find(key);
        if (it != open.end()) {
          next[key] = it->second;
          open.erase(it);
        } else {
          next[key] = r;
        }
        c = e;
      }
    }
    for (const auto& kv : open) emit(kv.first.first, kv.first.second, kv.second, r - 1);
    open.swap(next);
  }
  return world;
}

World LoadWorld(const std::string& path, const WorldLoadOptions& options,
                std::vector<std::string>* warnings) {
  const std::string ext = Extension(path);
  if (ext == "world" || ext == "sdf") return LoadSdfWorld(path, options, warnings);
  if (ext == "yaml" || ext == "yml") return LoadFloorPlanWorld(path, options, warnings);
  throw WorldError(path + ": unknown world format '." + ext +
                   "' (expected .world, .sdf or .yaml)");
}

}  // namespace minibot3d_sim
