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
///
/// Mounts calibrated online (calibrate_mount_yaw): the state also holds each radar's yaw offset
/// delta_k from its published mount (true mount R_k R(delta_k)), so the radar measures
///   v_k = R(delta_k)^T R_k^T [1 0 -s_ky; 0 1 s_kx] (v_x, v_y, omega_z)     (an EKF, linearised
/// at the current delta_k). A radar whose yaw is off by delta sees the vehicle's velocity turned
/// by delta: against the other radars and the rear axle's zero lateral velocity that is a
/// contradiction the filter resolves into delta_k (observable once the vehicle moves; a common
/// offset of every radar only through the lateral prior, i.e. from straight driving).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/lie.hpp"
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
    /// Estimate each radar's mount yaw offset (above), starting at 0 with this spread [deg], and
    /// letting it walk this much per sqrt(hour) [deg] (0: a constant mount).
    bool calibrate_mount_yaw = true;
    double mount_yaw_sigma_deg = 1.0;
    double mount_yaw_walk_deg_per_sqrt_h = 0.0;

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
    /// T_base_radars: every radar's published mount (index = Update's radar). Throws
    /// std::invalid_argument on a bad config or no radar.
    PlanarTwistFilter(PlanarTwistFilterConfig config, VehicleVelocityPrior velocity_prior,
                      std::vector<Eigen::Isometry3d> T_base_radars);

    /// Predicts to @p stamp_ns and updates with radar @p radar's ego-velocity there. Throws
    /// std::out_of_range for a radar index beyond the mounts.
    TwistUpdate Update(int64_t stamp_ns, std::size_t radar, const EgoVelocityResult &ego);

    /// (v_x, v_y, omega_z) of the base origin in the base frame, and its covariance.
    [[nodiscard]] Eigen::Vector3d twist() const { return x_.head<3>(); }
    [[nodiscard]] Eigen::Matrix3d covariance() const { return P_.topLeftCorner<3, 3>(); }
    /// Radar @p radar's mount yaw offset from the published one [rad] and its 1-sigma (0 and 0
    /// without calibrate_mount_yaw).
    [[nodiscard]] double mount_yaw_offset_rad(std::size_t radar) const;
    [[nodiscard]] double mount_yaw_sigma_rad(std::size_t radar) const;
    /// What radar @p radar measures for a static world at the current twist: its velocity in its
    /// calibrated frame, R^T [1 0 -s_y; 0 1 s_x] (v_x, v_y, omega_z) (z = 0).
    [[nodiscard]] Eigen::Vector3d RadarVelocity(std::size_t radar) const;
    /// The base's motion over @p dt_s at the current twist, as ExpSE3's [rho; phi] (planar).
    [[nodiscard]] Vector6d MotionOver(double dt_s) const;
    /// The mount as calibrated: the published one turned by its yaw offset.
    [[nodiscard]] Eigen::Isometry3d T_base_radar(std::size_t radar) const;
    [[nodiscard]] std::size_t radars() const { return T_base_radars_.size(); }
    /// The stamp of the newest update; empty before the first.
    [[nodiscard]] std::optional<int64_t> stamp_ns() const { return stamp_ns_; }
    /// The chi^2 of the newest update's innovation (2 dof).
    [[nodiscard]] double last_nis() const { return last_nis_; }

  private:
    void Restart();
    [[nodiscard]] Eigen::Index OffsetIndex(std::size_t radar) const;

    PlanarTwistFilterConfig config_;
    VehicleVelocityPrior velocity_prior_;
    std::vector<Eigen::Isometry3d> T_base_radars_;
    Eigen::VectorXd x_;  ///< (v_x, v_y, omega_z, then each radar's yaw offset when calibrated)
    Eigen::MatrixXd P_;
    std::optional<int64_t> stamp_ns_;
    int gated_in_a_row_ = 0;
    double last_nis_ = 0.0;
};

}  // namespace dorado::odometry
