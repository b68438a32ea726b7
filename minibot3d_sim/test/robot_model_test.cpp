// ParseRobotModel on the shipped xacro and on small inline URDFs with one thing wrong each.
#include "minibot3d_sim/robot_model.h"

#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "urdf_fixtures.h"

namespace minibot3d_sim {
namespace {

std::string ExpandXacro(const std::string& path) {
  const std::string cmd = "xacro '" + path + "' 2>/dev/null";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return "";
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof(buf), pipe)) > 0) out.append(buf, n);
  pclose(pipe);
  return out;
}

std::string ExpandShippedXacro() { return ExpandXacro(MINIBOT3D_DESCRIPTION_XACRO); }

// The other shipped robots: every tag read, nothing warned about.
TEST(RobotModelTest, ShippedDiffbotAndQuadbot) {
  const std::string dir = std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/../minibot3d_description/urdf/";
  RobotModelOptions o;
  o.resolve_mesh_url = [](const std::string& url) {
    const std::string pkg = "package://minibot3d_description/";
    return std::string(MINIBOT3D_SIM_SOURCE_DIR) + "/../minibot3d_description/" +
           url.substr(pkg.size());
  };
  const RobotModel diffbot = ParseRobotModel(ExpandXacro(dir + "diffbot.xacro"), o);
  EXPECT_TRUE(diffbot.warnings.empty()) << diffbot.warnings.front();
  EXPECT_EQ(diffbot.drive.kind, DriveKind::kDiffDrive);
  EXPECT_EQ(diffbot.lasers.size(), 1u);
  EXPECT_EQ(diffbot.imus.size(), 1u);
  ASSERT_EQ(diffbot.cameras.size(), 1u);
  EXPECT_EQ(diffbot.cameras[0].ros.frame_name, "camera_optical_frame");
  EXPECT_EQ(diffbot.supports.size(), 1u);  // the caster ball
  o.controllers = LoadControllerParams(std::string(MINIBOT3D_SIM_SOURCE_DIR) +
                                       "/../config/robots/quadbot/control.yaml");
  const RobotModel quadbot = ParseRobotModel(ExpandXacro(dir + "quadbot.xacro"), o);
  EXPECT_TRUE(quadbot.warnings.empty()) << quadbot.warnings.front();
  EXPECT_EQ(quadbot.drive.kind, DriveKind::kDiffDriveController);
  EXPECT_EQ(quadbot.drive.controller_name, "mobile_base_controller");
  EXPECT_EQ(quadbot.drive.joint_state_controller_name, "joint_state_controller");
  EXPECT_EQ(quadbot.wheels.size(), 4u);
  EXPECT_NEAR(quadbot.drive.controller.wheel_separation, 0.36, 1e-12);  // from the URDF
  EXPECT_DOUBLE_EQ(quadbot.drive.controller.wheel_separation_multiplier, 1.79);
  ASSERT_EQ(quadbot.lasers.size(), 2u);
  EXPECT_EQ(quadbot.lasers[1].topic, "rear_laser/scan");
  // The rear laser looks backwards.
  EXPECT_NEAR((quadbot.lasers[1].pose_in_root.linear() * Eigen::Vector3d::UnitX()).x(), -1.0, 1e-9);
  // The mesh bumper counts as collision geometry: the footprint reaches its front.
  double front = 0.0;
  for (const auto& p : quadbot.footprint) front = std::max(front, p.x());
  EXPECT_NEAR(front, 0.29, 1e-4);
}

// A minimal valid robot: a box body and four wheels, the drive plugin and a ray sensor.
std::string MiniUrdf(const std::string& drive_extra = "", const std::string& sensor = "",
                     const std::string& first_joint = "fl") {
  std::string wheels;
  const char* names[4] = {"fl", "fr", "rl", "rr"};
  const double xs[4] = {0.1, 0.1, -0.1, -0.1}, ys[4] = {0.15, -0.15, 0.15, -0.15};
  for (int i = 0; i < 4; ++i) {
    wheels += std::string("<link name='") + names[i] + "_w'><collision><origin rpy='1.5708 0 0'/>"
              "<geometry><cylinder radius='0.05' length='0.03'/></geometry></collision>"
              "<inertial><mass value='0.1'/><inertia ixx='1e-4' iyy='1e-4' izz='1e-4' ixy='0' "
              "ixz='0' iyz='0'/></inertial></link>"
              "<joint name='" + names[i] + "' type='continuous'><parent link='base'/><child link='" +
              names[i] + "_w'/><origin xyz='" + std::to_string(xs[i]) + " " +
              std::to_string(ys[i]) + " 0.05'/><axis xyz='0 1 0'/>"
              "<limit effort='1' velocity='10'/></joint>";
  }
  const std::string default_sensor =
      "<gazebo reference='lidar'><sensor type='ray' name='s'><pose>0 0 0.02 0 0 0</pose>"
      "<update_rate>5</update_rate><ray><scan><horizontal><samples>90</samples>"
      "<min_angle>-1.5</min_angle><max_angle>1.5</max_angle></horizontal></scan>"
      "<range><min>0.1</min><max>8</max></range></ray>"
      "<plugin name='p' filename='libgazebo_ros_laser.so'><topicName>scan2</topicName>"
      "<frameName>lidar</frameName></plugin></sensor></gazebo>";
  return "<?xml version='1.0'?><robot name='mini'>"
         "<link name='base'><collision><origin xyz='0 0 0.1'/><geometry><box size='0.3 0.2 0.1'/>"
         "</geometry></collision><inertial><origin xyz='0 0 0.1'/><mass value='2'/><inertia "
         "ixx='0.01' iyy='0.02' izz='0.03' ixy='0' ixz='0' iyz='0'/></inertial></link>"
         "<link name='lidar'/><joint name='lj' type='fixed'><parent link='base'/><child "
         "link='lidar'/><origin xyz='0.05 0 0.2' rpy='0 0 3.14159265'/></joint>" +
         wheels +
         "<gazebo><plugin name='d' filename='libgazebo_ros_skid_steer_drive.so'>"
         "<leftFrontJoint>" + first_joint + "</leftFrontJoint><rightFrontJoint>fr</rightFrontJoint>"
         "<leftRearJoint>rl</leftRearJoint><rightRearJoint>rr</rightRearJoint>"
         "<wheelSeparation>0.3</wheelSeparation><wheelDiameter>0.1</wheelDiameter>"
         "<torque>3</torque><robotBaseFrame>base</robotBaseFrame>" + drive_extra +
         "</plugin></gazebo>" + (sensor.empty() ? default_sensor : sensor) + "</robot>";
}

TEST(RobotModelTest, ShippedRobot) {
  const std::string xml = ExpandShippedXacro();
  ASSERT_FALSE(xml.empty()) << "xacro could not expand " << MINIBOT3D_DESCRIPTION_XACRO;
  const RobotModel m = ParseRobotModel(xml);
  EXPECT_EQ(m.root_link, "base_footprint");
  EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
  ASSERT_EQ(m.drive.kind, DriveKind::kSkidSteer);
  const SkidSteerDriveOptions& d = m.drive.skid_steer;
  EXPECT_DOUBLE_EQ(d.wheel_separation, 0.2);
  EXPECT_DOUBLE_EQ(d.wheel_diameter, 0.08);
  EXPECT_DOUBLE_EQ(d.torque, 2.0);
  EXPECT_EQ(d.robot_base_frame, "base_footprint");
  EXPECT_EQ(d.command_topic, "cmd_vel");
  EXPECT_EQ(d.odometry_frame, "odom");
  EXPECT_TRUE(d.broadcast_tf);
  EXPECT_EQ(m.drive.robot_namespace, "/");
  ASSERT_EQ(m.wheels.size(), 4u);
  EXPECT_EQ(m.wheels[0].joint, "front_left_wheel_hinge");
  EXPECT_EQ(m.wheels[3].joint, "rear_right_wheel_hinge");
  EXPECT_TRUE(m.supports.empty()) << "the casters ride above the floor";
  for (const auto& w : m.wheels) {
    EXPECT_NEAR(w.radius, 0.04, 1e-9);
    EXPECT_NEAR(w.position.z(), 0.04, 1e-9) << w.joint << ": axle height";
    EXPECT_NEAR(std::abs(w.position.y()), 0.1, 1e-9);
    EXPECT_DOUBLE_EQ(w.mu1, 1.0);
    EXPECT_GT(w.inertia_axle, 0.0);
    EXPECT_GT(w.velocity_limit, 0.0);
  }
  EXPECT_GT(m.wheels[0].position.y(), 0.0);
  EXPECT_GT(m.wheels[0].position.x(), 0.0);
  ASSERT_EQ(m.lasers.size(), 1u);
  const LaserSpec& l = m.lasers[0];
  EXPECT_EQ(l.frame_id, "laser");
  EXPECT_EQ(l.topic, "scan");
  EXPECT_EQ(l.samples, 360);
  EXPECT_DOUBLE_EQ(l.min_range, 0.15);
  EXPECT_DOUBLE_EQ(l.max_range, 12.0);
  EXPECT_DOUBLE_EQ(l.update_rate, 10.0);
  EXPECT_DOUBLE_EQ(l.noise_stddev, 0.01);
  // laser = chassis top (0.04 + 0.055) + 0.02 forward, yawed by pi; rays 3 cm above it.
  EXPECT_NEAR(l.link_in_root.translation().x(), 0.02, 1e-9);
  EXPECT_NEAR(l.link_in_root.translation().z(), 0.095, 1e-9);
  EXPECT_NEAR(l.pose_in_root.translation().z(), 0.125, 1e-9);
  EXPECT_NEAR((l.link_in_root.linear() * Eigen::Vector3d::UnitX()).x(), -1.0, 1e-6);
  EXPECT_NEAR(m.total_mass, 1.0 + 4 * 0.08 + 2 * 0.02 + 0.17, 1e-9);
  EXPECT_NEAR(m.body_size.x(), 0.24, 1e-9);
  EXPECT_GT(m.body_inertia_z, 0.0);
  EXPECT_GE(m.footprint.size(), 4u);
}

TEST(RobotModelTest, MinimalRobot) {
  const RobotModel m = ParseRobotModel(MiniUrdf());
  ASSERT_EQ(m.lasers.size(), 1u);
  const LaserSpec& l = m.lasers[0];
  EXPECT_EQ(l.topic, "scan2");
  EXPECT_EQ(l.samples, 90);
  EXPECT_DOUBLE_EQ(l.update_rate, 5.0);
  EXPECT_NEAR(l.pose_in_root.translation().z(), 0.22, 1e-9);
  EXPECT_DOUBLE_EQ(m.drive.skid_steer.torque, 3.0);
  EXPECT_EQ(m.drive.skid_steer.odometry_topic, "odom");  // the plugin's defaults for absent tags
  EXPECT_FALSE(m.drive.skid_steer.broadcast_tf);
  EXPECT_NEAR(m.wheels[1].position.y(), -0.15, 1e-6);
  EXPECT_NEAR(m.total_mass, 2.4, 1e-12);
  // Footprint: the hull of body and wheels spans the wheels' outer faces.
  double max_y = 0;
  for (const auto& p : m.footprint) max_y = std::max(max_y, p.y());
  EXPECT_NEAR(max_y, 0.165, 1e-6);
}

void ExpectError(const std::string& xml, const std::string& needle) {
  try {
    ParseRobotModel(xml);
    ADD_FAILURE() << "no error; expected one mentioning '" << needle << "'";
  } catch (const RobotModelError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(RobotModelTest, BadInputIsNamed) {
  ExpectError("", "empty");
  ExpectError("<robot name='x'>", "not valid XML");
  ExpectError("<notarobot/>", "<robot>");
  std::string no_drive = MiniUrdf();
  no_drive.replace(no_drive.find("libgazebo_ros_skid_steer_drive.so"), 33, "libother_plugin.so");
  ExpectError(no_drive, "no drive plugin");
  ExpectError(MiniUrdf("", "", "nosuchjoint"), "nosuchjoint");
  ExpectError(MiniUrdf("<updateRate>fast</updateRate>"), "updateRate");
  std::string bad_range = MiniUrdf();
  bad_range.replace(bad_range.find("<max>8</max>"), 12, "<max>0.05</max>");
  ExpectError(bad_range, "<range>");
  std::string bad_ref = MiniUrdf();
  bad_ref.replace(bad_ref.find("reference='lidar'"), 17, "reference='nolink'");
  ExpectError(bad_ref, "nolink");
}

// A laser needs no more than it is given, but a robot may have none: the simulator then publishes
// no scans.
TEST(RobotModelTest, ARobotWithoutLaserIsFine) {
  const RobotModel m =
      ParseRobotModel(MiniUrdf("", "<gazebo reference='lidar'><material>x</material></gazebo>"));
  EXPECT_TRUE(m.lasers.empty());
}

TEST(RobotModelTest, UnknownPluginsAndTagsWarnOnce) {
  const std::string extra_sensor =
      "<gazebo reference='lidar'><sensor type='ray' name='s'><update_rate>5</update_rate>"
      "<ray><scan><horizontal><samples>10</samples><min_angle>-1</min_angle><max_angle>1"
      "</max_angle></horizontal></scan><range><min>0.1</min><max>8</max></range></ray>"
      "<plugin name='p' filename='libgazebo_ros_laser.so'/></sensor>"
      "<wobble>1</wobble></gazebo><gazebo><plugin name='x' filename='libmystery.so'/></gazebo>";
  const RobotModel m = ParseRobotModel(MiniUrdf("", extra_sensor));
  auto count = [&m](const std::string& needle) {
    int n = 0;
    for (const auto& w : m.warnings) n += w.find(needle) != std::string::npos;
    return n;
  };
  EXPECT_EQ(count("<wobble>"), 1);
  EXPECT_EQ(count("libmystery.so"), 1);
  // A laser plugin without topicName/frameName gets Gazebo's defaults, with a warning.
  EXPECT_EQ(count("Gazebo's defaults /world"), 1);
  ASSERT_EQ(m.lasers.size(), 1u);
  EXPECT_EQ(m.lasers[0].topic, "/world");
  EXPECT_EQ(m.lasers[0].frame_id, "world");
}

}  // namespace
}  // namespace minibot3d_sim

namespace minibot3d_sim {
namespace {

using testing::DiffDriveUrdf;
using testing::FourWheelRosControlUrdf;

// A depth camera, an IMU sensor, a second laser and ground truth on the diff-drive robot.
std::string SensorBlocks(int width = 320) {
  return "<gazebo reference='base_scan'><sensor type='ray' name='front'><update_rate>5</update_rate>"
         "<pose>0 0 0 0 0 1.5707963267948966</pose><ray><scan><horizontal><samples>360</samples>"
         "<resolution>1</resolution><min_angle>0</min_angle><max_angle>6.28319</max_angle>"
         "</horizontal></scan><range><min>0.12</min><max>3.5</max><resolution>0.015</resolution>"
         "</range><noise type='gaussian'><mean>0</mean><stddev>0.01</stddev></noise></ray>"
         "<plugin name='l' filename='libgazebo_ros_laser.so'><topicName>scan</topicName>"
         "<frameName>base_scan</frameName></plugin></sensor></gazebo>"
         "<gazebo reference='base_link'><sensor type='imu' name='imu'><update_rate>200"
         "</update_rate><imu><angular_velocity><z><noise type='gaussian'><mean>0</mean><stddev>"
         "0.0002</stddev><bias_mean>0.0000075</bias_mean><bias_stddev>0.0000008</bias_stddev>"
         "</noise></z></angular_velocity></imu><plugin name='i' filename='libgazebo_ros_imu_sensor.so'>"
         "<topicName>imu</topicName><frameName>base_link</frameName><updateRateHZ>100"
         "</updateRateHZ></plugin></sensor>"
         "<sensor type='depth' name='cam'><update_rate>15</update_rate><pose>0.1 0 0.2 0 0 0</pose>"
         "<camera><horizontal_fov>1.0472</horizontal_fov><image><width>" + std::to_string(width) +
         "</width><height>240</height><format>R8G8B8</format></image><clip><near>0.05</near>"
         "<far>8</far></clip><depth_camera/></camera>"
         "<plugin name='c' filename='libgazebo_ros_openni_kinect.so'><cameraName>camera</cameraName>"
         "<frameName>base_link</frameName><pointCloudTopicName>depth/points</pointCloudTopicName>"
         "</plugin></sensor></gazebo>"
         "<gazebo><plugin name='gt' filename='libgazebo_ros_p3d.so'><bodyName>base_link</bodyName>"
         "<topicName>truth</topicName><updateRate>50</updateRate></plugin></gazebo>";
}

TEST(RobotModelTest, DiffDriveRobotWithSensors) {
  const RobotModel m = ParseRobotModel(DiffDriveUrdf("", SensorBlocks()));
  ASSERT_EQ(m.drive.kind, DriveKind::kDiffDrive);
  EXPECT_EQ(m.drive.robot_namespace, "/");  // injected, as spawn_model does
  ASSERT_EQ(m.wheels.size(), 2u);
  EXPECT_EQ(m.wheels[0].joint, "wheel_left_joint");
  EXPECT_NEAR(m.wheels[0].radius, 0.033, 1e-12);
  EXPECT_DOUBLE_EQ(m.wheels[0].torque, 5.0);  // wheelTorque's default
  // The caster ball touches the floor: it carries load.
  ASSERT_EQ(m.supports.size(), 1u);
  EXPECT_EQ(m.supports[0].link, "caster");
  ASSERT_EQ(m.lasers.size(), 1u);
  EXPECT_EQ(m.lasers[0].frame_id, "base_scan");
  EXPECT_NEAR(m.lasers[0].pose_in_root.translation().z(), 0.17, 1e-12);
  EXPECT_DOUBLE_EQ(m.lasers[0].noise_stddev, 0.01);
  ASSERT_EQ(m.imus.size(), 1u);
  EXPECT_EQ(m.imus[0].topic, "imu");
  EXPECT_TRUE(m.imus[0].gravity);
  EXPECT_DOUBLE_EQ(m.imus[0].update_rate, 100.0);  // the plugin's rate below the sensor's
  EXPECT_DOUBLE_EQ(m.imus[0].noise.av_z_stddev, 0.0002);
  ASSERT_EQ(m.cameras.size(), 1u);
  const CameraSpec& c = m.cameras[0];
  EXPECT_TRUE(c.depth);
  EXPECT_EQ(c.sensor.width, 320);
  EXPECT_DOUBLE_EQ(c.ros.point_cloud_cutoff_max, 5.0);  // openni_kinect's default
  EXPECT_EQ(c.ros.point_cloud_topic_name, "depth/points");
  EXPECT_EQ(c.ros.depth_image_topic_name, "depth/image_raw");
  EXPECT_DOUBLE_EQ(c.update_rate, 15.0);
  EXPECT_NEAR(c.pose_in_root.translation().x(), 0.1, 1e-12);
  ASSERT_EQ(m.ground_truths.size(), 1u);
  EXPECT_EQ(m.ground_truths[0].options.frame_name, "world");
  EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
}

// A robot description's plugins live in the namespace the simulator spawns it in unless they
// name their own.
TEST(RobotModelTest, SpawnNamespace) {
  RobotModelOptions o;
  o.spawn_namespace = "/robot2";
  const RobotModel m = ParseRobotModel(DiffDriveUrdf("", SensorBlocks()), o);
  EXPECT_EQ(m.drive.robot_namespace, "/robot2");
  EXPECT_EQ(m.lasers[0].robot_namespace, "/robot2");
  const RobotModel own = ParseRobotModel(DiffDriveUrdf("<robotNamespace>/mine</robotNamespace>"), o);
  EXPECT_EQ(own.drive.robot_namespace, "/mine");
}

void ExpectError(const std::string& xml, const RobotModelOptions& o, const std::string& needle) {
  try {
    ParseRobotModel(xml, o);
    ADD_FAILURE() << "no error; expected one mentioning '" << needle << "'";
  } catch (const RobotModelError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(RobotModelTest, BadInputOfOtherRobotsIsNamed) {
  const RobotModelOptions none;
  // A plugin naming a joint the URDF lacks.
  std::string xml = DiffDriveUrdf();
  const std::string left = "<leftJoint>wheel_left_joint";
  xml.replace(xml.find(left), left.size(), "<leftJoint>no_such_joint");
  ExpectError(xml, none, "no_such_joint");
  // Two drive plugins.
  ExpectError(DiffDriveUrdf("", "<gazebo><plugin name='second' filename='libgazebo_ros_planar_move.so'/>"
                                "</gazebo>"),
              none, "two drive plugins");
  // A sensor on a link that does not exist.
  ExpectError(DiffDriveUrdf("", "<gazebo reference='no_such_link'><sensor type='ray' name='s'/>"
                                "</gazebo>"),
              none, "no_such_link");
  // A camera wider than 2^15 pixels.
  ExpectError(DiffDriveUrdf("", SensorBlocks(40000)), none, "40000");
  // A mesh that will not load.
  std::string mesh = DiffDriveUrdf();
  const std::string box = "<box size='0.3 0.2 0.1'/>";
  mesh.replace(mesh.find(box), box.size(), "<mesh filename='file:///no/such/mesh.stl'/>");
  ExpectError(mesh, none, "/no/such/mesh.stl");
  // gazebo_ros_control without a controller, and a controller missing a wheel.
  ExpectError(FourWheelRosControlUrdf(), none, "no diff_drive_controller");
  RobotModelOptions c;
  c.controllers["base"] = {{"type", "diff_drive_controller/DiffDriveController"},
                           {"left_wheel", "[front_left_wheel, rear_left_wheel]"},
                           {"right_wheel", "[front_right_wheel]"},
                           {"pose_covariance_diagonal", "[1, 1, 1, 1, 1, 1]"},
                           {"twist_covariance_diagonal", "[1, 1, 1, 1, 1, 1]"}};
  ExpectError(FourWheelRosControlUrdf(), c, "'left_wheel' has 2 joints and 'right_wheel' 1");
  c.controllers["base"].erase("right_wheel");
  ExpectError(FourWheelRosControlUrdf(), c, "'right_wheel'");
  c.controllers["base"]["right_wheel"] = "[front_right_wheel, rear_right_whee]";
  ExpectError(FourWheelRosControlUrdf(), c, "rear_right_whee");
  c.controllers["base"]["right_wheel"] = "[front_left_wheel, rear_left_wheel]";
  c.controllers["base"]["left_wheel"] = "[front_right_wheel, rear_right_wheel]";
  ExpectError(FourWheelRosControlUrdf(), c, "is listed in left_wheel but is on the right");
  // A bad odometrySource and a laser with several ranges per beam.
  ExpectError(DiffDriveUrdf("<odometrySource>gps</odometrySource>"), none, "odometrySource");
  std::string res = SensorBlocks();
  const std::string one = "<resolution>1</resolution>";
  res.replace(res.find(one), one.size(), "<resolution>2</resolution>");
  ExpectError(DiffDriveUrdf("", res), none, "<horizontal><resolution>");
}

}  // namespace
}  // namespace minibot3d_sim
