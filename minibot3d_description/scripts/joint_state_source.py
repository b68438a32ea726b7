#!/usr/bin/env python3
"""Publishes sensor_msgs/JointState for every movable joint of robot_description, at rest.

A stand-in for joint_state_publisher (not packaged for Debian 12) when the robot is only viewed:
robot_state_publisher needs a state for each non-fixed joint before it can publish their tf.
Under the simulator, minibot3d_sim publishes the real wheel states instead.
Parameters: ~rate (Hz, default 10), robot_description.
"""
import sys
import xml.etree.ElementTree as ET

import rospy
from sensor_msgs.msg import JointState


def movable_joints(urdf_xml):
    root = ET.fromstring(urdf_xml)
    return [j.get('name') for j in root.findall('joint')
            if j.get('type') not in ('fixed', 'floating', 'planar')]


def main():
    rospy.init_node('joint_state_source')
    try:
        urdf_xml = rospy.get_param('robot_description')
    except KeyError:
        rospy.logfatal('joint_state_source: parameter robot_description is not set')
        return 1
    try:
        names = movable_joints(urdf_xml)
    except ET.ParseError as e:
        rospy.logfatal('joint_state_source: robot_description is not valid XML: %s', e)
        return 1
    rate_hz = rospy.get_param('~rate', 10.0)
    if rate_hz <= 0:
        rospy.logfatal('joint_state_source: ~rate must be > 0, got %s', rate_hz)
        return 1
    pub = rospy.Publisher('joint_states', JointState, queue_size=1)
    msg = JointState(name=names, position=[0.0] * len(names))
    rate = rospy.Rate(rate_hz)
    while not rospy.is_shutdown():
        msg.header.stamp = rospy.Time.now()
        pub.publish(msg)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    return 0


if __name__ == '__main__':
    sys.exit(main())
