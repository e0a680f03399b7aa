#pragma once
/// @file paper_mount.hpp
/// The radar mount from the parameters of the paper's ROS node (andresgalu/doppler_odometry,
/// launch/launch.xml): `sensor_pose`, `calib_rot` and `sensor_to_icr_x`.
///
/// How the paper's node uses them (src/odom.cpp, read, not copied):
///  - the sensor velocity goes to its base_link as v_s = R(calib_rot) R(sensor_rot) v_radar, so
///    R_base_radar = R(calib_rot) R(sensor_rot) (the calibration is applied after the mount);
///  - omega_z = -v_sy / sensor_to_icr_x and omega_y = v_sz / sensor_to_icr_x: one lever arm for
///    both rates. sensor_to_icr_x is the ICR's X minus the sensor's X, so the sensor is
///    s_x = -sensor_to_icr_x ahead of the Z-ICR axis, and the Y-ICR axis is the same line (the
///    Husky is skid-steer: both ICR axes are at mid-vehicle). In dorado's model (omega_z = v_sy /
///    s_x, omega_y = v_sz / (m - s_x)) that is m = 0;
///  - its base velocity is v_s - omega x sensor_pos, with sensor_pos in its base_link, whose
///    origin is not on the ICR axis: base_link sits (sensor_pos.x + sensor_to_icr_x) ahead of it.
/// dorado's base frame has its origin on the Z-ICR axis, axes as base_link's: the radar sits at
/// (s_x, sensor_pos.y, sensor_pos.z) and base_link at (sensor_pos.x - s_x, 0, 0).

#include <Eigen/Geometry>

#include "dorado/core/extrinsics.hpp"

namespace dorado {

/// The paper node's mount parameters; the defaults are its launch file's (the Hugin on a Husky).
struct PaperMountParameters {
    /// sensor_pose x y z: the radar in the paper's base_link [m].
    Eigen::Vector3d sensor_position_m{0.85, 0.22, 0.17};
    /// sensor_pose qx qy qz qw: R_baselink_radar before the calibration.
    Eigen::Quaterniond sensor_rotation{0.011519528015294512, 0.6857716483037417, 0.7276229492792916,
                                       0.012222542255175764};  // w, x, y, z
    /// calib_rot qx qy qz qw: the calibrated correction, applied after sensor_rotation.
    Eigen::Quaterniond calib_rotation{0.99978789, -0.00295514, -0.01095426, 0.01718881};
    /// sensor_to_icr_x: the ICR's X minus the radar's X [m] (negative: the ICR is behind).
    double sensor_to_icr_x_m = -0.9944683540059478;
};

/// dorado's mount for those parameters.
struct PaperMount {
    Extrinsics extrinsics;          ///< T_base_radar (T_base_imu identity: the node has no IMU)
    double half_wheelbase_m = 0.0;  ///< m = 0: the Y-ICR axis is the Z-ICR axis
    /// The base origin (the paper's base_link height) above the road [m]: husky_description's
    /// base_footprint offset, wheel radius 0.1651 - wheel vertical offset 0.0328.
    double base_height_m = 0.132;
    /// The paper's base_link in dorado's base frame (a pure X shift): the node publishes
    /// T_world_base * T_base_baselink so that its TF means what the paper's does.
    Eigen::Isometry3d T_base_baselink = Eigen::Isometry3d::Identity();
};

/// The mount from the paper node's parameters (derivation in paper_mount.hpp's header comment).
/// Quaternions are normalised.
[[nodiscard]] PaperMount MountFromPaperParameters(const PaperMountParameters &parameters);

}  // namespace dorado
