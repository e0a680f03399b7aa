#pragma once
// Private to dorado_io: the ROS2 messages dorado reads, from their CDR serialization (the
// rosbag2 "cdr" format: a 4-byte encapsulation header, then XCDR1 with alignment).

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
};

/// sensor_msgs/msg/Imu (orientation and covariances are not used).
struct CdrImu {
    CdrHeader header;
    Eigen::Vector3d omega_radps = Eigen::Vector3d::Zero();
    Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();
};

/// The pose of nav_msgs/msg/Odometry or geometry_msgs/msg/PoseStamped.
struct CdrPose {
    CdrHeader header;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// Each throws DecodeError when the bytes end early or hold an invalid value.
[[nodiscard]] CdrPointCloud2 DecodePointCloud2Cdr(const std::vector<uint8_t> &bytes);
[[nodiscard]] CdrImu DecodeImuCdr(const std::vector<uint8_t> &bytes);
[[nodiscard]] CdrPose DecodeOdometryCdr(const std::vector<uint8_t> &bytes);
[[nodiscard]] CdrPose DecodePoseStampedCdr(const std::vector<uint8_t> &bytes);

}  // namespace dorado::io
