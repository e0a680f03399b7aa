#pragma once
/// @file cdr_messages.hpp
/// The ROS 2 messages dorado reads, from their CDR serialization (the rosbag2 "cdr" format and
/// what a ROS 2 publisher sends on DDS: a 4-byte encapsulation header, then XCDR1 with
/// alignment). One codec for the rosbag2 reader, dorado_ros2 and `dorado replay`. Built with
/// rosbag2 support (Fast-CDR; DORADO_HAVE_ROSBAG2).

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "dorado/io/pointcloud_decoder.hpp"

namespace dorado::io {

struct CdrHeader {
    int64_t stamp_ns = 0;  ///< 0 when the driver left the stamp empty
    std::string frame_id;
};

/// sensor_msgs/msg/PointCloud2; cloud.data points into the serialized bytes.
struct CdrPointCloud2 {
    CdrHeader header;
    CloudBufferView cloud;
    bool is_dense = false;
};

/// sensor_msgs/msg/Imu, every field (row-major 3x3 covariances, as in the message).
struct CdrImu {
    CdrHeader header;
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    double orientation_covariance[9] = {};
    Eigen::Vector3d omega_radps = Eigen::Vector3d::Zero();
    double omega_covariance[9] = {};
    Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();
    double accel_covariance[9] = {};
};

/// The pose of nav_msgs/msg/Odometry or geometry_msgs/msg/PoseStamped (and, of an Odometry, its
/// child frame and pose covariance; the twist is not read).
struct CdrPose {
    CdrHeader header;
    std::string child_frame_id;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    double covariance[36] = {};
};

/// Each throws DecodeError when the bytes end early or hold an invalid value.
[[nodiscard]] CdrPointCloud2 DecodePointCloud2Cdr(const std::vector<uint8_t> &bytes);
[[nodiscard]] CdrImu DecodeImuCdr(const std::vector<uint8_t> &bytes);
[[nodiscard]] CdrPose DecodeOdometryCdr(const std::vector<uint8_t> &bytes);
[[nodiscard]] CdrPose DecodePoseStampedCdr(const std::vector<uint8_t> &bytes);
/// rosgraph_msgs/msg/Clock: its time [ns].
[[nodiscard]] int64_t DecodeClockCdr(const std::vector<uint8_t> &bytes);

}  // namespace dorado::io
