#pragma once
/// @file node_settings.hpp
/// The live nodes' parameters (dorado_ros, dorado_ros2): the paper node's
/// (andresgalu/doppler_odometry, same names and meanings) mapped onto dorado's dataset and
/// front-end configuration, and dorado's own.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/dataset_config.hpp"
#include "dorado/loops/loop_closer.hpp"
#include "live_input.hpp"
#include "param_source.hpp"

namespace dorado::ros_node {

struct NodeSettings {
    io::DatasetConfig dataset;           ///< field map, extrinsics, vehicle (the `config` YAML)
    frontend::FrontEndConfig front_end;  ///< odometry_config + mapper_config + the paper's keys
    /// mapper_config's loop_closure section: with the mapper, map -> odom carries its correction.
    loops::LoopClosureConfig loop_closure;
    std::string input_topic;  ///< PointCloud2
    std::string imu_topic;    ///< sensor_msgs/Imu, subscribed when the prior needs it
    bool needs_imu = false;
    std::string tf_from_frame = "odom";  ///< REP 105's odom frame: /doppler_odom's
    std::string map_frame = "map";       ///< REP 105's map frame: /dorado/map_odom's, map -> odom
    std::string tf_to_frame = "base_link";
    bool publish_tf = true;
    /// The pose of tf_to_frame at the first scan (the paper's initial_pose).
    Eigen::Isometry3d T_world_child_initial = Eigen::Isometry3d::Identity();
    /// tf_to_frame in dorado's base frame (the paper's base_link is not on the ICR axis).
    Eigen::Isometry3d T_base_child = Eigen::Isometry3d::Identity();
    bool verbose = false;
    int queue_size = 2;  ///< scans waiting; a scan overtaken beyond it is dropped (late)
    GapPolicy gaps;
    double imu_wait_s = 0.05;         ///< how long a scan waits for the IMU to catch up
    double local_map_period_s = 1.0;  ///< /dorado/local_map at most this often (>= 1 s)
    double report_period_s = 5.0;     ///< summarised warnings at most this often
    std::string summary_file;         ///< JSON counts and latencies written at exit (optional)
    std::string description;          ///< what was read from where, for the start-up message
};

/// Reads every parameter from @p source (ROS1: private `~name` first, then `name` in the node's
/// namespace, as the paper's launch file sets them; ROS 2: the node's `ros__parameters`). Throws
/// io::ConfigError (a bad YAML, a parameter of the wrong size or type) naming the parameter.
[[nodiscard]] NodeSettings ReadNodeSettings(const ParamSource &source);

/// The name of every parameter ReadNodeSettings reads (for an unknown name's "did you mean").
[[nodiscard]] std::vector<std::string> ParameterNames();

}  // namespace dorado::ros_node
