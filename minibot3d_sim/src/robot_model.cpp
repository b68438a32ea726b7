#include "minibot3d_sim/robot_model.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <sys/stat.h>
#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>
#include <urdf/model.h>

#include "minibot3d_sim/world_loader.h"

namespace minibot3d_sim {
namespace {

// Largest image side a camera may have (the issue of an exploding ray count, not of Embree).
constexpr int kMaxImageSide = 1 << 15;
// A non-driven link whose collision geometry comes within this of the floor carries load (m).
constexpr double kSupportClearance = 1e-3;

Eigen::Isometry3d ToEigen(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return t;
}

Eigen::Matrix3d Rpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

std::vector<double> Numbers(const std::string& text, size_t n, const std::string& where) {
  std::istringstream in(text);
  std::vector<double> v(n);
  for (double& x : v) {
    if (!(in >> x) || !std::isfinite(x)) {
      throw RobotModelError(where + " needs " + std::to_string(n) + " numbers, got '" + text + "'");
    }
  }
  std::string rest;
  if (in >> rest) {
    throw RobotModelError(where + " needs " + std::to_string(n) + " numbers, got '" + text + "'");
  }
  return v;
}

// SDF pose text "x y z roll pitch yaw" → transform (R = Rz(yaw) Ry(pitch) Rx(roll)).
Eigen::Isometry3d ParseSdfPose(const std::string& text, const std::string& where) {
  const std::vector<double> v = Numbers(text, 6, where + ": <pose>");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  t.linear() = Rpy(v[3], v[4], v[5]);
  return t;
}

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::string Attribute(const tinyxml2::XMLElement* e, const char* name) {
  const char* a = e->Attribute(name);
  return a ? a : "";
}

// An element's leaves as (path, text), paths relative to `e` ("ray/scan/horizontal/samples").
// Attributes of inner elements count as children (<noise type="gaussian"> → "noise/type"); the
// first of two equal paths wins, as SDF's GetElement does. Elements named in `skip` are left out.
void Flatten(const tinyxml2::XMLElement* e, const std::string& prefix,
             const std::set<std::string>& skip,
             std::vector<std::pair<std::string, std::string>>* out) {
  for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string name = c->Name();
    if (prefix.empty() && skip.count(name)) continue;
    const std::string path = prefix.empty() ? name : prefix + "/" + name;
    for (const tinyxml2::XMLAttribute* a = c->FirstAttribute(); a; a = a->Next()) {
      out->emplace_back(path + "/" + a->Name(), a->Value());
    }
    if (c->FirstChildElement()) {
      Flatten(c, path, skip, out);
    } else {
      out->emplace_back(path, c->GetText() ? Trim(c->GetText()) : "");
    }
  }
}

// Reads `tags` into *options through `table`; tags the table lacks become one warning each.
template <typename T>
void ReadTags(const options::OptionTable<T>& table,
              const std::vector<std::pair<std::string, std::string>>& tags,
              const std::string& where, T* options, std::vector<std::string>* warnings,
              std::set<std::string>* given = nullptr) {
  std::set<std::string> seen;
  for (const auto& kv : tags) {
    if (!seen.insert(kv.first).second) continue;  // SDF reads the first of equal tags
    if (!table.Has(kv.first)) {
      warnings->push_back(where + ": <" + kv.first + "> is not simulated; ignored");
      continue;
    }
    try {
      table.Set(kv.first, kv.second, options);
    } catch (const std::invalid_argument& e) {
      throw RobotModelError(where + ": <" + kv.first + ">: " + e.what());
    }
    if (given) given->insert(kv.first);
  }
}

std::vector<std::pair<std::string, std::string>> PluginTags(const tinyxml2::XMLElement* plugin) {
  std::vector<std::pair<std::string, std::string>> tags;
  Flatten(plugin, "", {}, &tags);
  return tags;
}

std::string PluginWhere(const tinyxml2::XMLElement* plugin) {
  return "<plugin name=\"" + Attribute(plugin, "name") + "\" filename=\"" +
         Attribute(plugin, "filename") + "\">";
}

// Root-frame pose of every link at zero joint positions.
void LinkPoses(const urdf::LinkConstSharedPtr& link, const Eigen::Isometry3d& pose,
               std::map<std::string, Eigen::Isometry3d>* out) {
  (*out)[link->name] = pose;
  for (const auto& child : link->child_links) {
    LinkPoses(child, pose * ToEigen(child->parent_joint->parent_to_joint_origin_transform), out);
  }
}

// Corners of a shape's bounding box in the root frame; a mesh's vertices.
std::vector<Eigen::Vector3d> ShapeCorners(const Shape& s) {
  std::vector<Eigen::Vector3d> corners;
  if (s.type == ShapeType::kMesh) {
    for (const auto& v : s.mesh->vertices) corners.push_back(s.pose * v.cast<double>());
    return corners;
  }
  Eigen::Vector3d half;
  switch (s.type) {
    case ShapeType::kBox:
      half = 0.5 * s.size;
      break;
    case ShapeType::kCylinder:
      half = Eigen::Vector3d(s.size.x(), s.size.x(), 0.5 * s.size.z());
      break;
    default:  // sphere
      half = Eigen::Vector3d::Constant(s.size.x());
      break;
  }
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d c((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    corners.push_back(s.pose * c.cwiseProduct(half));
  }
  return corners;
}

// Points whose convex hull seen from above is the shape's outline: a box's corners, a mesh's
// vertices, the rims of a cylinder and the equator of a sphere as 32-gons circumscribing them
// (0.5 % outside the round shape, never inside it).
std::vector<Eigen::Vector3d> OutlinePoints(const Shape& s) {
  if (s.type == ShapeType::kBox || s.type == ShapeType::kMesh) return ShapeCorners(s);
  constexpr int kSides = 32;
  const double r = s.size.x() / std::cos(M_PI / kSides);
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < kSides; ++k) {
    const double a = 2.0 * M_PI * k / kSides;
    if (s.type == ShapeType::kCylinder) {
      for (double z : {-0.5 * s.size.z(), 0.5 * s.size.z()}) {
        points.push_back(s.pose * Eigen::Vector3d(r * std::cos(a), r * std::sin(a), z));
      }
    } else {  // sphere: the equator in the root frame
      points.push_back(s.pose.translation() + Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0));
    }
  }
  return points;
}

std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

bool IsFile(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
bool IsDir(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// package://PKG/rest through ROS_PACKAGE_PATH (a folder PKG holding package.xml, searched a few
// levels deep as rospack does), file://path, or a plain path.
std::string DefaultResolveMesh(const std::string& url) {
  const std::string kPackage = "package://", kFile = "file://";
  if (url.compare(0, kFile.size(), kFile) == 0) return url.substr(kFile.size());
  if (url.compare(0, kPackage.size(), kPackage) != 0) return url;
  const std::string rest = url.substr(kPackage.size());
  const size_t slash = rest.find('/');
  const std::string pkg = rest.substr(0, slash);
  const std::string tail = slash == std::string::npos ? "" : rest.substr(slash);
  const char* env = std::getenv("ROS_PACKAGE_PATH");
  std::istringstream roots(env ? env : "");
  std::function<std::string(const std::string&, int)> find = [&](const std::string& dir,
                                                                  int depth) -> std::string {
    if (IsFile(dir + "/" + pkg + "/package.xml")) return dir + "/" + pkg;
    if (depth == 0) return "";
    // A shallow scan of sub-folders that are themselves not packages.
    std::vector<std::string> subs;
    if (FILE* ls = popen(("ls -1 '" + dir + "' 2>/dev/null").c_str(), "r")) {
      char buf[4096];
      while (fgets(buf, sizeof(buf), ls)) {
        std::string name = Trim(buf);
        if (!name.empty() && name[0] != '.' && IsDir(dir + "/" + name) &&
            !IsFile(dir + "/" + name + "/package.xml")) {
          subs.push_back(dir + "/" + name);
        }
      }
      pclose(ls);
    }
    for (const auto& s : subs) {
      const std::string hit = find(s, depth - 1);
      if (!hit.empty()) return hit;
    }
    return "";
  };
  for (std::string root; std::getline(roots, root, ':');) {
    if (root.empty()) continue;
    const std::string dir = find(root, 2);
    if (!dir.empty()) return dir + tail;
  }
  return "";
}

// The robot's collision geometry (every link, every <collision>) in the root frame.
void ReadCollisions(const urdf::Model& urdf, const RobotModelOptions& options, RobotModel* m) {
  std::vector<urdf::LinkSharedPtr> links;
  urdf.getLinks(links);
  std::sort(links.begin(), links.end(),
            [](const urdf::LinkSharedPtr& a, const urdf::LinkSharedPtr& b) { return a->name < b->name; });
  std::map<std::string, std::shared_ptr<const TriangleMesh>> meshes;
  for (const auto& link : links) {
    const Eigen::Isometry3d& pose = m->link_poses.at(link->name);
    for (size_t k = 0; k < link->collision_array.size(); ++k) {
      const urdf::Collision& c = *link->collision_array[k];
      if (!c.geometry) continue;
      CollisionShape cs;
      cs.link = link->name;
      cs.shape.name = link->name + "::collision" + (k ? std::to_string(k) : "");
      cs.shape.pose = pose * ToEigen(c.origin);
      switch (c.geometry->type) {
        case urdf::Geometry::BOX: {
          auto b = std::static_pointer_cast<const urdf::Box>(c.geometry);
          cs.shape.type = ShapeType::kBox;
          cs.shape.size = Eigen::Vector3d(b->dim.x, b->dim.y, b->dim.z);
          break;
        }
        case urdf::Geometry::CYLINDER: {
          auto cy = std::static_pointer_cast<const urdf::Cylinder>(c.geometry);
          cs.shape.type = ShapeType::kCylinder;
          cs.shape.size = Eigen::Vector3d(cy->radius, cy->radius, cy->length);
          break;
        }
        case urdf::Geometry::SPHERE: {
          auto sp = std::static_pointer_cast<const urdf::Sphere>(c.geometry);
          cs.shape.type = ShapeType::kSphere;
          cs.shape.size = Eigen::Vector3d::Constant(sp->radius);
          break;
        }
        case urdf::Geometry::MESH: {
          auto me = std::static_pointer_cast<const urdf::Mesh>(c.geometry);
          const std::string where = "link '" + link->name + "' <collision><mesh filename=\"" +
                                    me->filename + "\">";
          const std::string path = options.resolve_mesh_url ? options.resolve_mesh_url(me->filename)
                                                            : DefaultResolveMesh(me->filename);
          if (path.empty()) throw RobotModelError(where + ": cannot find the file (package not found)");
          const Eigen::Vector3d scale(me->scale.x, me->scale.y, me->scale.z);
          const std::string key = path + " " + std::to_string(scale.x()) + " " +
                                  std::to_string(scale.y()) + " " + std::to_string(scale.z());
          auto& cached = meshes[key];
          if (!cached) {
            try {
              cached = std::make_shared<TriangleMesh>(LoadMesh(path, scale));
            } catch (const WorldError& e) {
              throw RobotModelError(where + ": the mesh will not load: " + e.what());
            }
            if (cached->triangles.empty()) throw RobotModelError(where + ": the mesh has no triangles");
          }
          cs.shape.type = ShapeType::kMesh;
          cs.shape.mesh = cached;
          break;
        }
        default:
          continue;
      }
      std::vector<Eigen::Vector2d> flat;
      cs.z_min = std::numeric_limits<double>::infinity();
      cs.z_max = -cs.z_min;
      for (const auto& p : ShapeCorners(cs.shape)) {
        cs.z_min = std::min(cs.z_min, p.z());
        cs.z_max = std::max(cs.z_max, p.z());
      }
      for (const auto& p : OutlinePoints(cs.shape)) flat.emplace_back(p.x(), p.y());
      cs.outline = ConvexHull(flat);
      m->collisions.push_back(std::move(cs));
    }
  }
}

struct GazeboBlocks {
  std::vector<const tinyxml2::XMLElement*> model_plugins;
  // <gazebo reference="link"> blocks, in document order.
  std::vector<std::pair<std::string, const tinyxml2::XMLElement*>> link_blocks;
};

const std::set<std::string> kKnownLinkTags = {
    "material", "mu1", "mu2", "kp", "kd", "fdir1", "maxVel", "minDepth", "selfCollide", "gravity",
    "turnGravityOff", "maxContacts", "dampingFactor", "sensor", "visual", "collision",
    "laserRetro", "self_collide", "enable_wind", "kinematic", "dampingFactor"};
const std::set<std::string> kKnownJointTags = {
    "implicitSpringDamper", "provideFeedback", "cfmDamping", "stopCfm", "stopErp",
    "springStiffness", "springReference", "fudgeFactor", "disableFixedJointLumping",
    "preserveFixedJoint"};
const std::set<std::string> kDrivePlugins = {
    "libgazebo_ros_skid_steer_drive.so", "libgazebo_ros_diff_drive.so",
    "libgazebo_ros_planar_move.so", "libgazebo_ros_control.so"};

GazeboBlocks ReadGazeboBlocks(const tinyxml2::XMLElement* robot, const urdf::Model& urdf,
                              RobotModel* m) {
  GazeboBlocks b;
  for (auto* g = robot->FirstChildElement("gazebo"); g; g = g->NextSiblingElement("gazebo")) {
    const char* ref = g->Attribute("reference");
    if (!ref) {
      for (auto* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
        const std::string tag = e->Name();
        if (tag == "plugin") {
          b.model_plugins.push_back(e);
        } else if (tag != "static" && tag != "self_collide" && tag != "allow_auto_disable") {
          m->warnings.push_back("<gazebo> tag <" + tag + "> is not simulated; ignored");
        }
      }
      continue;
    }
    if (urdf.getLink(ref)) {
      b.link_blocks.emplace_back(ref, g);
      for (auto* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
        if (!kKnownLinkTags.count(e->Name())) {
          m->warnings.push_back(std::string("<gazebo reference=\"") + ref + "\"> tag <" +
                                e->Name() + "> is not simulated; ignored");
        }
      }
    } else if (urdf.getJoint(ref)) {
      for (auto* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
        if (!kKnownJointTags.count(e->Name())) {
          m->warnings.push_back(std::string("<gazebo reference=\"") + ref + "\"> tag <" +
                                e->Name() + "> is not simulated; ignored");
        }
      }
    } else {
      throw RobotModelError(std::string("<gazebo reference=\"") + ref +
                            "\"> names neither a link nor a joint of the URDF");
    }
  }
  return b;
}

// Gazebo's spawn_model gives every plugin without one the robot's namespace; with
// -robot_namespace it replaces every plugin's.
std::string Namespace(const std::string& given, bool has, const RobotModelOptions& o) {
  return has && !o.replace_namespaces ? given : o.spawn_namespace;
}

urdf::JointConstSharedPtr WheelJoint(const urdf::Model& urdf, const std::string& joint,
                                     const std::string& where, const std::string& tag) {
  auto j = urdf.getJoint(joint);
  if (!j) {
    throw RobotModelError(where + ": <" + tag + "> names joint '" + joint +
                          "', which is not in the URDF");
  }
  if (j->type != urdf::Joint::CONTINUOUS && j->type != urdf::Joint::REVOLUTE) {
    throw RobotModelError(where + ": joint '" + joint + "' (" + tag +
                          ") must be continuous or revolute");
  }
  return j;
}

// Fills a driven wheel from its joint, link, <gazebo reference> tags and limits.
WheelSpec MakeWheel(const urdf::Model& urdf, const urdf::JointConstSharedPtr& joint,
                    double fallback_radius, const RobotModel& m,
                    const std::map<std::string, const tinyxml2::XMLElement*>& link_tags,
                    std::vector<std::string>* warnings, const std::string& where) {
  WheelSpec w;
  w.joint = joint->name;
  w.link = joint->child_link_name;
  auto link = urdf.getLink(w.link);
  const Eigen::Isometry3d& pose = m.link_poses.at(w.link);
  w.position = pose.translation();
  w.left = w.position.y() > 0.0;
  const Eigen::Vector3d axis = pose.linear() * Eigen::Vector3d(joint->axis.x, joint->axis.y, joint->axis.z);
  if (std::abs(std::abs(axis.normalized().y()) - 1.0) > 1e-3) {
    throw RobotModelError(where + ": wheel joint '" + w.joint +
                          "': its axis must be the robot's y axis (left), e.g. <axis xyz=\"0 1 0\"/>");
  }
  auto cyl = link->collision
                 ? std::dynamic_pointer_cast<const urdf::Cylinder>(link->collision->geometry)
                 : nullptr;
  auto sph = link->collision
                 ? std::dynamic_pointer_cast<const urdf::Sphere>(link->collision->geometry)
                 : nullptr;
  if (cyl) {
    w.radius = cyl->radius;
    w.width = cyl->length;
  } else if (sph) {
    w.radius = sph->radius;
    w.width = 2.0 * sph->radius;
  } else {
    w.radius = fallback_radius;
    w.width = 0.02;
    warnings->push_back("wheel link '" + w.link + "' has no cylinder collision; using the drive's "
                        "wheel diameter");
  }
  if (std::abs(2.0 * w.radius - 2.0 * fallback_radius) > 1e-3) {
    warnings->push_back("wheel link '" + w.link + "' radius " + std::to_string(w.radius) +
                        " disagrees with the drive's wheel diameter " +
                        std::to_string(2.0 * fallback_radius) + "; odometry uses the drive's");
  }
  if (link->inertial) {
    w.mass = link->inertial->mass;
    Eigen::Matrix3d i;
    const auto& in = *link->inertial;
    i << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    const Eigen::Matrix3d r = pose.linear() * ToEigen(in.origin).linear();
    w.inertia_axle = (r * i * r.transpose())(1, 1);
  }
  if (w.mass <= 0 || w.inertia_axle <= 0) {
    throw RobotModelError("wheel link '" + w.link + "' needs an <inertial> with mass > 0");
  }
  if (joint->limits) {
    w.effort_limit = joint->limits->effort;
    w.velocity_limit = joint->limits->velocity;
  }
  if (auto it = link_tags.find(w.link); it != link_tags.end()) {
    const std::string lw = "<gazebo reference=\"" + w.link + "\">";
    auto number = [&](const char* tag, double fallback) {
      const tinyxml2::XMLElement* e = it->second->FirstChildElement(tag);
      if (!e || !e->GetText()) return fallback;
      return Numbers(e->GetText(), 1, lw + " <" + tag + ">")[0];
    };
    w.mu1 = number("mu1", w.mu1);
    w.mu2 = number("mu2", w.mu2);
    w.kp = number("kp", w.kp);
    w.kd = number("kd", w.kd);
    if (w.mu1 < 0 || w.mu2 < 0) throw RobotModelError(lw + ": mu1/mu2 must be >= 0");
  }
  return w;
}

// The drive's wheels, torque limits and checks that left is left.
void ReadDrive(const std::vector<const tinyxml2::XMLElement*>& plugins, const urdf::Model& urdf,
               const RobotModelOptions& o,
               const std::map<std::string, const tinyxml2::XMLElement*>& link_tags,
               RobotModel* m) {
  const tinyxml2::XMLElement* drive = nullptr;
  for (const auto* p : plugins) {
    if (!kDrivePlugins.count(Attribute(p, "filename"))) continue;
    if (drive) {
      throw RobotModelError("robot_description has two drive plugins, " + PluginWhere(drive) +
                            " and " + PluginWhere(p) + "; the simulator drives a robot with one");
    }
    drive = p;
  }
  if (!drive) {
    throw RobotModelError(
        "robot_description has no drive plugin: the simulator needs one <gazebo><plugin> of "
        "libgazebo_ros_skid_steer_drive.so, libgazebo_ros_diff_drive.so, "
        "libgazebo_ros_planar_move.so or libgazebo_ros_control.so (with a "
        "diff_drive_controller) to know how the robot moves");
  }
  DrivePluginSpec& d = m->drive;
  d.plugin_name = Attribute(drive, "name");
  d.filename = Attribute(drive, "filename");
  const std::string where = PluginWhere(drive);
  const auto tags = PluginTags(drive);
  std::set<std::string> given;
  auto& warnings = m->warnings;
  auto wheel = [&](const std::string& joint, const std::string& tag, double radius) {
    return MakeWheel(urdf, WheelJoint(urdf, joint, where, tag), radius, *m, link_tags, &warnings,
                     where);
  };
  if (d.filename == "libgazebo_ros_skid_steer_drive.so") {
    d.kind = DriveKind::kSkidSteer;
    SkidSteerDriveOptions& s = d.skid_steer;
    ReadTags(SkidSteerDriveTable(), tags, where, &s, &warnings, &given);
    d.robot_namespace = Namespace(s.robot_namespace, given.count("robotNamespace"), o);
    if (!(s.update_rate >= 0)) throw RobotModelError(where + ": <updateRate> must be >= 0");
    if (!(s.wheel_separation > 0)) throw RobotModelError(where + ": <wheelSeparation> must be > 0");
    if (!(s.wheel_diameter > 0)) throw RobotModelError(where + ": <wheelDiameter> must be > 0");
    if (!(s.torque > 0)) throw RobotModelError(where + ": <torque> must be > 0");
    const std::pair<std::string, std::string> joints[4] = {
        {s.left_front_joint, "leftFrontJoint"}, {s.right_front_joint, "rightFrontJoint"},
        {s.left_rear_joint, "leftRearJoint"}, {s.right_rear_joint, "rightRearJoint"}};
    for (const auto& j : joints) m->wheels.push_back(wheel(j.first, j.second, s.wheel_diameter / 2));
    for (auto& w : m->wheels) w.torque = s.torque;
    if (m->wheels[0].position.y() < m->wheels[1].position.y()) {
      throw RobotModelError(where + ": leftFrontJoint '" + m->wheels[0].joint +
                            "' is right of rightFrontJoint: the drive plugin's joints are swapped");
    }
    const double track = std::abs(m->wheels[0].position.y() - m->wheels[1].position.y());
    if (std::abs(track - s.wheel_separation) > 1e-3) {
      warnings.push_back(where + ": wheelSeparation " + std::to_string(s.wheel_separation) +
                         " differs from the URDF's wheel track " + std::to_string(track));
    }
    if (!urdf.getLink(s.robot_base_frame)) {
      throw RobotModelError(where + ": <robotBaseFrame> '" + s.robot_base_frame +
                            "' is not a link of the URDF");
    }
  } else if (d.filename == "libgazebo_ros_diff_drive.so") {
    d.kind = DriveKind::kDiffDrive;
    DiffDriveOptions& s = d.diff_drive;
    ReadTags(DiffDriveTable(), tags, where, &s, &warnings, &given);
    d.robot_namespace = Namespace(s.robot_namespace, given.count("robotNamespace"), o);
    if (!(s.update_rate >= 0)) throw RobotModelError(where + ": <updateRate> must be >= 0");
    if (!(s.wheel_separation > 0)) throw RobotModelError(where + ": <wheelSeparation> must be > 0");
    if (!(s.wheel_diameter > 0)) throw RobotModelError(where + ": <wheelDiameter> must be > 0");
    if (!(s.wheel_torque > 0)) throw RobotModelError(where + ": <wheelTorque> must be > 0");
    if (!(s.wheel_acceleration >= 0)) {
      throw RobotModelError(where + ": <wheelAcceleration> must be >= 0");
    }
    if (s.odometry_source != "world" && s.odometry_source != "encoder") {
      throw RobotModelError(where + ": <odometrySource> must be world or encoder, got '" +
                            s.odometry_source + "'");
    }
    if (s.legacy_mode) {
      warnings.push_back(where + ": <legacyMode> true is ignored, as by ROS Noetic's plugin; if "
                         "the robot turns the wrong way, swap leftJoint and rightJoint");
    }
    m->wheels.push_back(wheel(s.left_joint, "leftJoint", s.wheel_diameter / 2));
    m->wheels.push_back(wheel(s.right_joint, "rightJoint", s.wheel_diameter / 2));
    for (auto& w : m->wheels) w.torque = s.wheel_torque;
    if (m->wheels[0].position.y() < m->wheels[1].position.y()) {
      throw RobotModelError(where + ": leftJoint '" + m->wheels[0].joint +
                            "' is right of rightJoint: the drive plugin's joints are swapped");
    }
    if (!urdf.getLink(s.robot_base_frame)) {
      throw RobotModelError(where + ": <robotBaseFrame> '" + s.robot_base_frame +
                            "' is not a link of the URDF");
    }
  } else if (d.filename == "libgazebo_ros_planar_move.so") {
    d.kind = DriveKind::kPlanarMove;
    PlanarMoveOptions& s = d.planar_move;
    ReadTags(PlanarMoveTable(), tags, where, &s, &warnings, &given);
    d.robot_namespace = Namespace(s.robot_namespace, given.count("robotNamespace"), o);
    if (!urdf.getLink(s.robot_base_frame)) {
      throw RobotModelError(where + ": <robotBaseFrame> '" + s.robot_base_frame +
                            "' is not a link of the URDF");
    }
  } else {  // libgazebo_ros_control.so
    d.kind = DriveKind::kDiffDriveController;
    RosControlOptions& s = d.ros_control;
    ReadTags(RosControlTable(), tags, where, &s, &warnings, &given);
    d.robot_namespace = Namespace(s.robot_namespace, given.count("robotNamespace"), o);
    if (s.robot_sim_type != "gazebo_ros_control/DefaultRobotHWSim") {
      throw RobotModelError(where + ": <robotSimType> '" + s.robot_sim_type +
                            "' is not simulated (only gazebo_ros_control/DefaultRobotHWSim)");
    }
    if (!(s.control_period >= 0)) throw RobotModelError(where + ": <controlPeriod> must be >= 0");
    // The controllers configured on the parameter server.
    std::string drive_name;
    for (const auto& c : o.controllers) {
      auto t = c.second.find("type");
      const std::string type = t == c.second.end() ? "" : t->second;
      const std::string cw = "controller '" + c.first + "' (type " + type + ")";
      std::vector<std::pair<std::string, std::string>> keys(c.second.begin(), c.second.end());
      if (type == "diff_drive_controller/DiffDriveController") {
        if (!drive_name.empty()) {
          throw RobotModelError("two diff_drive_controllers, '" + drive_name + "' and '" + c.first +
                                "'; the simulator drives a robot with one");
        }
        drive_name = c.first;
        std::set<std::string> controller_keys;
        ReadTags(DiffDriveControllerTable(), keys, cw, &d.controller, &warnings, &controller_keys);
        if (controller_keys.count("wheel_radius_multiplier")) {
          // diff_drive_controller: a common multiplier overrides both sides'.
          d.controller.left_wheel_radius_multiplier = d.controller.wheel_radius_multiplier;
          d.controller.right_wheel_radius_multiplier = d.controller.wheel_radius_multiplier;
        }
        d.controller.wheel_radius_multiplier = 1.0;
      } else if (type == "joint_state_controller/JointStateController") {
        d.joint_state_controller_name = c.first;
        ReadTags(JointStateControllerTable(), keys, cw, &d.joint_state_controller, &warnings);
        if (!c.second.count("publish_rate")) {
          throw RobotModelError(cw + ": parameter 'publish_rate' is not set (required)");
        }
      } else if (!type.empty()) {
        warnings.push_back(cw + " is not simulated; ignored");
      }
    }
    if (drive_name.empty()) {
      throw RobotModelError(where + ": no diff_drive_controller/DiffDriveController is configured "
                            "under the robot's namespace '" + d.robot_namespace +
                            "' (load the controller YAML before the simulator starts)");
    }
    d.controller_name = drive_name;
    DiffDriveControllerOptions& c = d.controller;
    const std::string cw = "controller '" + drive_name + "'";
    if (c.left_wheel.empty() || c.right_wheel.empty()) {
      throw RobotModelError(cw + ": 'left_wheel' and 'right_wheel' must each name at least one "
                            "wheel joint");
    }
    if (c.left_wheel.size() != c.right_wheel.size()) {
      throw RobotModelError(cw + ": 'left_wheel' has " + std::to_string(c.left_wheel.size()) +
                            " joints and 'right_wheel' " + std::to_string(c.right_wheel.size()) +
                            "; they must have as many");
    }
    for (const char* key : {"pose_covariance_diagonal", "twist_covariance_diagonal"}) {
      const auto& v = std::string(key) == "pose_covariance_diagonal" ? c.pose_covariance_diagonal
                                                                      : c.twist_covariance_diagonal;
      if (v.size() != 6) {
        throw RobotModelError(cw + ": '" + key + "' must be a list of 6 numbers (it has " +
                              std::to_string(v.size()) + ")");
      }
      for (const auto& x : v) Numbers(x, 1, cw + ": '" + std::string(key) + "'");
    }
    if (!(c.publish_rate > 0)) throw RobotModelError(cw + ": 'publish_rate' must be > 0");
    if (!(c.cmd_vel_timeout > 0)) throw RobotModelError(cw + ": 'cmd_vel_timeout' must be > 0");
    if (c.velocity_rolling_window_size < 1) {
      throw RobotModelError(cw + ": 'velocity_rolling_window_size' must be >= 1");
    }
    auto lj = WheelJoint(urdf, c.left_wheel[0], cw, "left_wheel");
    auto rj = WheelJoint(urdf, c.right_wheel[0], cw, "right_wheel");
    if (!(c.wheel_separation > 0)) {
      // diff_drive_controller: the distance between the first left and right wheel joints'
      // origins, each relative to its parent link.
      const auto& a = lj->parent_to_joint_origin_transform.position;
      const auto& b = rj->parent_to_joint_origin_transform.position;
      c.wheel_separation = std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) +
                                     (a.z - b.z) * (a.z - b.z));
      if (!(c.wheel_separation > 0)) {
        throw RobotModelError(cw + ": 'wheel_separation' is not set and the URDF's wheel joints "
                              "give none");
      }
    }
    if (!(c.wheel_radius > 0)) {
      auto link = urdf.getLink(lj->child_link_name);
      auto cyl = link->collision ? std::dynamic_pointer_cast<const urdf::Cylinder>(link->collision->geometry) : nullptr;
      auto sph = link->collision ? std::dynamic_pointer_cast<const urdf::Sphere>(link->collision->geometry) : nullptr;
      if (cyl) c.wheel_radius = cyl->radius;
      else if (sph) c.wheel_radius = sph->radius;
      else {
        throw RobotModelError(cw + ": 'wheel_radius' is not set and wheel link '" +
                              link->name + "' has no cylinder or sphere collision to take it from");
      }
    }
    for (const auto& j : c.left_wheel) m->wheels.push_back(wheel(j, "left_wheel", c.wheel_radius));
    for (const auto& j : c.right_wheel) m->wheels.push_back(wheel(j, "right_wheel", c.wheel_radius));
    const size_t n = c.left_wheel.size();
    for (size_t i = 0; i < m->wheels.size(); ++i) {
      WheelSpec& w = m->wheels[i];
      // DefaultRobotHWSim drives a velocity joint with the URDF's effort limit as its torque.
      w.torque = w.effort_limit > 0 ? w.effort_limit : 1e6;
      const bool on_left_list = i < n;
      if (w.left != on_left_list) {
        throw RobotModelError(cw + ": wheel joint '" + w.joint + "' is listed in " +
                              (on_left_list ? "left_wheel" : "right_wheel") + " but is on the " +
                              (w.left ? "left" : "right") + " of the robot");
      }
    }
    if (!urdf.getLink(c.base_frame_id)) {
      throw RobotModelError(cw + ": 'base_frame_id' '" + c.base_frame_id +
                            "' is not a link of the URDF");
    }
  }
}

LaserSpec ReadLaser(const tinyxml2::XMLElement* sensor, const std::string& link,
                    const RobotModel& m, const RobotModelOptions& o,
                    std::vector<std::string>* warnings, bool* published) {
  const std::string where = "<sensor type=\"" + Attribute(sensor, "type") + "\" name=\"" +
                            Attribute(sensor, "name") + "\"> on link '" + link + "'";
  RaySensorOptions r;
  std::vector<std::pair<std::string, std::string>> tags;
  Flatten(sensor, "", {"plugin"}, &tags);
  ReadTags(RaySensorTable(), tags, where, &r, warnings);
  LaserSpec l;
  l.sensor_name = Attribute(sensor, "name");
  l.link = link;
  l.link_in_root = m.link_poses.at(link);
  l.pose_in_root = l.link_in_root * ParseSdfPose(r.pose, where);
  if (r.samples < 1 || r.samples > 100000) {
    throw RobotModelError(where + ": <samples> must be a whole number in 1..100000");
  }
  if (r.resolution != 1.0) {
    throw RobotModelError(where + ": <horizontal><resolution> " + options::Num(r.resolution) +
                          " is not simulated (only 1: one range per beam)");
  }
  if (r.vertical_samples != 1) {
    throw RobotModelError(where + ": <vertical><samples> " + std::to_string(r.vertical_samples) +
                          " is not simulated (planar lasers only)");
  }
  l.samples = r.samples;
  l.min_angle = r.min_angle;
  l.max_angle = r.max_angle;
  if (l.samples > 1 && !(l.max_angle > l.min_angle)) {
    throw RobotModelError(where + ": <max_angle> must be greater than <min_angle>");
  }
  l.min_range = r.range_min;
  l.max_range = r.range_max;
  l.resolution = r.range_resolution;
  if (!(l.min_range >= 0 && l.max_range > l.min_range)) {
    throw RobotModelError(where + ": need 0 <= <min> < <max> in <range>");
  }
  if (l.resolution < 0) throw RobotModelError(where + ": <resolution> must be >= 0");
  if (!r.noise_type.empty() && r.noise_type != "gaussian") {
    throw RobotModelError(where + ": <noise><type> '" + r.noise_type +
                          "' is not supported (gaussian)");
  }
  l.noise_mean = r.noise_mean;
  l.noise_stddev = r.noise_stddev;
  if (l.noise_stddev < 0) throw RobotModelError(where + ": <noise><stddev> must be >= 0");
  l.update_rate = r.update_rate;  // 0: every physics step, as Gazebo
  if (!(l.update_rate >= 0)) throw RobotModelError(where + ": <update_rate> must be >= 0");
  *published = false;
  for (auto* p = sensor->FirstChildElement("plugin"); p; p = p->NextSiblingElement("plugin")) {
    const std::string file = Attribute(p, "filename");
    if (file == "libgazebo_ros_laser.so" || file == "libgazebo_ros_gpu_laser.so") {
      LaserPluginOptions lo;
      std::set<std::string> given;
      ReadTags(LaserPluginTable(), PluginTags(p), where + " " + PluginWhere(p), &lo, warnings,
               &given);
      *published = true;
      l.topic = lo.topic_name;
      l.frame_id = lo.frame_name;
      if (!given.count("topicName") || !given.count("frameName")) {
        warnings->push_back(where + ": " + PluginWhere(p) + " sets no <topicName> or <frameName>; "
                            "Gazebo's defaults /world are used");
      }
      l.robot_namespace = Namespace(lo.robot_namespace, given.count("robotNamespace"), o);
    } else {
      warnings->push_back(where + ": plugin '" + file + "' is not simulated; ignored");
    }
  }
  // tf names have no leading slash.
  if (!l.frame_id.empty() && l.frame_id[0] == '/') l.frame_id.erase(0, 1);
  if (m.HasLink(l.frame_id)) {
    l.link_in_root = m.link_poses.at(l.frame_id);
  } else if (*published) {
    warnings->push_back(where + ": <frameName> '" + l.frame_id +
                        "' is not a URDF link; scans are published in it anyway");
  }
  return l;
}

Eigen::Quaterniond RpyOffset(const std::string& text, const std::string& where) {
  const std::vector<double> v = Numbers(text, 3, where);
  return Eigen::Quaterniond(Rpy(v[0], v[1], v[2]));
}

void ReadSensors(const GazeboBlocks& blocks, const RobotModelOptions& o, RobotModel* m) {
  for (const auto& [link, block] : blocks.link_blocks) {
    for (auto* s = block->FirstChildElement("sensor"); s; s = s->NextSiblingElement("sensor")) {
      const std::string type = Attribute(s, "type");
      const std::string where =
          "<sensor type=\"" + type + "\" name=\"" + Attribute(s, "name") + "\"> on link '" + link + "'";
      if (type == "ray" || type == "gpu_ray") {
        bool published = false;
        LaserSpec l = ReadLaser(s, link, *m, o, &m->warnings, &published);
        if (published) {
          m->lasers.push_back(l);
        } else {
          m->warnings.push_back(where + " has no libgazebo_ros_laser.so plugin; not published");
        }
      } else if (type == "imu") {
        ImuSensorOptions so;
        std::vector<std::pair<std::string, std::string>> tags;
        Flatten(s, "", {"plugin"}, &tags);
        ReadTags(ImuSensorTable(), tags, where, &so, &m->warnings);
        for (const std::string* type : {&so.av_x_type, &so.av_y_type, &so.av_z_type, &so.la_x_type,
                                        &so.la_y_type, &so.la_z_type}) {
          if (!type->empty() && *type != "gaussian") {
            throw RobotModelError(where + ": noise type '" + *type + "' is not supported (gaussian)");
          }
        }
        bool published = false;
        for (auto* p = s->FirstChildElement("plugin"); p; p = p->NextSiblingElement("plugin")) {
          const std::string file = Attribute(p, "filename");
          if (file != "libgazebo_ros_imu_sensor.so") {
            m->warnings.push_back(where + ": plugin '" + file + "' is not simulated; ignored");
            continue;
          }
          ImuPluginOptions po;
          std::set<std::string> given;
          const std::string pw = where + " " + PluginWhere(p);
          ReadTags(ImuSensorPluginTable(), PluginTags(p), pw, &po, &m->warnings, &given);
          if (po.frame_name.empty()) throw RobotModelError(pw + ": missing <frameName> (required)");
          ImuSpec imu;
          imu.name = Attribute(s, "name");
          imu.link = link;
          imu.frame_id = po.frame_name;
          imu.topic = po.topic_name.empty() ? "imu_data" : po.topic_name;
          imu.robot_namespace = Namespace(po.robot_namespace, given.count("robotNamespace"), o);
          imu.pose_in_root = m->link_poses.at(link) * ParseSdfPose(so.pose, where);
          if (!(po.update_rate_hz > 0)) throw RobotModelError(pw + ": <updateRateHZ> must be > 0");
          imu.update_rate = so.update_rate > 0 ? std::min(so.update_rate, po.update_rate_hz)
                                               : po.update_rate_hz;
          imu.gravity = true;
          imu.gaussian_noise = po.gaussian_noise;
          imu.noise = so;
          imu.orientation_offset = RpyOffset(po.rpy_offset, pw + ": <rpyOffset>");
          imu.initial_orientation_as_reference = po.initial_orientation_as_reference;
          m->imus.push_back(imu);
          published = true;
        }
        if (!published) m->warnings.push_back(where + " has no libgazebo_ros_imu_sensor.so plugin; not published");
      } else if (type == "depth" || type == "camera") {
        CameraSensorOptions co;
        std::vector<std::pair<std::string, std::string>> tags;
        Flatten(s, "", {"plugin"}, &tags);
        // <depth_camera> (an empty marker or its <output>) says what Gazebo renders.
        tags.erase(std::remove_if(tags.begin(), tags.end(),
                                  [](const std::pair<std::string, std::string>& t) {
                                    return t.first.rfind("camera/depth_camera", 0) == 0 ||
                                           t.first.rfind("camera/distortion", 0) == 0;
                                  }),
                   tags.end());
        ReadTags(CameraSensorTable(), tags, where, &co, &m->warnings);
        if (co.width < 1 || co.width > kMaxImageSide || co.height < 1 || co.height > kMaxImageSide) {
          throw RobotModelError(where + ": image " + std::to_string(co.width) + " x " +
                                std::to_string(co.height) + " pixels: <width> and <height> must "
                                "be in 1.." + std::to_string(kMaxImageSide));
        }
        if (!(co.horizontal_fov > 0 && co.horizontal_fov < M_PI)) {
          throw RobotModelError(where + ": <horizontal_fov> must be in (0, pi) rad");
        }
        if (!(co.clip_near > 0 && co.clip_far > co.clip_near)) {
          throw RobotModelError(where + ": need 0 < <clip><near> < <clip><far>");
        }
        if (co.format != "R8G8B8" && co.format != "B8G8R8" && co.format != "L8") {
          throw RobotModelError(where + ": <format> '" + co.format +
                                "' is not simulated (R8G8B8, B8G8R8 or L8)");
        }
        bool published = false;
        for (auto* p = s->FirstChildElement("plugin"); p; p = p->NextSiblingElement("plugin")) {
          const std::string file = Attribute(p, "filename");
          const bool depth_plugin = file == "libgazebo_ros_depth_camera.so" ||
                                    file == "libgazebo_ros_openni_kinect.so";
          if (!(depth_plugin || file == "libgazebo_ros_camera.so")) {
            m->warnings.push_back(where + ": plugin '" + file + "' is not simulated; ignored");
            continue;
          }
          if (depth_plugin && type != "depth") {
            throw RobotModelError(where + ": " + PluginWhere(p) + " needs a <sensor type=\"depth\">");
          }
          CameraSpec c;
          c.name = Attribute(s, "name");
          c.plugin = file;
          c.depth = depth_plugin;
          c.link = link;
          c.sensor = co;
          if (file == "libgazebo_ros_openni_kinect.so") c.ros.point_cloud_cutoff_max = 5.0;
          std::set<std::string> given;
          const std::string pw = where + " " + PluginWhere(p);
          ReadTags(CameraPluginTable(), PluginTags(p), pw, &c.ros, &m->warnings, &given);
          c.robot_namespace = Namespace(c.ros.robot_namespace, given.count("robotNamespace"), o);
          c.pose_in_root = m->link_poses.at(link) * ParseSdfPose(co.pose, where);
          if (c.ros.update_rate < 0) throw RobotModelError(pw + ": <updateRate> must be >= 0");
          const double sensor_rate = co.update_rate;
          c.update_rate = c.ros.update_rate > 0 && (sensor_rate <= 0 || c.ros.update_rate < sensor_rate)
                              ? c.ros.update_rate
                              : sensor_rate;
          if (!(c.update_rate > 0)) {
            throw RobotModelError(where + ": set <update_rate> > 0 (a camera rendering every "
                                  "physics step is not simulated)");
          }
          if (c.ros.frame_name.empty()) {
            m->warnings.push_back(pw + " sets no <frameName>; images are published with an empty "
                                  "frame_id, as by Gazebo");
          } else if (c.ros.frame_name[0] == '/') {
            c.ros.frame_name.erase(0, 1);
          }
          if (!c.ros.frame_name.empty() && !m->HasLink(c.ros.frame_name)) {
            m->warnings.push_back(pw + ": <frameName> '" + c.ros.frame_name +
                                  "' is not a URDF link");
          }
          m->cameras.push_back(c);
          published = true;
        }
        if (!published) m->warnings.push_back(where + " has no ROS camera plugin; not published");
      } else {
        m->warnings.push_back(where + " is not simulated; ignored");
      }
    }
  }
}

// Model plugins other than the drive: IMU, ground truth, joint states.
void ReadModelPlugins(const GazeboBlocks& blocks, const urdf::Model& urdf,
                      const RobotModelOptions& o, RobotModel* m) {
  for (const auto* p : blocks.model_plugins) {
    const std::string file = Attribute(p, "filename");
    if (kDrivePlugins.count(file)) continue;
    const std::string where = PluginWhere(p);
    std::set<std::string> given;
    if (file == "libgazebo_ros_imu.so") {
      ImuPluginOptions po;
      ReadTags(ImuModelPluginTable(), PluginTags(p), where, &po, &m->warnings, &given);
      if (po.body_name.empty()) throw RobotModelError(where + ": missing <bodyName> (required)");
      if (!urdf.getLink(po.body_name)) {
        throw RobotModelError(where + ": <bodyName> '" + po.body_name +
                              "' is not a link of the URDF");
      }
      if (!(po.update_rate >= 0)) throw RobotModelError(where + ": <updateRate> must be >= 0");
      ImuSpec imu;
      imu.name = Attribute(p, "name");
      imu.link = po.body_name;
      imu.frame_id = po.frame_name.empty() ? po.body_name : po.frame_name;
      imu.topic = po.topic_name.empty() ? "/default_imu" : po.topic_name;
      imu.robot_namespace = Namespace(po.robot_namespace, given.count("robotNamespace"), o);
      imu.pose_in_root = m->link_poses.at(po.body_name);
      imu.update_rate = po.update_rate;
      imu.gravity = false;  // libgazebo_ros_imu.so reports the acceleration without gravity
      imu.gaussian_noise = po.gaussian_noise;
      imu.orientation_offset = RpyOffset(po.rpy_offset, where + ": <rpyOffset>");
      m->imus.push_back(imu);
    } else if (file == "libgazebo_ros_p3d.so") {
      GroundTruthSpec g;
      ReadTags(GroundTruthTable(), PluginTags(p), where, &g.options, &m->warnings, &given);
      if (g.options.body_name.empty()) throw RobotModelError(where + ": missing <bodyName> (required)");
      if (g.options.topic_name.empty()) throw RobotModelError(where + ": missing <topicName> (required)");
      if (!urdf.getLink(g.options.body_name)) {
        throw RobotModelError(where + ": <bodyName> '" + g.options.body_name +
                              "' is not a link of the URDF");
      }
      if (!(g.options.update_rate >= 0)) throw RobotModelError(where + ": <updateRate> must be >= 0");
      g.robot_namespace = Namespace(g.options.robot_namespace, given.count("robotNamespace"), o);
      g.link_in_root = m->link_poses.at(g.options.body_name);
      const std::vector<double> xyz = Numbers(g.options.xyz_offset, 3, where + ": <xyzOffset>");
      g.offset.translation() = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
      g.offset.linear() = RpyOffset(g.options.rpy_offset, where + ": <rpyOffset>").toRotationMatrix();
      std::string frame = g.options.frame_name;
      if (!frame.empty() && frame[0] == '/') frame.erase(0, 1);
      if (frame != "world" && frame != "map") {
        if (!urdf.getLink(frame)) {
          throw RobotModelError(where + ": <frameName> '" + g.options.frame_name +
                                "' is neither world, map nor a link of the URDF");
        }
        g.reference_link = frame;
        g.reference_in_root = m->link_poses.at(frame);
      }
      m->ground_truths.push_back(g);
    } else if (file == "libgazebo_ros_joint_state_publisher.so") {
      JointStatePublisherOptions jo;
      ReadTags(JointStatePublisherTable(), PluginTags(p), where, &jo, &m->warnings, &given);
      JointStatePublisherSpec j;
      j.robot_namespace = Namespace(jo.robot_namespace, given.count("robotNamespace"), o);
      j.update_rate = jo.update_rate;
      std::istringstream names(jo.joint_name);
      for (std::string n; std::getline(names, n, ',');) {
        n.erase(std::remove_if(n.begin(), n.end(), ::isspace), n.end());
        if (n.empty()) continue;
        if (!urdf.getJoint(n)) {
          throw RobotModelError(where + ": <jointName> names joint '" + n +
                                "', which is not in the URDF");
        }
        j.joints.push_back(n);
      }
      m->joint_state_publishers.push_back(j);
    } else {
      m->warnings.push_back("<gazebo> plugin '" + file + "' is not simulated; ignored");
    }
  }
}

}  // namespace

ControllerParams LoadControllerParams(const std::string& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    throw RobotModelError(yaml_path + ": " + e.what());
  }
  ControllerParams out;
  std::function<void(const YAML::Node&, const std::string&, std::map<std::string, std::string>*)>
      flatten = [&](const YAML::Node& n, const std::string& prefix,
                    std::map<std::string, std::string>* keys) {
        for (const auto& kv : n) {
          const std::string key =
              prefix.empty() ? kv.first.as<std::string>() : prefix + "/" + kv.first.as<std::string>();
          if (kv.second.IsMap()) {
            flatten(kv.second, key, keys);
          } else if (kv.second.IsSequence()) {
            std::string text;
            for (const auto& item : kv.second) text += (text.empty() ? "" : ", ") + item.as<std::string>();
            (*keys)[key] = "[" + text + "]";
          } else {
            (*keys)[key] = kv.second.as<std::string>();
          }
        }
      };
  if (!root.IsMap()) throw RobotModelError(yaml_path + ": not a YAML map of controllers");
  for (const auto& kv : root) {
    if (!kv.second.IsMap() || !kv.second["type"]) continue;
    flatten(kv.second, "", &out[kv.first.as<std::string>()]);
  }
  return out;
}

const Eigen::Isometry3d& RobotModel::LinkPose(const std::string& link) const {
  auto it = link_poses.find(link);
  if (it == link_poses.end()) throw RobotModelError("'" + link + "' is not a link of the URDF");
  return it->second;
}

RobotModel ParseRobotModel(const std::string& urdf_xml, const RobotModelOptions& options) {
  if (urdf_xml.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw RobotModelError("robot_description is empty");
  }
  tinyxml2::XMLDocument doc;
  if (doc.Parse(urdf_xml.c_str()) != tinyxml2::XML_SUCCESS) {
    throw RobotModelError(std::string("robot_description is not valid XML: ") + doc.ErrorStr());
  }
  const tinyxml2::XMLElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Name()) != "robot") {
    throw RobotModelError("robot_description has no <robot> root element");
  }
  urdf::Model urdf;
  if (!urdf.initString(urdf_xml)) {
    throw RobotModelError("robot_description: urdfdom cannot parse the URDF (see its messages above)");
  }
  RobotModel m;
  m.name = urdf.getName();
  m.root_link = urdf.getRoot()->name;
  LinkPoses(urdf.getRoot(), Eigen::Isometry3d::Identity(), &m.link_poses);
  std::vector<std::pair<std::string, urdf::JointSharedPtr>> joints(urdf.joints_.begin(),
                                                                     urdf.joints_.end());
  for (const auto& j : joints) {
    const int t = j.second->type;
    if (t == urdf::Joint::REVOLUTE || t == urdf::Joint::CONTINUOUS || t == urdf::Joint::PRISMATIC) {
      m.joints.push_back({j.first, t == urdf::Joint::PRISMATIC ? "prismatic"
                                   : t == urdf::Joint::REVOLUTE ? "revolute" : "continuous"});
    }
  }

  const GazeboBlocks blocks = ReadGazeboBlocks(robot, urdf, &m);
  std::map<std::string, const tinyxml2::XMLElement*> link_tags;
  for (const auto& [link, block] : blocks.link_blocks) link_tags.emplace(link, block);
  ReadCollisions(urdf, options, &m);
  ReadDrive(blocks.model_plugins, urdf, options, link_tags, &m);
  ReadSensors(blocks, options, &m);
  ReadModelPlugins(blocks, urdf, options, &m);

  // Mass, yaw inertia, the body box (everything rigidly attached, wheels aside) and supports.
  std::set<std::string> wheel_links;
  for (const auto& w : m.wheels) wheel_links.insert(w.link);
  std::vector<urdf::LinkSharedPtr> links;
  urdf.getLinks(links);
  std::sort(links.begin(), links.end(),
            [](const urdf::LinkSharedPtr& a, const urdf::LinkSharedPtr& b) { return a->name < b->name; });
  std::vector<Eigen::Vector3d> corners;
  std::vector<Eigen::Vector2d> outline;
  for (const auto& link : links) {
    const Eigen::Isometry3d& pose = m.link_poses.at(link->name);
    if (link->inertial) {
      const auto& in = *link->inertial;
      Eigen::Matrix3d i;
      i << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      const Eigen::Isometry3d com = pose * ToEigen(in.origin);
      const Eigen::Matrix3d r = com.linear();
      const Eigen::Vector3d c = com.translation();
      m.total_mass += in.mass;
      m.body_inertia_z += (r * i * r.transpose())(2, 2) + in.mass * (c.x() * c.x() + c.y() * c.y());
      if (!wheel_links.count(link->name)) m.body_mass += in.mass;
    }
    const bool movable = link->parent_joint && link->parent_joint->type != urdf::Joint::FIXED;
    double lowest = std::numeric_limits<double>::infinity();
    for (const auto& c : m.collisions) {
      if (c.link != link->name) continue;
      const auto link_corners = ShapeCorners(c.shape);
      outline.insert(outline.end(), c.outline.begin(), c.outline.end());
      if (!wheel_links.count(link->name) && !movable && c.shape.type != ShapeType::kMesh) {
        corners.insert(corners.end(), link_corners.begin(), link_corners.end());
      }
      lowest = std::min(lowest, c.z_min);
    }
    if (!wheel_links.count(link->name) && lowest <= kSupportClearance) {
      m.supports.push_back({link->name, pose.translation().head<2>()});
    }
  }
  if (m.total_mass <= 0) throw RobotModelError("the URDF has no link with an <inertial> mass");
  if (corners.empty()) {
    throw RobotModelError("the URDF has no box/cylinder/sphere <collision> outside the wheels: "
                          "the simulator needs the body's shape");
  }
  Eigen::Vector3d lo = corners[0], hi = corners[0];
  for (const auto& c : corners) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  m.body_size = hi - lo;
  m.body_pose = Eigen::Isometry3d::Identity();
  m.body_pose.translation() = 0.5 * (lo + hi);
  m.footprint = ConvexHull(outline);
  return m;
}

double FloorClearance(const RobotModel& robot) {
  double min_radius = std::numeric_limits<double>::infinity();
  for (const WheelSpec& w : robot.wheels) min_radius = std::min(min_radius, w.radius);
  return std::isfinite(min_radius) ? std::max(0.005, 0.25 * min_radius) : 0.005;
}

std::vector<BodyPart> BodyParts(const RobotModel& robot) {
  const double floor = FloorClearance(robot);
  std::vector<BodyPart> parts;
  for (const CollisionShape& c : robot.collisions) {
    if (c.outline.size() < 3 || c.z_max <= floor) continue;
    parts.push_back(BodyPart{c.link, c.outline, std::max(c.z_min, floor), c.z_max});
  }
  if (!robot.collisions.empty()) return parts;
  const Eigen::Vector3d centre = robot.body_pose.translation();
  const Eigen::Vector3d h = robot.body_size / 2.0;
  BodyPart part;
  part.link = robot.root_link;
  part.outline = robot.footprint;
  if (part.outline.size() < 3) {
    part.outline = {centre.head<2>() + Eigen::Vector2d(-h.x(), -h.y()),
                    centre.head<2>() + Eigen::Vector2d(h.x(), -h.y()),
                    centre.head<2>() + Eigen::Vector2d(h.x(), h.y()),
                    centre.head<2>() + Eigen::Vector2d(-h.x(), h.y())};
  }
  part.z_min = std::max(floor, centre.z() - h.z());
  part.z_max = centre.z() + h.z();
  for (const WheelSpec& w : robot.wheels) part.z_max = std::max(part.z_max, w.position.z() + w.radius);
  if (part.z_max <= part.z_min) part.z_max = part.z_min + 0.01;
  parts.push_back(std::move(part));
  return parts;
}

}  // namespace minibot3d_sim
