#include "dorado_node.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>

#include "ros_messages.hpp"

namespace dorado::ros_node {
namespace {

std_msgs::Header HeaderOf(int64_t stamp_ns, const std::string &frame_id) {
    std_msgs::Header header;
    header.stamp.fromNSec(static_cast<uint64_t>(stamp_ns));
    header.frame_id = frame_id;
    return header;
}

}  // namespace

DoradoNode::DoradoNode(ros::NodeHandle &node, NodeSettings settings) {
    odom_pub_ = node.advertise<nav_msgs::Odometry>("/doppler_odom", 100);
    if (settings.front_end.run_mapper) {
        map_odom_pub_ = node.advertise<nav_msgs::Odometry>("/dorado/map_odom", 100);
        smoothed_odom_pub_ = node.advertise<nav_msgs::Odometry>("/dorado/smoothed_odom", 100);
        static_pub_ = node.advertise<sensor_msgs::PointCloud2>("/dorado/static_points", 5);
        dynamic_pub_ = node.advertise<sensor_msgs::PointCloud2>("/dorado/dynamic_points", 5);
        local_map_pub_ = node.advertise<sensor_msgs::PointCloud2>("/dorado/local_map", 1, true);
    }
    pipeline_ = std::make_unique<LivePipeline>(std::move(settings), *this, "dorado_ros");
    const NodeSettings &s = pipeline_->settings();
    // The ROS queue is long and the callback cheap: the node, not roscpp, decides what is dropped.
    cloud_sub_ = node.subscribe(s.input_topic, 100, &DoradoNode::OnCloud, this,
                                ros::TransportHints().tcpNoDelay());
    if (s.needs_imu)
        imu_sub_ = node.subscribe(s.imu_topic, 1000, &DoradoNode::OnImu, this,
                                  ros::TransportHints().tcpNoDelay());
    ROS_INFO("dorado_ros: %s; radar %s -> /doppler_odom and TF %s -> %s%s%s", s.description.c_str(),
             s.input_topic.c_str(), s.tf_from_frame.c_str(), s.tf_to_frame.c_str(),
             pipeline_->MapperDescription().c_str(),
             s.needs_imu ? ("; IMU " + s.imu_topic).c_str() : "");
}

DoradoNode::~DoradoNode() {
    Shutdown();
}

void DoradoNode::OnCloud(const sensor_msgs::PointCloud2ConstPtr &msg) {
    LiveCloud cloud;
    cloud.arrival = Clock::now();
    cloud.stamp_ns = static_cast<int64_t>(msg->header.stamp.toNSec());
    cloud.frame_id = msg->header.frame_id;
    cloud.view = io::ViewOf(*msg);
    cloud.owner = std::shared_ptr<const void>(
        msg.get(), [msg](const void *) {});  // roscpp's boost::shared_ptr
    pipeline_->OnCloud(std::move(cloud));
}

void DoradoNode::OnImu(const sensor_msgs::ImuConstPtr &msg) {
    ImuSample sample;
    sample.stamp_ns = static_cast<int64_t>(msg->header.stamp.toNSec());
    sample.omega_imu_radps << msg->angular_velocity.x, msg->angular_velocity.y,
        msg->angular_velocity.z;
    sample.accel_imu_mps2 << msg->linear_acceleration.x, msg->linear_acceleration.y,
        msg->linear_acceleration.z;
    pipeline_->OnImu(sample);
}

void DoradoNode::Shutdown() {
    if (!pipeline_) return;
    // roscpp is down by now (main calls this after ros::waitForShutdown): nothing more to publish.
    pipeline_->Shutdown(false);
    cloud_sub_.shutdown();
    imu_sub_.shutdown();
}

ros::Publisher &DoradoNode::PublisherOf(OdometryTopic topic) {
    switch (topic) {
        case OdometryTopic::kMapOdom:
            return map_odom_pub_;
        case OdometryTopic::kSmoothedOdom:
            return smoothed_odom_pub_;
        case OdometryTopic::kDopplerOdom:
            break;
    }
    return odom_pub_;
}

const ros::Publisher &DoradoNode::PublisherOf(CloudTopic topic) const {
    switch (topic) {
        case CloudTopic::kStaticPoints:
            return static_pub_;
        case CloudTopic::kDynamicPoints:
            return dynamic_pub_;
        case CloudTopic::kLocalMap:
            break;
    }
    return local_map_pub_;
}

void DoradoNode::Publish(OdometryTopic topic, const OdometryOutput &odometry) {
    nav_msgs::Odometry msg;
    msg.header = HeaderOf(odometry.stamp_ns, odometry.frame_id);
    msg.child_frame_id = odometry.child_frame_id;
    FillOdometry(odometry.T_frame_child, odometry.pose_covariance, odometry.twist_child, msg);
    PublisherOf(topic).publish(msg);
}

void DoradoNode::Publish(const TransformOutput &transform) {
    geometry_msgs::TransformStamped tf;
    tf.header = HeaderOf(transform.stamp_ns, transform.parent_frame);
    tf.child_frame_id = transform.child_frame;
    const Eigen::Isometry3d &T = transform.T_parent_child;
    const Eigen::Quaterniond q(T.linear());
    tf.transform.translation.x = T.translation().x();
    tf.transform.translation.y = T.translation().y();
    tf.transform.translation.z = T.translation().z();
    tf.transform.rotation.x = q.x();
    tf.transform.rotation.y = q.y();
    tf.transform.rotation.z = q.z();
    tf.transform.rotation.w = q.w();
    tf_broadcaster_.sendTransform(tf);
}

bool DoradoNode::HasSubscribers(CloudTopic topic) const {
    return PublisherOf(topic).getNumSubscribers() > 0;
}

void DoradoNode::Publish(CloudTopic topic, const CloudOutput &cloud) {
    PublisherOf(topic).publish(MakeCloud(HeaderOf(cloud.stamp_ns, cloud.frame_id), cloud));
}

void DoradoNode::Log(LogLevel level, const std::string &text) {
    switch (level) {
        case LogLevel::kInfo:
            ROS_INFO("%s", text.c_str());
            break;
        case LogLevel::kWarn:
            ROS_WARN("%s", text.c_str());
            break;
        case LogLevel::kError:
            ROS_ERROR("%s", text.c_str());
            break;
    }
}

int64_t DoradoNode::NowNs() const {
    return static_cast<int64_t>(ros::Time::now().toNSec());
}

}  // namespace dorado::ros_node
