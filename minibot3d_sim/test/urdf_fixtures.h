// Small robot descriptions written in the tests: a two-wheel diff-drive base (TurtleBot-style
// wheel joints, a caster on the floor), a holonomic planar-move base, and a four-wheel base driven
// through gazebo_ros_control. Each takes extra plugin tags and extra <gazebo> blocks.
#ifndef MINIBOT3D_SIM_TEST_URDF_FIXTURES_H_
#define MINIBOT3D_SIM_TEST_URDF_FIXTURES_H_

#include <string>

namespace minibot3d_sim {
namespace testing {

inline std::string Inertial(double mass) {
  return "<inertial><mass value='" + std::to_string(mass) +
         "'/><inertia ixx='1e-3' iyy='1e-3' izz='1e-3' ixy='0' ixz='0' iyz='0'/></inertial>";
}

// base_footprint → base_link (0.3 × 0.2 × 0.1 box, its bottom 0.03 m up), wheels of radius 0.033
// at y = ±0.14 on joints turned by rpy (-π/2, 0, 0) about axis z (as TurtleBot3's), a caster ball
// resting on the floor at x = -0.1, and a laser link.
inline std::string DiffDriveUrdf(const std::string& plugin_tags = "",
                                 const std::string& gazebo_blocks = "") {
  std::string wheels;
  for (const char* side : {"left", "right"}) {
    const double y = std::string(side) == "left" ? 0.14 : -0.14;
    wheels += std::string("<link name='wheel_") + side +
              "_link'><collision><geometry><cylinder radius='0.033' length='0.018'/></geometry>"
              "</collision>" + Inertial(0.03) + "</link><joint name='wheel_" + side +
              "_joint' type='continuous'><parent link='base_link'/><child link='wheel_" + side +
              "_link'/><origin xyz='0 " + std::to_string(y) +
              " 0.033' rpy='-1.5707963267948966 0 0'/><axis xyz='0 0 1'/></joint>";
  }
  return "<?xml version='1.0'?><robot name='diffbot'><link name='base_footprint'/>"
         "<link name='base_link'><collision><origin xyz='0 0 0.08'/><geometry><box size='0.3 "
         "0.2 0.1'/></geometry></collision>" + Inertial(1.0) + "</link>"
         "<joint name='base_joint' type='fixed'><parent link='base_footprint'/><child "
         "link='base_link'/></joint>" + wheels +
         "<link name='caster'><collision><geometry><sphere radius='0.02'/></geometry></collision>" +
         Inertial(0.01) + "</link><joint name='caster_joint' type='fixed'><parent "
         "link='base_link'/><child link='caster'/><origin xyz='-0.1 0 0.02'/></joint>"
         "<link name='base_scan'/><joint name='scan_joint' type='fixed'><parent link='base_link'/>"
         "<child link='base_scan'/><origin xyz='0 0 0.17'/></joint>"
         "<gazebo><plugin name='drive' filename='libgazebo_ros_diff_drive.so'>"
         "<leftJoint>wheel_left_joint</leftJoint><rightJoint>wheel_right_joint</rightJoint>"
         "<wheelSeparation>0.28</wheelSeparation><wheelDiameter>0.066</wheelDiameter>"
         "<commandTopic>cmd_vel</commandTopic><odometryTopic>odom</odometryTopic>"
         "<odometryFrame>odom</odometryFrame><robotBaseFrame>base_footprint</robotBaseFrame>" +
         plugin_tags + "</plugin></gazebo>" + gazebo_blocks + "</robot>";
}

// A round-ish holonomic base with no wheels.
inline std::string PlanarMoveUrdf(const std::string& plugin_tags = "") {
  return "<?xml version='1.0'?><robot name='omni'><link name='base_footprint'/>"
         "<link name='base_link'><collision><origin xyz='0 0 0.1'/><geometry><cylinder "
         "radius='0.2' length='0.15'/></geometry></collision>" + Inertial(5.0) + "</link>"
         "<joint name='base_joint' type='fixed'><parent link='base_footprint'/><child "
         "link='base_link'/></joint>"
         "<gazebo><plugin name='move' filename='libgazebo_ros_planar_move.so'>"
         "<commandTopic>cmd_vel</commandTopic><odometryTopic>odom</odometryTopic>"
         "<odometryFrame>odom</odometryFrame><odometryRate>20</odometryRate>"
         "<robotBaseFrame>base_footprint</robotBaseFrame>" + plugin_tags + "</plugin></gazebo>"
         "</robot>";
}

// A four-wheel base (wheels of radius 0.11 at (±0.25, ±0.25) about base_link, which sits at axle
// height) driven by gazebo_ros_control; the controllers come from the parameter server.
inline std::string FourWheelRosControlUrdf(const std::string& gazebo_blocks = "") {
  std::string wheels;
  for (const char* fb : {"front", "rear"}) {
    for (const char* side : {"left", "right"}) {
      const double x = std::string(fb) == "front" ? 0.25 : -0.25;
      const double y = std::string(side) == "left" ? 0.25 : -0.25;
      const std::string name = std::string(fb) + "_" + side + "_wheel";
      wheels += "<link name='" + name + "_link'><collision><origin rpy='1.5707963267948966 0 0'/>"
                "<geometry><cylinder radius='0.11' length='0.1'/></geometry></collision>" +
                Inertial(2.0) + "</link><joint name='" + name +
                "' type='continuous'><parent link='base_link'/><child link='" + name +
                "_link'/><origin xyz='" + std::to_string(x) + " " + std::to_string(y) +
                " 0'/><axis xyz='0 1 0'/><limit effort='40' velocity='20'/></joint>"
                "<transmission name='" + name + "_trans'><type>transmission_interface/"
                "SimpleTransmission</type><joint name='" + name + "'><hardwareInterface>"
                "hardware_interface/VelocityJointInterface</hardwareInterface></joint><actuator "
                "name='" + name + "_motor'><mechanicalReduction>1</mechanicalReduction></actuator>"
                "</transmission>";
    }
  }
  return "<?xml version='1.0'?><robot name='quad'><link name='base_footprint'/>"
         "<link name='base_link'><collision><origin xyz='0 0 0.1'/><geometry><box size='0.8 "
         "0.4 0.2'/></geometry></collision>" + Inertial(30.0) + "</link>"
         "<joint name='base_joint' type='fixed'><parent link='base_footprint'/><child "
         "link='base_link'/><origin xyz='0 0 0.11'/></joint>" + wheels +
         "<gazebo><plugin name='gazebo_ros_control' filename='libgazebo_ros_control.so'>"
         "<robotNamespace>/</robotNamespace></plugin></gazebo>" + gazebo_blocks + "</robot>";
}

// The diff-drive fixture (body 0.3 x 0.2 m, 3-13 cm up) with a laser looking ahead 7 cm up (through
// the height of other robots' bodies and of actors) and a depth camera 10 cm up.
inline std::string SensingDiffDriveUrdf() {
  return testing::DiffDriveUrdf(
      "<updateRate>0</updateRate>",
      "<gazebo reference='base_scan'><sensor type='ray' name='front'><update_rate>10</update_rate>"
      "<pose>0 0 -0.1 0 0 0</pose><ray><scan><horizontal><samples>181</samples>"
      "<resolution>1</resolution><min_angle>-1.5707963</min_angle><max_angle>1.5707963</max_angle>"
      "</horizontal></scan><range><min>0.05</min><max>8</max><resolution>0.001</resolution>"
      "</range></ray><plugin name='l' filename='libgazebo_ros_laser.so'><topicName>scan"
      "</topicName><frameName>base_scan</frameName></plugin></sensor></gazebo>"
      "<gazebo reference='base_link'><sensor type='depth' name='cam'><update_rate>10</update_rate>"
      "<pose>0.16 0 0.1 0 0 0</pose><camera><horizontal_fov>1.0</horizontal_fov><image><width>41"
      "</width><height>31</height><format>R8G8B8</format></image><clip><near>0.05</near>"
      "<far>8</far></clip><depth_camera/></camera><plugin name='c' "
      "filename='libgazebo_ros_openni_kinect.so'><cameraName>camera</cameraName><frameName>"
      "base_link</frameName></plugin></sensor></gazebo>");
}

}  // namespace testing
}  // namespace minibot3d_sim

#endif  // MINIBOT3D_SIM_TEST_URDF_FIXTURES_H_
