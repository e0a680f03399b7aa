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

namespace dorado::ros_node {

/// A PointCloud2 of the given points (float32 x, y, z, and doppler, power when given).
[[nodiscard]] sensor_msgs::PointCloud2 MakeCloud(const std_msgs::Header &header,
                                                 const Eigen::Matrix3Xd &points,
                                                 const Eigen::VectorXd *doppler = nullptr,
                                                 const Eigen::VectorXd *power = nullptr);

/// The points of `scan` where keep == want (the static or the dynamic part), as a PointCloud2.
[[nodiscard]] sensor_msgs::PointCloud2 MakeCloud(const std_msgs::Header &header,
                                                 const RadarScan &scan,
                                                 const Eigen::Array<bool, Eigen::Dynamic, 1> &keep,
                                                 bool want);

/// The twist of a frame at T_base_child (no rotation: base_link shares the base's axes, else
/// rotated too), from the base twist: v_child = R^T (v + omega x p), omega_child = R^T omega,
/// with the covariance carried through the same linear map. The result is the child frame's own
/// twist: in it, `base` is the child frame.
[[nodiscard]] Twist TwistAt(const Twist &twist_base, const Eigen::Isometry3d &T_base_child);

/// Fills pose (and its covariance, row-major 6x6) and twist (with covariance) of an Odometry.
void FillOdometry(const Eigen::Isometry3d &T_world_child, const Matrix6d &pose_covariance,
                  const Twist &twist_child, nav_msgs::Odometry &msg);

}  // namespace dorado::ros_node
