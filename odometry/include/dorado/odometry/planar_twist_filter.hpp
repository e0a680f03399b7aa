#pragma once
/// @file planar_twist_filter.hpp
/// The vehicle's planar twist (v_x, v_y, yaw rate) from several 2D radars that fire at different
/// times: a Kalman filter whose state is the base twist, predicted between scans by a random walk
/// (the accelerations) and updated by each radar's own ego-velocity at that radar's own time.
///
/// A radar k at s_k in the base frame, turned by R_k, measures its own planar velocity
///   v_k = R_k^T [1 0 -s_ky; 0 1 s_kx] (v_x, v_y, omega_z)            (2 of the 3 unknowns),
/// so one radar alone cannot tell the yaw rate from the lateral velocity; radars at different
/// places, one after the other, can (Kellner et al. ICRA 2014 fit them jointly at one instant;
/// here each scan counts at its own stamp, none is paired with another's). A ground vehicle's
/// rear axle has no lateral velocity: with the vehicle's velocity prior on, every update also
/// takes v_y = 0 with that spread, which makes even one radar observe the yaw rate (the Ackermann
/// model in the plane).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>

#include "dorado/core/extrinsics.hpp"
#include "dorado/odometry/ego_velocity.hpp"

namespace dorado::odometry {

struct PlanarTwistFilterConfig {
    /// Random-walk spreads of the twist [per sqrt(s)]: how fast the vehicle may change its
    /// velocity (m/s per sqrt s) and its yaw rate (rad/s per sqrt s).
    double velocity_walk_mps = 2.0;
    double yaw_rate_walk_radps = 0.5;
    /// Floor of a radar's velocity spread [m/s], added to its ego-velocity covariance (eq. 6
    /// from one scan's residuals claims too little on real radars; the mount's error adds).
    double min_radar_sigma_mps = 0.05;
    /// An update whose normalised innovation (chi^2, 2 dof) exceeds this is not taken (a RANSAC
    /// that locked onto a moving crowd); 0 = take every update. 13.8 = 99.9 %.
    double gate_chi2 = 13.8;
    /// After this many gated updates in a row the filter restarts from the next radar's scan (it
    /// lost the vehicle, not the radars the vehicle).
    int max_gated_in_a_row = 10;

    /// Throws std::invalid_argument naming the first bad field.
    void Validate() const;
};

/// What one radar's scan did to the filter.
enum class TwistUpdate {
    kTaken,       ///< the radar's velocity updated the twist
    kInvalid,     ///< the radar's ego-velocity was not valid: prediction only
    kGated,       ///< innovation beyond gate_chi2: prediction only
    kRestarted,   ///< too many gated in a row: the filter restarted at this scan
    kOutOfOrder,  ///< a stamp before the filter's: ignored
};
[[nodiscard]] const char *ToString(TwistUpdate update);

class PlanarTwistFilter {
  public:
    /// Throws std::invalid_argument on a bad config.
    PlanarTwistFilter(PlanarTwistFilterConfig config, VehicleVelocityPrior velocity_prior);

    /// Predicts to @p stamp_ns and updates with radar @p T_base_radar's ego-velocity there.
    TwistUpdate Update(int64_t stamp_ns, const Eigen::Isometry3d &T_base_radar,
                       const EgoVelocityResult &ego);

    /// (v_x, v_y, omega_z) of the base origin in the base frame, and its covariance.
    [[nodiscard]] const Eigen::Vector3d &twist() const { return x_; }
    [[nodiscard]] const Eigen::Matrix3d &covariance() const { return P_; }
    /// The stamp of the newest update; empty before the first.
    [[nodiscard]] std::optional<int64_t> stamp_ns() const { return stamp_ns_; }
    /// The chi^2 of the newest update's innovation (2 dof).
    [[nodiscard]] double last_nis() const { return last_nis_; }

  private:
    void Restart();

    PlanarTwistFilterConfig config_;
    VehicleVelocityPrior velocity_prior_;
    Eigen::Vector3d x_ = Eigen::Vector3d::Zero();
    Eigen::Matrix3d P_;
    std::optional<int64_t> stamp_ns_;
    int gated_in_a_row_ = 0;
    double last_nis_ = 0.0;
};

}  // namespace dorado::odometry
