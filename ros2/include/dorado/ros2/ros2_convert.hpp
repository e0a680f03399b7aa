#pragma once
/// @file ros2_convert.hpp
/// dorado's values into the idlc-generated ROS 2 messages (ros2/msg/ros2_messages.idl). The
/// messages borrow: their strings and sequences point into the values given, which must outlive
/// the write.

#include <cstdint>
#include <string>
#include <vector>

#include "dorado/io/cdr_messages.hpp"
#include "live_sink.hpp"
#include "ros2_messages.h"

namespace dorado::ros2 {

/// builtin_interfaces/msg/Time of a stamp [ns] (negative stamps: sec < 0, nanosec in 0..1e9-1).
[[nodiscard]] builtin_interfaces_msg_dds__Time_ TimeOf(int64_t stamp_ns);
/// std_msgs/msg/Header; frame_id borrowed.
[[nodiscard]] std_msgs_msg_dds__Header_ HeaderOf(int64_t stamp_ns, const std::string &frame_id);
std_msgs_msg_dds__Header_ HeaderOf(int64_t stamp_ns, std::string &&frame_id) = delete;

/// nav_msgs/msg/Odometry of a live node's output (row-major covariances).
/// Its frames borrowed: `odometry` must outlive the message.
[[nodiscard]] nav_msgs_msg_dds__Odometry_ OdometryOf(const ros_node::OdometryOutput &odometry);
nav_msgs_msg_dds__Odometry_ OdometryOf(ros_node::OdometryOutput &&odometry) = delete;

/// geometry_msgs/msg/TransformStamped of a transform (its frames borrowed).
[[nodiscard]] geometry_msgs_msg_dds__TransformStamped_ TransformOf(
    const ros_node::TransformOutput &transform);
geometry_msgs_msg_dds__TransformStamped_ TransformOf(ros_node::TransformOutput &&transform) =
    delete;

/// sensor_msgs/msg/PointCloud2 of packed points; `fields` is storage the message's field sequence
/// points into.
[[nodiscard]] sensor_msgs_msg_dds__PointCloud2_ CloudOf(
    int64_t stamp_ns, const std::string &frame_id, const ros_node::PackedCloud &packed,
    std::vector<sensor_msgs_msg_dds__PointField_> &fields);

/// sensor_msgs/msg/PointCloud2 of a decoded one (`replay`: what the recording holds, unchanged).
[[nodiscard]] sensor_msgs_msg_dds__PointCloud2_ CloudOf(
    const io::CdrPointCloud2 &cloud, std::vector<sensor_msgs_msg_dds__PointField_> &fields);
sensor_msgs_msg_dds__PointCloud2_ CloudOf(
    io::CdrPointCloud2 &&cloud, std::vector<sensor_msgs_msg_dds__PointField_> &fields) = delete;

/// sensor_msgs/msg/Imu of a decoded one (its frame_id borrowed: `imu` must outlive the message).
[[nodiscard]] sensor_msgs_msg_dds__Imu_ ImuOf(const io::CdrImu &imu);
/// A temporary would leave the message's frame_id dangling.
sensor_msgs_msg_dds__Imu_ ImuOf(io::CdrImu &&imu) = delete;

}  // namespace dorado::ros2
