#pragma once
/// @file output_frames.hpp
/// The live nodes' outputs in the frames ROS expects (nav_msgs/Odometry), without ROS.

#include <Eigen/Geometry>

#include "dorado/core/lie.hpp"
#include "dorado/core/twist.hpp"

namespace dorado::ros_node {

/// The mapper's pose covariance (right perturbation [rho; phi] of T_map_base in the base frame)
/// as nav_msgs/Odometry's pose covariance of T_map_base * T_base_child: position and rotation
/// errors about the map frame's axes.
[[nodiscard]] Matrix6d MapPoseCovariance(const Eigen::Isometry3d &T_map_base,
                                         const Eigen::Isometry3d &T_base_child,
                                         const Matrix6d &C_base);

/// The twist of a frame at T_base_child (no rotation: base_link shares the base's axes, else
/// rotated too), from the base twist: v_child = R^T (v + omega x p), omega_child = R^T omega,
/// with the covariance carried through the same linear map. The result is the child frame's own
/// twist: in it, `base` is the child frame.
[[nodiscard]] Twist TwistAt(const Twist &twist_base, const Eigen::Isometry3d &T_base_child);

}  // namespace dorado::ros_node
