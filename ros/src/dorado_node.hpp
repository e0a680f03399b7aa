#pragma once
/// @file dorado_node.hpp
/// dorado_ros: the roscpp edge of a LivePipeline (ros/common/live_pipeline.hpp): subscribes the
/// radar (and the IMU when the prior needs it), hands each message to the pipeline, and publishes
/// its outputs as nav_msgs/Odometry, TF and PointCloud2.

#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>

#include "live_pipeline.hpp"
#include "live_sink.hpp"
#include "node_settings.hpp"

namespace dorado::ros_node {

class DoradoNode : public LiveSink {
  public:
    DoradoNode(ros::NodeHandle &node, NodeSettings settings);
    ~DoradoNode() override;

    /// Stops the pipeline (the scans still waiting are dropped and counted), logs the totals and
    /// writes summary_file.
    void Shutdown();

    void Publish(OdometryTopic topic, const OdometryOutput &odometry) override;
    void Publish(const TransformOutput &transform) override;
    [[nodiscard]] bool HasSubscribers(CloudTopic topic) const override;
    void Publish(CloudTopic topic, const CloudOutput &cloud) override;
    void Log(LogLevel level, const std::string &text) override;
    [[nodiscard]] int64_t NowNs() const override;

  private:
    void OnCloud(const sensor_msgs::PointCloud2ConstPtr &msg);
    void OnImu(const sensor_msgs::ImuConstPtr &msg);
    ros::Publisher &PublisherOf(OdometryTopic topic);
    const ros::Publisher &PublisherOf(CloudTopic topic) const;

    ros::Publisher odom_pub_, map_odom_pub_, smoothed_odom_pub_, static_pub_, dynamic_pub_,
        local_map_pub_;
    tf2_ros::TransformBroadcaster tf_broadcaster_;
    std::unique_ptr<LivePipeline> pipeline_;  // after the publishers: its worker uses them
    ros::Subscriber cloud_sub_, imu_sub_;
};

}  // namespace dorado::ros_node
