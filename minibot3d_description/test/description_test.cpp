// Checks the expanded minibot3d URDF: it parses with urdfdom, its tree, joints and physical
// properties are sensible, and the Gazebo-style tags carry what minibot3d_sim expects.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <tinyxml2.h>
#include <urdf/model.h>

namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class DescriptionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    xml_ = ReadFile(MINIBOT3D_URDF);
    ASSERT_FALSE(xml_.empty()) << "expanded URDF missing: " << MINIBOT3D_URDF;
    ASSERT_TRUE(model_.initString(xml_)) << "urdfdom cannot parse " << MINIBOT3D_URDF;
    ASSERT_EQ(doc_.Parse(xml_.c_str()), tinyxml2::XML_SUCCESS);
  }

  // Text of <gazebo><plugin filename=...><tag> for the plugin with that file name.
  std::string PluginParam(const std::string& filename, const std::string& tag) {
    for (auto* g = doc_.RootElement()->FirstChildElement("gazebo"); g;
         g = g->NextSiblingElement("gazebo")) {
      for (auto* p = g->FirstChildElement("plugin"); p; p = p->NextSiblingElement("plugin")) {
        if (p->Attribute("filename", filename.c_str())) {
          auto* e = p->FirstChildElement(tag.c_str());
          return e && e->GetText() ? e->GetText() : "";
        }
      }
    }
    return "";
  }

  tinyxml2::XMLElement* Sensor() {
    for (auto* g = doc_.RootElement()->FirstChildElement("gazebo"); g;
         g = g->NextSiblingElement("gazebo")) {
      if (g->Attribute("reference", "laser")) return g->FirstChildElement("sensor");
    }
    return nullptr;
  }

  std::string xml_;
  urdf::Model model_;
  tinyxml2::XMLDocument doc_;
};

const char* const kWheelJoints[] = {"front_left_wheel_hinge", "front_right_wheel_hinge",
                                    "rear_left_wheel_hinge", "rear_right_wheel_hinge"};

TEST_F(DescriptionTest, TreeFromFootprintToLaser) {
  ASSERT_TRUE(model_.getRoot());
  EXPECT_EQ(model_.getRoot()->name, "base_footprint");
  auto parent_of = [&](const std::string& link) {
    auto l = model_.getLink(link);
    EXPECT_TRUE(l) << link;
    return l && l->getParent() ? l->getParent()->name : std::string();
  };
  EXPECT_EQ(parent_of("base_link"), "base_footprint");
  EXPECT_EQ(parent_of("chassis"), "base_link");
  EXPECT_EQ(parent_of("laser"), "chassis");
  EXPECT_EQ(model_.getJoint("base_footprint_joint")->type, urdf::Joint::FIXED);
}

TEST_F(DescriptionTest, WheelHingesAreContinuousAboutY) {
  for (const char* name : kWheelJoints) {
    auto j = model_.getJoint(name);
    ASSERT_TRUE(j) << name;
    EXPECT_EQ(j->type, urdf::Joint::CONTINUOUS) << name;
    EXPECT_EQ(j->parent_link_name, "base_link") << name;
    EXPECT_DOUBLE_EQ(j->axis.x, 0.0);
    EXPECT_DOUBLE_EQ(j->axis.y, 1.0);
    EXPECT_DOUBLE_EQ(j->axis.z, 0.0);
    ASSERT_TRUE(j->limits) << name << " has no <limit>";
    EXPECT_GT(j->limits->effort, 0.0) << name;
    EXPECT_GT(j->limits->velocity, 0.0) << name;
    // Every driven wheel has a transmission.
    bool has_transmission = false;
    for (auto* t = doc_.RootElement()->FirstChildElement("transmission"); t;
         t = t->NextSiblingElement("transmission")) {
      auto* tj = t->FirstChildElement("joint");
      if (tj && tj->Attribute("name", name)) has_transmission = true;
    }
    EXPECT_TRUE(has_transmission) << name;
  }
  // Two free dummy casters.
  for (const char* name : {"front_caster_wheel_joint", "rear_caster_wheel_joint"}) {
    auto j = model_.getJoint(name);
    ASSERT_TRUE(j) << name;
    EXPECT_EQ(j->type, urdf::Joint::CONTINUOUS) << name;
  }
}

TEST_F(DescriptionTest, WheelGeometryMatchesDrivePlugin) {
  const double separation = std::stod(PluginParam("libgazebo_ros_skid_steer_drive.so",
                                                  "wheelSeparation"));
  const double diameter = std::stod(PluginParam("libgazebo_ros_skid_steer_drive.so",
                                                "wheelDiameter"));
  EXPECT_NEAR(diameter, 0.08, 1e-9);
  for (const char* name : kWheelJoints) {
    auto j = model_.getJoint(name);
    const auto& p = j->parent_to_joint_origin_transform.position;
    EXPECT_NEAR(2.0 * std::abs(p.y), separation, 1e-9) << name;
    auto link = model_.getLink(j->child_link_name);
    ASSERT_TRUE(link->collision);
    auto cyl = std::dynamic_pointer_cast<urdf::Cylinder>(link->collision->geometry);
    ASSERT_TRUE(cyl) << name << ": wheel collision is not a cylinder";
    EXPECT_NEAR(2.0 * cyl->radius, diameter, 1e-9);
    // The wheel touches the floor: axle height above base_footprint equals the radius.
    const auto& base = model_.getJoint("base_footprint_joint")->parent_to_joint_origin_transform;
    EXPECT_NEAR(base.position.z + p.z, cyl->radius, 1e-9) << name;
  }
}

TEST_F(DescriptionTest, LidarJointAsDesigned) {
  auto j = model_.getJoint("rplidar_joint");
  ASSERT_TRUE(j);
  EXPECT_EQ(j->type, urdf::Joint::FIXED);
  EXPECT_EQ(j->child_link_name, "laser");
  const auto& t = j->parent_to_joint_origin_transform;
  EXPECT_NEAR(t.position.x, 0.02, 1e-9);
  EXPECT_NEAR(t.position.y, 0.0, 1e-9);
  EXPECT_NEAR(t.position.z, 0.0, 1e-9);
  double roll, pitch, yaw;
  t.rotation.getRPY(roll, pitch, yaw);
  EXPECT_NEAR(std::abs(yaw), M_PI, 1e-3);
  auto laser = model_.getLink("laser");
  ASSERT_TRUE(laser->visual);
  auto mesh = std::dynamic_pointer_cast<urdf::Mesh>(laser->visual->geometry);
  ASSERT_TRUE(mesh) << "the laser's visual should be the RPLIDAR mesh";
  EXPECT_NE(mesh->filename.find("package://minibot3d_description/meshes/"), std::string::npos);
}

TEST_F(DescriptionTest, EveryLinkHasPhysicalInertia) {
  std::vector<urdf::LinkSharedPtr> links;
  model_.getLinks(links);
  int with_mass = 0;
  for (const auto& link : links) {
    if (!link->inertial) {
      // Only the frames that are pure frames may lack mass.
      EXPECT_TRUE(link->name == "base_footprint" || link->name == "base_link") << link->name;
      continue;
    }
    ++with_mass;
    const auto& i = *link->inertial;
    EXPECT_GT(i.mass, 0.0) << link->name;
    EXPECT_GT(i.ixx, 0.0) << link->name;
    EXPECT_GT(i.iyy, 0.0) << link->name;
    EXPECT_GT(i.izz, 0.0) << link->name;
    // Principal moments of a real body satisfy the triangle inequality.
    EXPECT_LE(i.ixx, i.iyy + i.izz + 1e-12) << link->name;
    EXPECT_LE(i.iyy, i.ixx + i.izz + 1e-12) << link->name;
    EXPECT_LE(i.izz, i.ixx + i.iyy + 1e-12) << link->name;
  }
  EXPECT_EQ(with_mass, 8);  // chassis, 4 wheels, 2 casters, laser
}

TEST_F(DescriptionTest, DrivePluginParameters) {
  const std::string so = "libgazebo_ros_skid_steer_drive.so";
  EXPECT_EQ(PluginParam(so, "leftFrontJoint"), "front_left_wheel_hinge");
  EXPECT_EQ(PluginParam(so, "rightFrontJoint"), "front_right_wheel_hinge");
  EXPECT_EQ(PluginParam(so, "leftRearJoint"), "rear_left_wheel_hinge");
  EXPECT_EQ(PluginParam(so, "rightRearJoint"), "rear_right_wheel_hinge");
  EXPECT_EQ(PluginParam(so, "robotBaseFrame"), "base_footprint");
  EXPECT_EQ(PluginParam(so, "commandTopic"), "cmd_vel");
  EXPECT_EQ(PluginParam(so, "odometryTopic"), "odom");
  EXPECT_EQ(PluginParam(so, "odometryFrame"), "odom");
  EXPECT_EQ(PluginParam(so, "broadcastTF"), "true");
  EXPECT_GT(std::stod(PluginParam(so, "updateRate")), 0.0);
  EXPECT_GT(std::stod(PluginParam(so, "torque")), 0.0);
  for (const char* c : {"covariance_x", "covariance_y", "covariance_yaw"}) {
    EXPECT_GT(std::stod(PluginParam(so, c)), 0.0) << c;
  }
}

TEST_F(DescriptionTest, RplidarSensor) {
  auto* sensor = Sensor();
  ASSERT_NE(sensor, nullptr) << "no <sensor> in <gazebo reference=\"laser\">";
  EXPECT_STREQ(sensor->Attribute("type"), "ray");
  EXPECT_DOUBLE_EQ(std::stod(sensor->FirstChildElement("update_rate")->GetText()), 10.0);
  auto* ray = sensor->FirstChildElement("ray");
  ASSERT_NE(ray, nullptr);
  auto* h = ray->FirstChildElement("scan")->FirstChildElement("horizontal");
  EXPECT_EQ(std::stoi(h->FirstChildElement("samples")->GetText()), 360);
  const double fov = std::stod(h->FirstChildElement("max_angle")->GetText()) -
                     std::stod(h->FirstChildElement("min_angle")->GetText());
  EXPECT_NEAR(fov, 2.0 * M_PI, 1e-6);
  auto* range = ray->FirstChildElement("range");
  EXPECT_DOUBLE_EQ(std::stod(range->FirstChildElement("min")->GetText()), 0.15);
  EXPECT_DOUBLE_EQ(std::stod(range->FirstChildElement("max")->GetText()), 12.0);
  auto* noise = ray->FirstChildElement("noise");
  EXPECT_STREQ(noise->FirstChildElement("type")->GetText(), "gaussian");
  EXPECT_NEAR(std::stod(noise->FirstChildElement("stddev")->GetText()), 0.01, 1e-12);
  auto* plugin = sensor->FirstChildElement("plugin");
  ASSERT_NE(plugin, nullptr);
  EXPECT_STREQ(plugin->Attribute("filename"), "libgazebo_ros_laser.so");
  EXPECT_STREQ(plugin->FirstChildElement("topicName")->GetText(), "scan");
  EXPECT_STREQ(plugin->FirstChildElement("frameName")->GetText(), "laser");
}

}  // namespace
