#pragma once
/// @file live_sink.hpp
/// What a live node publishes, as values (no ROS types): the ROS edge of each node (dorado_ros on
/// roscpp, dorado_ros2 on DDS) turns them into its messages. REP 105 frames throughout.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/core/twist.hpp"

namespace dorado::ros_node {

/// The odometry topics: /doppler_odom, /dorado/map_odom, /dorado/smoothed_odom.
enum class OdometryTopic { kDopplerOdom, kMapOdom, kSmoothedOdom };
/// The point-cloud topics: /dorado/static_points, /dorado/dynamic_points, /dorado/local_map.
enum class CloudTopic { kStaticPoints, kDynamicPoints, kLocalMap };
enum class LogLevel { kInfo, kWarn, kError };

/// The topic name of each (the ROS1 and ROS 2 names are the same).
[[nodiscard]] const char *TopicName(OdometryTopic topic);
[[nodiscard]] const char *TopicName(CloudTopic topic);

/// nav_msgs/Odometry: the pose of child_frame in frame (row-major 6x6 covariances, x y z then
/// rotation about x y z) and the child frame's own twist.
struct OdometryOutput {
    int64_t stamp_ns = 0;
    std::string frame_id, child_frame_id;
    Eigen::Isometry3d T_frame_child = Eigen::Isometry3d::Identity();
    Matrix6d pose_covariance = Matrix6d::Zero();
    Twist twist_child;  ///< zero with a zero covariance when none (the smoothed poses)
};

/// One transform of /tf.
struct TransformOutput {
    int64_t stamp_ns = 0;
    std::string parent_frame, child_frame;
    Eigen::Isometry3d T_parent_child = Eigen::Isometry3d::Identity();
};

/// A PointCloud2 of float32 x, y, z (and doppler, power when not empty).
struct CloudOutput {
    int64_t stamp_ns = 0;
    std::string frame_id;
    Eigen::Matrix3Xd points;
    Eigen::VectorXd doppler, power;
};

/// A CloudOutput as PointCloud2 bytes: one float32 field per name (offset 4 i), little-endian,
/// height 1, dense.
struct PackedCloud {
    std::vector<std::string> fields;
    uint32_t width = 0, point_step = 0;
    std::vector<uint8_t> data;
};
[[nodiscard]] PackedCloud PackCloud(const CloudOutput &cloud);

/// The ROS edge a LivePipeline publishes through. Called from the pipeline's worker thread
/// (Log also from the edge's own callbacks, through the pipeline).
class LiveSink {
  public:
    virtual ~LiveSink() = default;
    virtual void Publish(OdometryTopic topic, const OdometryOutput &odometry) = 0;
    virtual void Publish(const TransformOutput &transform) = 0;
    /// Whether anyone listens (a cloud is built only then).
    [[nodiscard]] virtual bool HasSubscribers(CloudTopic topic) const = 0;
    virtual void Publish(CloudTopic topic, const CloudOutput &cloud) = 0;
    virtual void Log(LogLevel level, const std::string &text) = 0;
    /// The node's clock (ROS time: /clock under use_sim_time) [ns], for scans stamped 0.
    [[nodiscard]] virtual int64_t NowNs() const = 0;
};

}  // namespace dorado::ros_node
