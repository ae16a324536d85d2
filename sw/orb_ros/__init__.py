# SPDX-License-Identifier: MIT
"""The accelerator's ROS 1 node (docs/ros.md): orb_ros.node, and orb_ros.msgs for the message
classes generated from orb_accel_msgs/ by Debian's genpy. numpy and Debian's ROS packages only."""
