#pragma once
/// @file ros2_node.hpp
/// dorado_ros2: the ROS 2 edge of a LivePipeline (ros/common/live_pipeline.hpp) on Cyclone DDS:
/// the radar's sensor_msgs/msg/PointCloud2 (and sensor_msgs/msg/Imu when the prior needs it)
/// read as CDR bytes and decoded by dorado_io's codec; nav_msgs/msg/Odometry, /tf, /tf_static and
/// PointCloud2 written as the idlc-generated types, with ROS 2's names and QoS.

#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include "dorado/ros2/dds.hpp"
#include "live_pipeline.hpp"
#include "live_sink.hpp"
#include "ros2_args.hpp"

namespace dorado::ros2 {

class Ros2Node : public ros_node::LiveSink {
  public:
    /// use_sim_time: the node's clock is /clock (for scans stamped 0).
    Ros2Node(const RosArgs &args, ros_node::NodeSettings settings, bool use_sim_time);
    ~Ros2Node() override;

    /// Stops reading, processes nothing more, publishes the poses still in the mapper's smoother,
    /// waits (up to 5 s) until the subscribers have every odometry message, prints the totals and
    /// writes summary_file.
    void Shutdown();

    void Publish(ros_node::OdometryTopic topic, const ros_node::OdometryOutput &odometry) override;
    void Publish(const ros_node::TransformOutput &transform) override;
    [[nodiscard]] bool HasSubscribers(ros_node::CloudTopic topic) const override;
    void Publish(ros_node::CloudTopic topic, const ros_node::CloudOutput &cloud) override;
    void Log(ros_node::LogLevel level, const std::string &text) override;
    [[nodiscard]] int64_t NowNs() const override;

  private:
    void OnCloud(std::vector<uint8_t> bytes);
    void OnImu(const std::vector<uint8_t> &bytes);
    void OnPublishers(const std::string &topic, int count, bool &lost);
    void PublishMount(const std::string &radar_frame);
    const Writer &WriterOf(ros_node::OdometryTopic topic) const;
    const Writer &WriterOf(ros_node::CloudTopic topic) const;

    std::string name_;
    bool use_sim_time_;
    Participant participant_;
    std::unique_ptr<Writer> odom_, map_odom_, smoothed_odom_, static_points_, dynamic_points_,
        local_map_, tf_, tf_static_;
    std::unique_ptr<ros_node::LivePipeline> pipeline_;  // after the writers: it writes with them
    std::unique_ptr<RawReader> cloud_reader_, imu_reader_, clock_reader_;
    std::string cloud_topic_, imu_topic_;
    bool cloud_lost_ = false, imu_lost_ = false;
    std::once_flag mount_published_;
    std::atomic<int64_t> clock_ns_{0};
    std::mutex log_mutex_;
};

}  // namespace dorado::ros2
