#pragma once
/// @file ros_messages.hpp
/// Between ROS messages and dorado's types: a PointCloud2's bytes as dorado_io's decoder reads
/// them (the bag reader's decoder, not a second one), point clouds and odometry to publish.

#include <nav_msgs/Odometry.h>
#include <sensor_msgs/PointCloud2.h>
#include <Eigen/Geometry>

#include "dorado/core/lie.hpp"
#include "dorado/core/radar_scan.hpp"
#include "dorado/core/twist.hpp"
#include "dorado/io/pointcloud_decoder.hpp"
#include "dorado/io/ros1_cloud_view.hpp"
#include "live_sink.hpp"

namespace dorado::ros_node {

/// A PointCloud2 of the given points (float32 x, y, z, and doppler, power when given).
[[nodiscard]] sensor_msgs::PointCloud2 MakeCloud(const std_msgs::Header &header,
                                                 const CloudOutput &points);

/// Fills pose (and its covariance, row-major 6x6) and twist (with covariance) of an Odometry.
void FillOdometry(const Eigen::Isometry3d &T_world_child, const Matrix6d &pose_covariance,
                  const Twist &twist_child, nav_msgs::Odometry &msg);

}  // namespace dorado::ros_node
