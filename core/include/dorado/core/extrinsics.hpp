#pragma once
/// @file extrinsics.hpp
/// Where the sensors sit on the vehicle, and the vehicle's geometry.
///
/// The base frame is the paper's (section III-B): origin at the centre of the rear axle (on the
/// Z-ICR axis), X forward towards the front axle, Y left along the rear axle, Z up.

#include <Eigen/Geometry>

namespace dorado {

struct Extrinsics {
    Eigen::Isometry3d T_base_radar =
        Eigen::Isometry3d::Identity();  ///< x_base = T_base_radar x_radar
    Eigen::Isometry3d T_base_imu = Eigen::Isometry3d::Identity();  ///< x_base = T_base_imu x_imu
};

struct VehicleGeometry {
    /// Half the distance between the two axles [m] (the paper's m): the Y-ICR axis is at x = m.
    double half_wheelbase_m = 0.256;
};

}  // namespace dorado
