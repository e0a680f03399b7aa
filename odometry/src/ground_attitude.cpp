#include "dorado/odometry/ground_attitude.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"

namespace dorado::odometry {

namespace {}  // namespace

void GroundAttitudeConfig::Validate() const {
    plane.Validate();
    auto require = [](bool ok, const char *key, const char *what) {
        if (!ok) throw std::invalid_argument(std::string("ground.") + key + ": " + what);
    };
    require(road_slope_sigma_deg > 0.0, "road_slope_sigma_deg", "must be > 0");
    require(road_correlation_m >= 0.0, "road_correlation_m", "must be >= 0");
    require(attitude_random_walk_deg_per_sqrt_s >= 0.0, "attitude_random_walk_deg_per_sqrt_s",
            "must be >= 0");
    require(max_innovation_chi2 >= 0.0, "max_innovation_chi2", "must be >= 0 (0: no gate)");
}

GroundAttitudeFilter::GroundAttitudeFilter(GroundAttitudeConfig config)
    : config_((config.Validate(), std::move(config))),
      initialized_(!config_.initialize_from_ground) {}

void GroundAttitudeFilter::Predict(const Eigen::Matrix3d &cov_omega_base, double dt_s) {
    if (!(dt_s > 0.0)) return;
    const double q = std::pow(DegToRad(config_.attitude_random_walk_deg_per_sqrt_s), 2);
    // Roll and pitch rates are the base's omega_x, omega_y to first order in roll and pitch.
    P_ +=
        cov_omega_base.topLeftCorner<2, 2>() * dt_s * dt_s + q * dt_s * Eigen::Matrix2d::Identity();
}

GroundAttitudeStep GroundAttitudeFilter::Update(const GroundObservation &observation,
                                                double distance_m,
                                                const Eigen::Matrix3d &R_world_base) {
    GroundAttitudeStep step;
    step.observation = observation;
    step.fit = observation;
    step.cov_roll_pitch = P_;
    step.R_world_base = R_world_base;
    if (!observation.valid) return step;
    const double slope2 = std::pow(DegToRad(config_.road_slope_sigma_deg), 2);
    Eigen::Vector3d rpy = RollPitchYaw(R_world_base);
    // Roll and pitch set to the observation's (the world frame is level with the road here).
    const auto level = [&] {
        step.correction_rad = observation.roll_pitch_rad - rpy.head<2>();
        rpy.head<2>() = observation.roll_pitch_rad;
        step.R_world_base = RotationFromRollPitchYaw(rpy);
        P_ = observation.cov_roll_pitch + slope2 * Eigen::Matrix2d::Identity();
        initialized_ = true;
        step.updated = true;
        step.cov_roll_pitch = P_;
        return step;
    };
    if (!initialized_) return level();
    if (!(distance_m > 1e-3)) return step;
    // z = [roll, pitch] of R_world_base (ZYX, yaw free); H = I on the Euler error.
    const Eigen::Vector2d innovation = observation.roll_pitch_rad - rpy.head<2>();
    // The gate: one look at the road's slope (a ridge, a kerb or a ramp under the vehicle tilts
    // the plane beyond what the road's slope and the drift since the last update explain).
    const Eigen::Matrix2d S1 =
        P_ + observation.cov_roll_pitch + slope2 * Eigen::Matrix2d::Identity();
    step.innovation_chi2 = innovation.dot(S1.ldlt().solve(innovation));
    if (config_.max_innovation_chi2 > 0.0 &&
        !(step.innovation_chi2 <= config_.max_innovation_chi2)) {
        // Refused over more than the road's correlation length, the ground disagrees with the
        // attitude for longer than any kerb or ramp: the attitude drifted beyond the gate, which
        // would refuse every later look. It is levelled with the ground again, as at the start.
        refused_distance_m_ += distance_m;
        if (config_.road_correlation_m > 0.0 && refused_distance_m_ > config_.road_correlation_m) {
            refused_distance_m_ = 0.0;
            step.relevelled = true;
            return level();
        }
        step.observation.valid = false;
        step.observation.fallback = GroundFallback::kInconsistent;
        return step;
    }
    refused_distance_m_ = 0.0;
    // The road's slope is the measurement's error: correlated over road_correlation_m, so a scan
    // that moved distance_m holds distance_m / road_correlation_m of an independent look at it.
    const double looks = std::max(1.0, config_.road_correlation_m / distance_m);
    const Eigen::Matrix2d R =
        observation.cov_roll_pitch + slope2 * looks * Eigen::Matrix2d::Identity();
    const Eigen::Matrix2d K = P_ * (P_ + R).inverse();
    step.correction_rad = K * innovation;
    if (!step.correction_rad.allFinite()) return step;
    rpy.head<2>() += step.correction_rad;
    step.R_world_base = RotationFromRollPitchYaw(rpy);
    P_ = (Eigen::Matrix2d::Identity() - K) * P_;
    P_ = 0.5 * (P_ + P_.transpose());
    step.updated = true;
    step.cov_roll_pitch = P_;
    return step;
}

}  // namespace dorado::odometry
