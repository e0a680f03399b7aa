#pragma once
/// @file node_fields.hpp
/// dorado_ros's own parameters as a field list (`VisitFields`, core/config_fields.hpp), without
/// ROS: node_settings.cpp reads them through it, after the files they override (`config`,
/// `odometry_config`, `mapper_config`). Read by hand there: those three files, the mount
/// (`sensor_pose`, `calib_rot`, `sensor_to_icr_x`), `threshold_mode` / `threshold_value`
/// (paper_estimator.hpp) and `initial_pose` (16 numbers).

#include "dorado/core/config_fields.hpp"
#include "dorado/mapping/mapper_fields.hpp"
#include "dorado/odometry/odometry_fields.hpp"
#include "node_settings.hpp"

namespace dorado::ros_node {

template <typename Visitor>
void VisitFields(NodeSettings &s, Visitor &&v) {
    v("input_topic", s.input_topic, "radar PointCloud2; default: the YAML's rosbag.radar_topic");
    v("imu_topic", s.imu_topic, "sensor_msgs/Imu; default: the YAML's rosbag.imu_topic");
    v("tf_from_frame", s.tf_from_frame, "REP 105's odom frame");
    v("map_frame", s.map_frame, "REP 105's map frame (differs from the other two)");
    v("tf_to_frame", s.tf_to_frame, "the moving frame");
    v("publish_tf", s.publish_tf, "TF on/off");
    v("verbose", s.verbose, "one line per scan");
    v("queue_size", s.queue_size, "scans waiting; an older one overtaken beyond it is dropped");
    v("max_gap_s", s.gaps.max_gap_s, "a longer gap starts over at the last pose [s] (> 0)");
    v("imu_wait_s", s.imu_wait_s, "how long a scan waits for the IMU [s]");
    v("local_map_period_s", s.local_map_period_s, "local map at most this often [s] (>= 1)");
    v("report_period_s", s.report_period_s, "summarised warnings this often [s]");
    v("summary_file", s.summary_file, "JSON counts and latencies at exit; empty: none");
    v("mapper", s.front_end.run_mapper, "the mapper on");
    v("prior", s.front_end.prior, mapping::PriorKindChoices(), "its prior (dorado map --prior)");
    v("method", s.front_end.odometry.method, odometry::OdometryMethodChoices(),
      "dorado odometry --method; default: odometry_config's");
    v("use_mask", s.front_end.use_mask, "register only the points labelled static");
    v("min_points", s.front_end.odometry.ego_velocity.min_points, "ego_velocity.min_points");
    v("use_power", s.front_end.odometry.ego_velocity.use_power, "ego_velocity.use_power");
}

}  // namespace dorado::ros_node
