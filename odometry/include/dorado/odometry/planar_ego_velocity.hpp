#pragma once
/// @file planar_ego_velocity.hpp
/// The radar's velocity in its own x-y plane from one scan of a 2D radar (no elevation: every
/// z = 0): eq. (1) with d_i = (x_i, y_i) / r_i, eq. (2) as a 2x2 power-weighted least squares
/// inside a 2-point RANSAC, eq. (6)'s covariance in 2-D, and the same static/dynamic mask.

#include "dorado/core/radar_scan.hpp"
#include "dorado/odometry/ego_velocity.hpp"

namespace dorado::odometry {

/// True when the scan has at least 3 points and every z is exactly 0 (a 2D radar's scan).
[[nodiscard]] bool IsPlanarScan(const RadarScan &scan_radar);

/// Estimates (v_x, v_y) of the radar from a 2D scan: for a static point, -doppler_i = d_i . v.
/// Reads the same EgoVelocityConfig as the 3-D estimator (pre-filters but elevation, weights,
/// gate, RANSAC budget, covariance model, validity); RobustMethod::kNone fits every point,
/// every other method is the 2-point RANSAC. The result's v_radar_mps.z() and the z row and
/// column of cov_v_radar are 0; condition_number is that of the 2x2 A^T W A.
class PlanarEgoVelocityEstimator {
  public:
    /// Validates the config (std::invalid_argument naming the field).
    explicit PlanarEgoVelocityEstimator(EgoVelocityConfig config);

    /// Never throws on bad data: an unusable scan comes back with its failure cause.
    [[nodiscard]] EgoVelocityResult Estimate(const RadarScan &scan_radar) const;

    [[nodiscard]] const EgoVelocityConfig &config() const { return config_; }

  private:
    EgoVelocityConfig config_;
};

}  // namespace dorado::odometry
