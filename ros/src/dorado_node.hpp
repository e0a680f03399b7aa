#pragma once
/// @file dorado_node.hpp
/// dorado_ros: a thin live driver of frontend::RadarFrontEnd. Scans are queued as they arrive
/// and processed in order by one worker thread; what cannot be used (a stamp not after the last
/// one, a scan overtaken while the worker was busy, an undecodable message) is dropped, counted
/// and reported in summarised warnings.

#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/transform_broadcaster.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

#include "dorado/core/time.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "live_input.hpp"
#include "loop_worker.hpp"
#include "node_settings.hpp"
#include "pose_covariance.hpp"

namespace dorado::ros_node {

/// The mapper's pose covariance (right perturbation [rho; phi] of T_map_base in the base frame)
/// as nav_msgs/Odometry's pose covariance of T_map_base * T_base_child: position and rotation
/// errors about the map frame's axes. node_publish.cpp.
[[nodiscard]] Matrix6d MapPoseCovariance(const Eigen::Isometry3d &T_map_base,
                                         const Eigen::Isometry3d &T_base_child,
                                         const Matrix6d &C_base);

class DoradoNode {
  public:
    DoradoNode(ros::NodeHandle &node, NodeSettings settings);
    ~DoradoNode();

    /// Stops the worker (the scans still waiting are dropped and counted), logs the totals and
    /// writes summary_file.
    void Shutdown();

  private:
    struct Pending {
        sensor_msgs::PointCloud2ConstPtr msg;
        Clock::time_point arrival;
    };

    void OnCloud(const sensor_msgs::PointCloud2ConstPtr &msg);
    void OnImu(const sensor_msgs::ImuConstPtr &msg);
    void Work();
    void Handle(const Pending &pending);
    bool Decode(const sensor_msgs::PointCloud2 &msg, RadarScan &scan);
    bool FeedImu(int64_t stamp_ns);
    void WatchImu(bool imu_current, int64_t stamp_ns);
    /// The mapper's written poses (smoothed, about mapper.smoother.lag_s old) on
    /// /dorado/smoothed_odom, each at its own scan's stamp.
    void PublishWritten(const std::vector<mapping::WrittenPose> &written);
    void Publish(const std_msgs::Header &header, const RadarScan &scan,
                 const frontend::FrontEndResult &result);
    void ReportPrior(const frontend::FrontEndResult &result);
    void Drop(const std::string &cause, const std::string &detail);
    void ReportPeriodically();
    void WriteSummary() const;

    NodeSettings settings_;
    frontend::RadarFrontEnd front_end_;
    StampGuard stamps_;
    FaultLog faults_;    ///< dropped scans, by cause
    FaultLog warnings_;  ///< scans used despite a fault (a gap, a prior substitution)
    LatencyStats latency_;
    PoseCovariance pose_covariance_;
    Eigen::Isometry3d T_world_base_initial_;

    ros::Subscriber cloud_sub_, imu_sub_;
    ros::Publisher odom_pub_, map_odom_pub_, smoothed_odom_pub_, static_pub_, dynamic_pub_,
        local_map_pub_;
    tf2_ros::TransformBroadcaster tf_broadcaster_;

    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<Pending> queue_;
    std::deque<ImuSample> imu_;
    int64_t last_imu_stamp_ns_ = 0;
    bool stop_ = false;
    long long received_ = 0, processed_ = 0, published_ = 0, resets_ = 0;
    long long late_drops_ = 0, late_drops_seen_ = 0;  ///< a gap the node made is not a stall
    bool imu_stalled_ = false;                        ///< worker only
    Clock::time_point last_report_, last_local_map_;
    std::thread worker_;
    /// Loop closure on the written poses, in a thread of its own (mapper and loop_closure.enabled).
    std::unique_ptr<LoopWorker> loops_;
};

}  // namespace dorado::ros_node
