#pragma once
/// @file measurements.hpp
/// The measurements the mapper's refinement and the window smoother share: scan-to-map
/// correspondences, static points' Doppler and the robust kernel both put on them.

#include <Eigen/Core>

namespace dorado::mapping {

/// One scan-to-map correspondence: p_base should lie at q_world; sqrt_information whitens the
/// 3-vector error R_world_base p_base + t_world_base - q_world (the point-to-distribution error).
struct Correspondence {
    Eigen::Vector3d p_base;
    Eigen::Vector3d q_world;
    Eigen::Matrix3d sqrt_information;
};

/// One static point's Doppler measurement.
struct DopplerObservation {
    Eigen::Vector3d d_radar;  ///< unit direction to the point, radar frame
    double doppler_mps;       ///< measured radial velocity, positive = receding
};

/// The road under the vehicle seen in one scan (the odometry's ground-plane fit): the plane's unit
/// up-vector in the base frame and the covariance of its x and y components, which must already
/// hold the road's own slope about level (the ground is the road, not gravity). The refinement
/// then holds the pose's roll and pitch to it: R_world_base^T e_z should equal up_base.
struct GroundUp {
    Eigen::Vector3d up_base = Eigen::Vector3d::UnitZ();
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  ///< of up_base.x(), .y()
    /// Refused when the innovation's squared Mahalanobis distance (against covariance plus the
    /// prior's roll/pitch) exceeds this (an uneven road the plane fit's gates let through);
    /// 0 = no gate.
    double max_innovation_chi2 = 9.21;
};

/// The interval assumed before the first scan, when no earlier stamp gives one [s] (a 10 Hz
/// radar): the first prior's and the first window state's time step.
inline constexpr double kFirstScanIntervalS = 0.1;

/// Robust loss of the registration and Doppler residuals (in whitened units).
enum class RobustKernel { kNone, kHuber, kCauchy, kTukey };

}  // namespace dorado::mapping
