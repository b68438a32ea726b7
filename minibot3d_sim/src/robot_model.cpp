#include "minibot3d_sim/robot_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include <tinyxml2.h>
#include <urdf/model.h>

namespace minibot3d_sim {
namespace {

Eigen::Isometry3d ToEigen(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return t;
}

// SDF pose text "x y z roll pitch yaw" → transform (R = Rz(yaw) Ry(pitch) Rx(roll)).
Eigen::Isometry3d ParseSdfPose(const std::string& text, const std::string& where) {
  std::istringstream in(text);
  double v[6];
  for (double& x : v) {
    if (!(in >> x)) throw RobotModelError(where + ": <pose> needs 6 numbers, got '" + text + "'");
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  t.linear() = (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return t;
}

const char* Text(const tinyxml2::XMLElement* parent, const char* tag) {
  const tinyxml2::XMLElement* e = parent ? parent->FirstChildElement(tag) : nullptr;
  return e && e->GetText() ? e->GetText() : nullptr;
}

// A numeric child <tag>; `fallback` when absent; RobotModelError naming `where`/tag when malformed.
double Number(const tinyxml2::XMLElement* parent, const char* tag, double fallback,
              const std::string& where) {
  const char* t = Text(parent, tag);
  if (!t) return fallback;
  char* end = nullptr;
  const double v = std::strtod(t, &end);
  while (end && *end && std::isspace(static_cast<unsigned char>(*end))) ++end;
  if (end == t || (end && *end) || !std::isfinite(v)) {
    throw RobotModelError(where + ": <" + tag + "> is not a number: '" + t + "'");
  }
  return v;
}

double RequiredNumber(const tinyxml2::XMLElement* parent, const char* tag,
                      const std::string& where) {
  if (!Text(parent, tag)) throw RobotModelError(where + ": missing <" + tag + ">");
  return Number(parent, tag, 0.0, where);
}

std::string String(const tinyxml2::XMLElement* parent, const char* tag,
                   const std::string& fallback) {
  const char* t = Text(parent, tag);
  if (!t) return fallback;
  std::string s(t);
  s.erase(0, s.find_first_not_of(" \t\r\n"));
  s.erase(s.find_last_not_of(" \t\r\n") + 1);
  return s;
}

bool Bool(const tinyxml2::XMLElement* parent, const char* tag, bool fallback,
          const std::string& where) {
  const std::string s = String(parent, tag, fallback ? "true" : "false");
  if (s == "true" || s == "1") return true;
  if (s == "false" || s == "0") return false;
  throw RobotModelError(where + ": <" + tag + "> must be true or false, got '" + s + "'");
}

// Root-frame pose of every link at zero joint positions.
void LinkPoses(const urdf::LinkConstSharedPtr& link, const Eigen::Isometry3d& pose,
               std::map<std::string, Eigen::Isometry3d>* out) {
  (*out)[link->name] = pose;
  for (const auto& child : link->child_links) {
    (*out)[child->name] = Eigen::Isometry3d::Identity();
    LinkPoses(child, pose * ToEigen(child->parent_joint->parent_to_joint_origin_transform), out);
  }
}

// Corners of a link's collision geometry approximated by its bounding box, in the root frame.
void AddCollisionCorners(const urdf::Collision& c, const Eigen::Isometry3d& link_pose,
                         std::vector<Eigen::Vector3d>* corners) {
  Eigen::Vector3d half;
  switch (c.geometry->type) {
    case urdf::Geometry::BOX: {
      auto b = std::static_pointer_cast<const urdf::Box>(c.geometry);
      half = 0.5 * Eigen::Vector3d(b->dim.x, b->dim.y, b->dim.z);
      break;
    }
    case urdf::Geometry::CYLINDER: {
      auto cy = std::static_pointer_cast<const urdf::Cylinder>(c.geometry);
      half = Eigen::Vector3d(cy->radius, cy->radius, 0.5 * cy->length);
      break;
    }
    case urdf::Geometry::SPHERE: {
      auto s = std::static_pointer_cast<const urdf::Sphere>(c.geometry);
      half = Eigen::Vector3d::Constant(s->radius);
      break;
    }
    default:
      return;  // meshes: not used for the body's contact box
  }
  const Eigen::Isometry3d t = link_pose * ToEigen(c.origin);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d s((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    corners->push_back(t * s.cwiseProduct(half));
  }
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

const std::set<std::string> kKnownLinkTags = {
    "material", "mu1", "mu2", "kp", "kd", "fdir1", "maxVel", "minDepth", "selfCollide",
    "gravity", "turnGravityOff", "maxContacts", "dampingFactor", "sensor", "visual", "collision"};
const std::set<std::string> kKnownSensorTags = {"pose", "visualize", "update_rate", "ray",
                                                "plugin", "always_on", "topic"};

void ParseDrive(const tinyxml2::XMLElement* p, const urdf::Model& urdf, RobotModel* m) {
  const std::string where = "<plugin filename=\"libgazebo_ros_skid_steer_drive.so\">";
  DriveSpec& d = m->drive;
  d.update_rate = Number(p, "updateRate", d.update_rate, where);
  if (d.update_rate < 0) throw RobotModelError(where + ": <updateRate> must be >= 0");
  d.command_topic = String(p, "topicName", d.command_topic);
  d.odometry_topic = String(p, "odometryTopic", d.odometry_topic);
  d.odometry_frame = String(p, "odometryFrame", d.odometry_frame);
  d.robot_base_frame = String(p, "robotBaseFrame", d.robot_base_frame);
  d.broadcast_tf = Bool(p, "broadcastTF", d.broadcast_tf, where);
  d.wheel_separation = RequiredNumber(p, "wheelSeparation", where);
  d.wheel_diameter = RequiredNumber(p, "wheelDiameter", where);
  d.torque = Number(p, "torque", 20.0, where);  // the plugin's own default
  if (d.wheel_separation <= 0) throw RobotModelError(where + ": <wheelSeparation> must be > 0");
  if (d.wheel_diameter <= 0) throw RobotModelError(where + ": <wheelDiameter> must be > 0");
  if (d.torque <= 0) throw RobotModelError(where + ": <torque> must be > 0");
  d.covariance_x = Number(p, "covariance_x", d.covariance_x, where);
  d.covariance_y = Number(p, "covariance_y", d.covariance_y, where);
  d.covariance_yaw = Number(p, "covariance_yaw", d.covariance_yaw, where);
  const char* tags[4] = {"leftFrontJoint", "rightFrontJoint", "leftRearJoint", "rightRearJoint"};
  for (int i = 0; i < 4; ++i) {
    d.joints[i] = String(p, tags[i], "");
    if (d.joints[i].empty()) throw RobotModelError(where + ": missing <" + tags[i] + ">");
    auto j = urdf.getJoint(d.joints[i]);
    if (!j) {
      throw RobotModelError(where + ": <" + std::string(tags[i]) + "> names joint '" +
                            d.joints[i] + "', which is not in the URDF");
    }
    if (j->type != urdf::Joint::CONTINUOUS && j->type != urdf::Joint::REVOLUTE) {
      throw RobotModelError("joint '" + d.joints[i] + "' (" + tags[i] +
                            ") must be continuous or revolute");
    }
  }
}

void ParseRaySensor(const tinyxml2::XMLElement* s, const std::string& link, RobotModel* m) {
  const std::string where = "<sensor type=\"ray\"> on link '" + link + "'";
  LidarSpec& l = m->lidar;
  l.link = link;
  for (auto* e = s->FirstChildElement(); e; e = e->NextSiblingElement()) {
    if (!kKnownSensorTags.count(e->Name())) {
      m->warnings.push_back(where + ": tag <" + std::string(e->Name()) + "> is not simulated");
    }
  }
  const char* pose = Text(s, "pose");
  const Eigen::Isometry3d sensor_pose =
      pose ? ParseSdfPose(pose, where) : Eigen::Isometry3d::Identity();
  l.update_rate = Number(s, "update_rate", 10.0, where);
  if (l.update_rate <= 0) throw RobotModelError(where + ": <update_rate> must be > 0");
  const tinyxml2::XMLElement* ray = s->FirstChildElement("ray");
  if (!ray) throw RobotModelError(where + ": missing <ray>");
  const tinyxml2::XMLElement* h = ray->FirstChildElement("scan")
                                      ? ray->FirstChildElement("scan")->FirstChildElement("horizontal")
                                      : nullptr;
  if (!h) throw RobotModelError(where + ": missing <ray><scan><horizontal>");
  const double samples = RequiredNumber(h, "samples", where + " <horizontal>");
  if (samples < 1 || samples != std::floor(samples) || samples > 100000) {
    throw RobotModelError(where + ": <samples> must be a whole number in 1..100000");
  }
  l.samples = static_cast<int>(samples);
  l.min_angle = Number(h, "min_angle", 0.0, where);
  l.max_angle = Number(h, "max_angle", 0.0, where);
  if (l.samples > 1 && !(l.max_angle > l.min_angle)) {
    throw RobotModelError(where + ": <max_angle> must be greater than <min_angle>");
  }
  const tinyxml2::XMLElement* range = ray->FirstChildElement("range");
  if (!range) throw RobotModelError(where + ": missing <ray><range>");
  l.min_range = RequiredNumber(range, "min", where + " <range>");
  l.max_range = RequiredNumber(range, "max", where + " <range>");
  l.resolution = Number(range, "resolution", 0.0, where);
  if (!(l.min_range >= 0 && l.max_range > l.min_range)) {
    throw RobotModelError(where + ": need 0 <= <min> < <max> in <range>");
  }
  if (l.resolution < 0) throw RobotModelError(where + ": <resolution> must be >= 0");
  if (const tinyxml2::XMLElement* noise = ray->FirstChildElement("noise")) {
    const std::string type = String(noise, "type", "gaussian");
    if (type != "gaussian") {
      throw RobotModelError(where + ": <noise><type> '" + type + "' is not supported (gaussian)");
    }
    l.noise_mean = Number(noise, "mean", 0.0, where);
    l.noise_stddev = Number(noise, "stddev", 0.0, where);
    if (l.noise_stddev < 0) throw RobotModelError(where + ": <noise><stddev> must be >= 0");
  }
  l.frame_id = link;
  bool ros_plugin = false;
  for (auto* p = s->FirstChildElement("plugin"); p; p = p->NextSiblingElement("plugin")) {
    const std::string file = p->Attribute("filename") ? p->Attribute("filename") : "";
    if (file == "libgazebo_ros_laser.so" || file == "libgazebo_ros_gpu_laser.so") {
      ros_plugin = true;
      l.topic = String(p, "topicName", "scan");
      l.frame_id = String(p, "frameName", link);
    } else {
      m->warnings.push_back(where + ": plugin '" + file + "' is not simulated; ignored");
    }
  }
  if (!ros_plugin) {
    m->warnings.push_back(where + ": no libgazebo_ros_laser.so plugin; publishing on 'scan' in "
                          "frame '" + link + "'");
  }
  l.pose_in_root = sensor_pose;  // completed with the link pose by the caller
}

}  // namespace

RobotModel ParseRobotModel(const std::string& urdf_xml) {
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

  std::map<std::string, Eigen::Isometry3d> poses;
  LinkPoses(urdf.getRoot(), Eigen::Isometry3d::Identity(), &poses);

  // <gazebo> extension blocks.
  const tinyxml2::XMLElement* drive = nullptr;
  const tinyxml2::XMLElement* sensor = nullptr;
  std::string sensor_link;
  std::map<std::string, const tinyxml2::XMLElement*> link_tags;
  for (auto* g = robot->FirstChildElement("gazebo"); g; g = g->NextSiblingElement("gazebo")) {
    const char* ref = g->Attribute("reference");
    if (!ref) {
      for (auto* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
        const std::string tag = e->Name();
        const std::string file = e->Attribute("filename") ? e->Attribute("filename") : "";
        if (tag == "plugin" && file == "libgazebo_ros_skid_steer_drive.so") {
          drive = e;
        } else if (tag == "plugin") {
          m.warnings.push_back("<gazebo> plugin '" + file + "' is not simulated; ignored");
        } else if (tag != "static") {
          m.warnings.push_back("<gazebo> tag <" + tag + "> is not simulated; ignored");
        }
      }
      continue;
    }
    if (!urdf.getLink(ref)) {
      throw RobotModelError(std::string("<gazebo reference=\"") + ref +
                            "\"> names a link that is not in the URDF");
    }
    link_tags[ref] = g;
    for (auto* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (!kKnownLinkTags.count(tag)) {
        m.warnings.push_back(std::string("<gazebo reference=\"") + ref + "\"> tag <" + tag +
                             "> is not simulated; ignored");
      }
      if (tag == "sensor") {
        const std::string type = e->Attribute("type") ? e->Attribute("type") : "";
        if (type == "ray" || type == "gpu_ray") {
          if (sensor) {
            m.warnings.push_back(std::string("a second ray sensor on '") + ref + "' is ignored");
          } else {
            sensor = e;
            sensor_link = ref;
          }
        } else {
          m.warnings.push_back(std::string("<sensor type=\"") + type + "\"> on '" + ref +
                               "' is not simulated; ignored");
        }
      }
    }
  }
  if (!drive) {
    throw RobotModelError("robot_description has no <gazebo><plugin filename="
                          "\"libgazebo_ros_skid_steer_drive.so\">: the simulator needs the "
                          "skid-steer drive plugin to know the wheels");
  }
  if (!sensor) {
    throw RobotModelError("robot_description has no <gazebo reference=\"...\"><sensor "
                          "type=\"ray\">: the simulator needs the lidar");
  }
  ParseDrive(drive, urdf, &m);
  ParseRaySensor(sensor, sensor_link, &m);
  m.lidar.link_in_root = poses.at(sensor_link);
  m.lidar.pose_in_root = m.lidar.link_in_root * m.lidar.pose_in_root;
  if (m.lidar.frame_id != sensor_link && !urdf.getLink(m.lidar.frame_id)) {
    m.warnings.push_back("ray sensor <frameName> '" + m.lidar.frame_id +
                         "' is not a URDF link; scans are published in it anyway");
  } else if (urdf.getLink(m.lidar.frame_id)) {
    m.lidar.link_in_root = poses.at(m.lidar.frame_id);
  }
  if (!urdf.getLink(m.drive.robot_base_frame)) {
    throw RobotModelError("skid-steer plugin <robotBaseFrame> '" + m.drive.robot_base_frame +
                          "' is not a link of the URDF");
  }

  // Wheels.
  std::set<std::string> wheel_links;
  for (int i = 0; i < 4; ++i) {
    auto joint = urdf.getJoint(m.drive.joints[i]);
    WheelSpec& w = m.wheels[i];
    w.joint = joint->name;
    w.link = joint->child_link_name;
    wheel_links.insert(w.link);
    auto link = urdf.getLink(w.link);
    w.position = poses.at(w.link).translation();
    const Eigen::Vector3d axis =
        poses.at(w.link).linear() * Eigen::Vector3d(joint->axis.x, joint->axis.y, joint->axis.z);
    if (std::abs(std::abs(axis.normalized().y()) - 1.0) > 1e-3) {
      throw RobotModelError("wheel joint '" + w.joint +
                            "': its axis must be the robot's y axis (left), e.g. <axis xyz=\"0 1 "
                            "0\"/>");
    }
    auto cyl = link->collision
                   ? std::dynamic_pointer_cast<const urdf::Cylinder>(link->collision->geometry)
                   : nullptr;
    if (cyl) {
      w.radius = cyl->radius;
      w.width = cyl->length;
    } else {
      w.radius = m.drive.wheel_diameter / 2.0;
      w.width = 0.02;
      m.warnings.push_back("wheel link '" + w.link + "' has no cylinder collision; using "
                           "wheelDiameter from the drive plugin");
    }
    if (std::abs(2.0 * w.radius - m.drive.wheel_diameter) > 1e-3) {
      m.warnings.push_back("wheel link '" + w.link + "' radius " + std::to_string(w.radius) +
                           " disagrees with the plugin's wheelDiameter " +
                           std::to_string(m.drive.wheel_diameter) + "; odometry uses the plugin's");
    }
    if (link->inertial) {
      w.mass = link->inertial->mass;
      // Inertia about the axle: the link's inertia tensor rotated into the root frame, yy.
      Eigen::Matrix3d i;
      const auto& in = *link->inertial;
      i << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      const Eigen::Matrix3d r = poses.at(w.link).linear() * ToEigen(in.origin).linear();
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
      const std::string where = "<gazebo reference=\"" + w.link + "\">";
      w.mu1 = Number(it->second, "mu1", w.mu1, where);
      w.mu2 = Number(it->second, "mu2", w.mu2, where);
      w.kp = Number(it->second, "kp", w.kp, where);
      w.kd = Number(it->second, "kd", w.kd, where);
      if (w.mu1 < 0 || w.mu2 < 0) throw RobotModelError(where + ": mu1/mu2 must be >= 0");
    }
  }
  const double measured_track = std::abs(m.wheels[kFrontLeft].position.y() -
                                         m.wheels[kFrontRight].position.y());
  if (std::abs(measured_track - m.drive.wheel_separation) > 1e-3) {
    m.warnings.push_back("wheelSeparation " + std::to_string(m.drive.wheel_separation) +
                         " differs from the URDF's wheel track " + std::to_string(measured_track));
  }
  if (m.wheels[kFrontLeft].position.y() < m.wheels[kFrontRight].position.y()) {
    throw RobotModelError("leftFrontJoint '" + m.wheels[kFrontLeft].joint +
                          "' is right of rightFrontJoint: the drive plugin's joints are swapped");
  }

  // Body: everything but the wheels, as one box; mass and yaw inertia of the whole robot.
  std::vector<urdf::LinkSharedPtr> links;
  urdf.getLinks(links);
  std::vector<Eigen::Vector3d> corners;
  std::vector<Eigen::Vector2d> outline;
  m.total_mass = 0.0;
  m.body_inertia_z = 0.0;
  for (const auto& link : links) {
    const Eigen::Isometry3d& pose = poses.at(link->name);
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
    std::vector<Eigen::Vector3d> link_corners;
    for (const auto& c : link->collision_array) AddCollisionCorners(*c, pose, &link_corners);
    for (const auto& c : link_corners) outline.emplace_back(c.x(), c.y());
    // Casters and wheels are not part of the body box; everything else rigidly attached is.
    const bool movable = link->parent_joint && link->parent_joint->type != urdf::Joint::FIXED;
    if (!wheel_links.count(link->name) && !movable) {
      corners.insert(corners.end(), link_corners.begin(), link_corners.end());
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

}  // namespace minibot3d_sim
