#pragma once
/// @file ground_attitude.hpp
/// Fuses the per-scan ground-plane observation (ground_plane.hpp) into the odometry's roll and
/// pitch: a two-state Kalman filter on the attitude error whose process is the integrated angular
/// rate (its covariance, plus a random walk for what the kinematic model misses) and whose
/// measurement says "the base's roll and pitch in the world equal those relative to the road",
/// i.e. the road is level up to a slope of road_slope_sigma_deg that changes over
/// road_correlation_m. That prior is what bounds the drift, and what misleads on a long climb
/// (docs/attitude.md).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>

#include "dorado/odometry/ground_plane.hpp"

namespace dorado::odometry {

struct GroundAttitudeConfig {
    /// true: roll and pitch corrected by the ground where the vehicle's base height is known
    /// (without it every scan is a kNoBaseHeight fallback and the rates are integrated alone);
    /// false: the rates alone (the paper).
    bool enabled = true;
    GroundPlaneConfig plane;
    /// Spread of the road's own slope (roll and pitch) about level [deg], 1 sigma.
    double road_slope_sigma_deg = 4.0;
    /// Distance over which the road's slope is correlated [m]: the scans within it see the same
    /// slope, so each scan's observation counts as 1/(scans per correlation length) of one.
    double road_correlation_m = 20.0;
    /// Random walk of roll and pitch from rate errors the twist covariance does not hold (a bias
    /// of the vertical velocity, the roll the model sets to zero) [deg/sqrt(s)].
    double attitude_random_walk_deg_per_sqrt_s = 0.3;
    /// true: the first ground observation sets roll and pitch (the world frame is then level
    /// with the road at the start, not with the first pose); false: the first pose is taken as
    /// exactly known and only later scans correct it.
    bool initialize_from_ground = true;
    /// Consistency with the predicted attitude: an observation whose innovation's squared
    /// Mahalanobis distance, against the prediction's covariance + the fit's + one look at the
    /// road's slope, exceeds this is refused (GroundFallback::kInconsistent). 9.21 = chi^2(2 dof)
    /// at 99 %; 0 = no gate.
    double max_innovation_chi2 = 9.21;

    /// Throws std::invalid_argument naming the first bad field ("ground.<key>: ...").
    void Validate() const;
};

/// What the filter did with one scan.
struct GroundAttitudeStep {
    /// The plane fit's observation as the filter decided on it (kInconsistent when refused).
    GroundObservation observation;
    /// The plane fit's observation before the filter's gate (another filter on another chain of
    /// poses, the mapper's prior, decides on it again).
    GroundObservation fit;
    bool updated = false;  ///< the attitude was corrected
    /// Levelled with the ground again: the filter had refused it over more than
    /// road_correlation_m (its attitude had drifted beyond the gate).
    bool relevelled = false;
    Eigen::Vector2d correction_rad = Eigen::Vector2d::Zero();  ///< roll, pitch added
    Eigen::Matrix2d cov_roll_pitch = Eigen::Matrix2d::Zero();  ///< after this scan [rad^2]
    /// The attitude after this scan: the given one, roll and pitch corrected when `updated`.
    Eigen::Matrix3d R_world_base = Eigen::Matrix3d::Identity();
    /// The innovation's squared Mahalanobis distance (see max_innovation_chi2); NaN when no
    /// observation was tested.
    double innovation_chi2 = std::numeric_limits<double>::quiet_NaN();
};

class GroundAttitudeFilter {
  public:
    explicit GroundAttitudeFilter(GroundAttitudeConfig config);

    /// Grows the roll/pitch covariance by the integration of omega over dt:
    /// P += C_omega[roll, pitch] dt^2 + q dt.
    void Predict(const Eigen::Matrix3d &cov_omega_base, double dt_s);

    /// Roll and pitch of R_world_base (yaw kept) corrected with the observation, the road counted
    /// as level within road_slope_sigma_deg, given the distance travelled since the previous scan:
    /// the step's R_world_base. Unchanged for an invalid observation or when standing still (the
    /// same road seen again carries no new information about it).
    [[nodiscard]] GroundAttitudeStep Update(const GroundObservation &observation, double distance_m,
                                            const Eigen::Matrix3d &R_world_base);

    [[nodiscard]] const Eigen::Matrix2d &covariance() const { return P_; }
    [[nodiscard]] const GroundAttitudeConfig &config() const { return config_; }
    /// Back to the start: the next ground observation initialises roll and pitch again.
    void Reset() {
        P_.setZero();
        initialized_ = !config_.initialize_from_ground;
        refused_distance_m_ = 0.0;
    }

  private:
    GroundAttitudeConfig config_;
    Eigen::Matrix2d P_ = Eigen::Matrix2d::Zero();  ///< covariance of [roll, pitch] error
    bool initialized_ = false;                     ///< roll and pitch have been set
    double refused_distance_m_ = 0.0;  ///< travelled since the last accepted observation, refusing
};

}  // namespace dorado::odometry
