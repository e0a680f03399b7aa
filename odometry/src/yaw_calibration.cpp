#include "dorado/odometry/yaw_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dorado/core/lie.hpp"

namespace dorado::odometry {

void YawCalibrationConfig::Validate() const {
    auto require = [](bool ok, const char *key, const char *what) {
        if (!ok)
            throw std::invalid_argument(std::string("online_calibration.") + key + ": " + what);
    };
    require(warmup_s >= 0.0, "warmup_s", "must be >= 0");
    require(window_s > 0.0, "window_s", "must be > 0");
    require(max_window_s >= window_s, "max_window_s", "must be >= window_s");
    require(min_turn_rad > 0.0, "min_turn_rad", "must be > 0 (straight driving is unobservable)");
    require(min_speed_mps >= 0.0, "min_speed_mps", "must be >= 0");
    require(measurement_sigma_rad > 0.0, "measurement_sigma_rad", "must be > 0");
    require(relative_sigma >= 0.0, "relative_sigma", "must be >= 0");
    require(initial_relative_sigma > 0.0, "initial_relative_sigma", "must be > 0");
    require(relative_random_walk_per_sqrt_s >= 0.0, "relative_random_walk_per_sqrt_s",
            "must be >= 0");
    require(max_innovation_chi2 >= 0.0, "max_innovation_chi2", "must be >= 0 (0: no gate)");
    require(max_ratio > 1.0, "max_ratio", "must be > 1");
}

const char *ToString(YawCalibrationStatus status) {
    switch (status) {
        case YawCalibrationStatus::kDisabled:
            return "disabled";
        case YawCalibrationStatus::kWarmup:
            return "warmup";
        case YawCalibrationStatus::kAccumulating:
            return "accumulating";
        case YawCalibrationStatus::kNotRegistered:
            return "not_registered";
        case YawCalibrationStatus::kStanding:
            return "standing";
        case YawCalibrationStatus::kStraight:
            return "straight";
        case YawCalibrationStatus::kOutlier:
            return "outlier";
        case YawCalibrationStatus::kUpdated:
            return "updated";
    }
    return "?";
}

YawRateCalibrator::YawRateCalibrator(const YawCalibrationConfig &config, double configured_s_x_m)
    : config_(config) {
    config_.Validate();
    if (!std::isfinite(configured_s_x_m) || std::abs(configured_s_x_m) < 1e-3)
        throw std::invalid_argument("online calibration: the configured s_x (" +
                                    std::to_string(configured_s_x_m) +
                                    " m) leaves the yaw rate unobservable");
    g0_ = 1.0 / configured_s_x_m;
    g_ = g0_;
    const double sigma = config_.initial_relative_sigma * g0_;
    P_ = sigma * sigma;
}

double YawRateCalibrator::sigma_s_x_m() const {
    return std::sqrt(P_) / (g_ * g_);  // |d(1/g)/dg| sigma_g
}

YawCalibrationStep YawRateCalibrator::Report(YawCalibrationStatus status, double chi2) const {
    YawCalibrationStep step;
    step.status = status;
    step.s_x_m = s_x_m();
    step.sigma_s_x_m = sigma_s_x_m();
    step.innovation_chi2 = chi2;
    return step;
}

void YawRateCalibrator::RestartWindow(bool at_registered_scan, const Eigen::Matrix3d &R_world_base) {
    window_open_ = at_registered_scan;
    R_start_ = R_world_base;
    h_m_ = elapsed_s_ = distance_m_ = 0.0;
}

YawCalibrationStep YawRateCalibrator::Update(double dpsi_rad, double h_m, double mean_speed_mps,
                                             double elapsed_s) {
    if (!(mean_speed_mps >= config_.min_speed_mps)) return Report(YawCalibrationStatus::kStanding);
    const double predicted = g_ * h_m;
    if (!(std::abs(predicted) >= config_.min_turn_rad))
        return Report(YawCalibrationStatus::kStraight);
    // Predict: g random-walks since the last update.
    const double q = config_.relative_random_walk_per_sqrt_s * g0_;
    const double P = P_ + q * q * std::max(elapsed_s, 0.0);
    // Measure: dpsi = g h + e, var(e) = sigma^2 + (relative * g h)^2.
    const double rel = config_.relative_sigma * predicted;
    const double R = config_.measurement_sigma_rad * config_.measurement_sigma_rad + rel * rel;
    const double S = h_m * h_m * P + R;
    const double innovation = dpsi_rad - predicted;
    const double chi2 = innovation * innovation / S;
    if (config_.max_innovation_chi2 > 0.0 && !(chi2 <= config_.max_innovation_chi2)) {
        P_ = P;  // the time passed still counts
        return Report(YawCalibrationStatus::kOutlier, chi2);
    }
    const double K = P * h_m / S;
    g_ += K * innovation;
    P_ = (1.0 - K * h_m) * P;
    // Keep s_x within [1 / max_ratio, max_ratio] of the configured value (and on its side).
    const double ratio = std::clamp(g_ / g0_, 1.0 / config_.max_ratio, config_.max_ratio);
    g_ = ratio * g0_;
    ++updates_;
    return Report(YawCalibrationStatus::kUpdated, chi2);
}

YawCalibrationStep YawRateCalibrator::AddScan(double dt_s, double v_sy_base_mps, double speed_mps,
                                              bool registered,
                                              const Eigen::Matrix3d &R_world_base) {
    if (!config_.enabled) return Report(YawCalibrationStatus::kDisabled);
    const double dt = std::isfinite(dt_s) && dt_s > 0.0 ? dt_s : 0.0;
    since_update_s_ += dt;
    age_s_ += dt;
    if (age_s_ < config_.warmup_s) {
        RestartWindow(false, R_world_base);
        return Report(YawCalibrationStatus::kWarmup);
    }
    if (!registered || !R_world_base.allFinite()) {
        RestartWindow(false, R_world_base);
        return Report(YawCalibrationStatus::kNotRegistered);
    }
    if (!window_open_) {
        RestartWindow(true, R_world_base);
        return Report(YawCalibrationStatus::kAccumulating);
    }
    if (std::isfinite(v_sy_base_mps) && std::isfinite(speed_mps)) {
        h_m_ += v_sy_base_mps * dt;
        distance_m_ += std::abs(speed_mps) * dt;
    }
    elapsed_s_ += dt;
    if (elapsed_s_ < config_.window_s) return Report(YawCalibrationStatus::kAccumulating);
    const double mean_speed = distance_m_ / elapsed_s_;
    if (mean_speed < config_.min_speed_mps) {
        RestartWindow(true, R_world_base);
        return Report(YawCalibrationStatus::kStanding);
    }
    if (std::abs(g_ * h_m_) < config_.min_turn_rad) {
        if (elapsed_s_ < config_.max_window_s) return Report(YawCalibrationStatus::kAccumulating);
        RestartWindow(true, R_world_base);
        return Report(YawCalibrationStatus::kStraight);
    }
    // The yaw change between the window's two registered poses, about the start's base Z axis
    // (to first order in roll and pitch, the integral of omega_z).
    const double dpsi = LogSO3(R_start_.transpose() * R_world_base).z();
    const YawCalibrationStep step = Update(dpsi, h_m_, mean_speed, since_update_s_);
    if (step.status == YawCalibrationStatus::kUpdated ||
        step.status == YawCalibrationStatus::kOutlier)
        since_update_s_ = 0.0;
    RestartWindow(true, R_world_base);
    return step;
}

}  // namespace dorado::odometry
