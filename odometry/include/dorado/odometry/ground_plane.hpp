#pragma once
/// @file ground_plane.hpp
/// The road under the vehicle from one radar scan: a robust plane fit to the static returns near
/// the expected ground, giving the base's roll and pitch relative to the local road plane, with
/// their covariance. No drift (one scan), but relative to the ROAD, not to gravity: on a slope the
/// road is not level (see docs/attitude.md for where that misleads).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace dorado::odometry {

/// Which points count as ground and when a fit is accepted.
struct GroundPlaneConfig {
    /// Height of the base origin (rear-axle centre) above the road [m]: the expected ground is the
    /// plane z_base = -base_height_m. Not a setting: DopplerOdometry copies the vehicle's
    /// (VehicleGeometry::base_height_m, the dataset's vehicle.base_height_m); NaN = unknown.
    double base_height_m = std::numeric_limits<double>::quiet_NaN();
    /// Ground candidates lie within this of the expected plane, widened by
    /// horizontal distance * tan(max_tilt_deg) [m].
    double height_window_m = 0.4;
    /// Largest angle between the fitted plane's normal and the base Z axis [deg].
    double max_tilt_deg = 12.0;
    /// Horizontal distance from the base origin of the points used [m]: the LOCAL road.
    double min_distance_m = 1.0;
    double max_distance_m = 15.0;
    /// RANSAC inlier distance to the plane [m] (the final fit reweights by each point's own
    /// vertical noise, see elevation_sigma_deg).
    double inlier_threshold_m = 0.15;
    int ransac_iterations = 60;
    int min_points = 30;  ///< plane inliers needed for an observation
    /// The inliers' horizontal distances must spread over this much (5th to 95th percentile) [m]:
    /// a band at one distance does not fix the pitch.
    double min_depth_spread_m = 3.0;
    /// Uneven ground (a ridge, a kerb, a ramp in the window): the refit's residual RMS, scaled
    /// to a point with the floor noise (GroundObservation::residual_sigma_m), above this [m]
    /// gives no observation: one plane does not describe the road under the vehicle.
    double max_residual_sigma_m = 0.5;
    /// Elevation noise of the radar [deg] (from the dataset's radar section when > 0): a point at
    /// range r has vertical noise ~ r * sigma; the refit weights it accordingly.
    double elevation_sigma_deg = 1.0;
    uint64_t seed = 7;  ///< RANSAC reseeded per fit: reproducible

    /// Throws std::invalid_argument naming the first bad field ("ground.<key>: ...").
    void Validate() const;
};

/// Why a scan gave no ground observation.
enum class GroundFallback : uint8_t {
    kNone = 0,        ///< an observation was made
    kFewCandidates,   ///< fewer than min_points static points in the ground window
    kNoPlane,         ///< RANSAC found no plane with min_points inliers within max_tilt_deg
    kTilted,          ///< the refit plane is tilted beyond max_tilt_deg
    kHeightMismatch,  ///< the refit plane is further than height_window_m from the expected one
    kDegenerate,      ///< the inliers span no area, or too short a range of distances
    kNoVelocity,      ///< the scan had no valid ego-velocity, so no static-point mask
    kUneven,          ///< the residuals spread beyond max_residual_sigma_m: not one plane
    kInconsistent,    ///< the filter refused it: innovation beyond max_innovation_chi2
    kNoBaseHeight,    ///< the vehicle's base height is unknown (vehicle.base_height_m absent)
};

/// "" | "few_ground_points" | "no_plane" | "tilted" | "height_mismatch" | "degenerate" |
/// "no_velocity" | "uneven" | "inconsistent" | "no_base_height".
[[nodiscard]] const char *ToString(GroundFallback reason);

struct GroundObservation {
    bool valid = false;
    GroundFallback fallback = GroundFallback::kNone;
    /// The plane in the base frame: z = height_m + slope.x() x + slope.y() y.
    double height_m = 0.0;
    Eigen::Vector2d slope = Eigen::Vector2d::Zero();
    /// Roll and pitch of the base relative to the plane (ZYX convention of RollPitchYaw: a plane
    /// rising ahead means the nose points down, positive pitch) [rad].
    Eigen::Vector2d roll_pitch_rad = Eigen::Vector2d::Zero();
    Eigen::Matrix2d cov_roll_pitch = Eigen::Matrix2d::Zero();  ///< [rad^2]
    double residual_sigma_m = 0.0;  ///< RMS residual scaled to a point with the floor noise [m]
    int candidates = 0;             ///< points in the ground window
    int inliers = 0;
};

/// Fits the ground plane to `points_base` (3 x N, base frame) whose `use` flag is set (the static
/// Doppler inliers). Never throws on bad data: an unusable scan comes back with valid = false and
/// the fallback reason.
[[nodiscard]] GroundObservation FitGroundPlane(const GroundPlaneConfig &config,
                                               const Eigen::Matrix3Xd &points_base,
                                               const std::vector<bool> &use);

/// The base's roll and pitch relative to a plane z = h + a x + b y in the base frame, and the
/// Jacobian d[roll, pitch] / d[a, b]. With R_plane_base = Ry(pitch) Rx(roll) the plane's normal in
/// the base frame is (-sin p, sin r cos p, cos r cos p) ~ (-a, -b, 1).
[[nodiscard]] Eigen::Vector2d RollPitchFromSlope(const Eigen::Vector2d &slope,
                                                 Eigen::Matrix2d *jacobian = nullptr);

}  // namespace dorado::odometry
