// The planar twist filter (derivation in planar_twist_filter.hpp).
#include "dorado/odometry/planar_twist_filter.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dorado/core/time.hpp"

namespace dorado::odometry {

namespace {

// Before any radar: no knowledge of the twist beyond what a road vehicle can do.
constexpr double kInitialSigmaVelocityMps = 50.0;
constexpr double kInitialSigmaYawRateRadps = 2.0;

}  // namespace

void PlanarTwistFilterConfig::Validate() const {
    const auto positive = [](double value, const char *name) {
        if (!(std::isfinite(value) && value > 0.0))
            throw std::invalid_argument(std::string("twist filter: ") + name +
                                        " must be a number > 0");
    };
    positive(velocity_walk_mps, "velocity_walk_mps");
    positive(yaw_rate_walk_radps, "yaw_rate_walk_radps");
    positive(min_radar_sigma_mps, "min_radar_sigma_mps");
    if (!(std::isfinite(gate_chi2) && gate_chi2 >= 0.0))
        throw std::invalid_argument("twist filter: gate_chi2 must be >= 0 (0: no gate)");
    if (max_gated_in_a_row < 1)
        throw std::invalid_argument("twist filter: max_gated_in_a_row must be >= 1");
}

const char *ToString(TwistUpdate update) {
    switch (update) {
        case TwistUpdate::kTaken:
            return "taken";
        case TwistUpdate::kInvalid:
            return "invalid";
        case TwistUpdate::kGated:
            return "gated";
        case TwistUpdate::kRestarted:
            return "restarted";
        case TwistUpdate::kOutOfOrder:
            return "out_of_order";
    }
    return "taken";
}

PlanarTwistFilter::PlanarTwistFilter(PlanarTwistFilterConfig config,
                                     VehicleVelocityPrior velocity_prior)
    : config_(config), velocity_prior_(velocity_prior) {
    config_.Validate();
    Restart();
}

void PlanarTwistFilter::Restart() {
    x_.setZero();
    P_ = Eigen::Vector3d(kInitialSigmaVelocityMps * kInitialSigmaVelocityMps,
                         kInitialSigmaVelocityMps * kInitialSigmaVelocityMps,
                         kInitialSigmaYawRateRadps * kInitialSigmaYawRateRadps)
             .asDiagonal();
    gated_in_a_row_ = 0;
}

TwistUpdate PlanarTwistFilter::Update(int64_t stamp_ns, const Eigen::Isometry3d &T_base_radar,
                                      const EgoVelocityResult &ego) {
    if (stamp_ns_ && stamp_ns < *stamp_ns_) return TwistUpdate::kOutOfOrder;
    // Predict: the twist walks.
    if (stamp_ns_) {
        const double dt = NanosToSeconds(stamp_ns - *stamp_ns_);
        const double qv = config_.velocity_walk_mps * config_.velocity_walk_mps * dt;
        const double qw = config_.yaw_rate_walk_radps * config_.yaw_rate_walk_radps * dt;
        P_ += Eigen::Vector3d(qv, qv, qw).asDiagonal().toDenseMatrix();
    }
    stamp_ns_ = stamp_ns;
    if (!ego.valid() || !ego.v_radar_mps.allFinite() || !ego.cov_v_radar.allFinite())
        return TwistUpdate::kInvalid;

    // The measurement: the radar's (v_x, v_y) in its frame, and the rear axle's lateral velocity
    // (0) when the vehicle's velocity prior is on.
    const Eigen::Matrix2d R = T_base_radar.linear().topLeftCorner<2, 2>();
    const Eigen::Vector3d s = T_base_radar.translation();
    Eigen::Matrix<double, 2, 3> M;  // the radar's velocity in the base frame = M x
    M << 1.0, 0.0, -s.y(), 0.0, 1.0, s.x();
    const int rows = velocity_prior_.enabled ? 3 : 2;
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(rows, 3);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(rows);
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(rows, rows);
    H.topRows<2>() = R.transpose() * M;
    z.head<2>() = ego.v_radar_mps.head<2>();
    C.topLeftCorner<2, 2>() =
        ego.cov_v_radar.topLeftCorner<2, 2>() +
        Eigen::Matrix2d::Identity() * config_.min_radar_sigma_mps * config_.min_radar_sigma_mps;
    if (velocity_prior_.enabled) {
        H(2, 1) = 1.0;
        C(2, 2) = velocity_prior_.sigma_lateral_mps * velocity_prior_.sigma_lateral_mps;
    }
    // The gate looks at the radar's own rows (the lateral prior is not a sensor).
    const Eigen::Vector2d innovation = z.head<2>() - H.topRows<2>() * x_;
    const Eigen::Matrix2d S2 =
        H.topRows<2>() * P_ * H.topRows<2>().transpose() + C.topLeftCorner<2, 2>();
    last_nis_ = innovation.dot(S2.ldlt().solve(innovation));
    TwistUpdate outcome = TwistUpdate::kTaken;
    if (config_.gate_chi2 > 0.0 && last_nis_ > config_.gate_chi2) {
        if (++gated_in_a_row_ < config_.max_gated_in_a_row) return TwistUpdate::kGated;
        Restart();
        outcome = TwistUpdate::kRestarted;
    }
    gated_in_a_row_ = 0;
    const Eigen::MatrixXd S = H * P_ * H.transpose() + C;
    const Eigen::MatrixXd K =
        P_ * H.transpose() * S.ldlt().solve(Eigen::MatrixXd::Identity(rows, rows));
    x_ += K * (z - H * x_);
    // Joseph form: stays symmetric and positive.
    const Eigen::Matrix3d I_KH = Eigen::Matrix3d::Identity() - K * H;
    P_ = I_KH * P_ * I_KH.transpose() + K * C * K.transpose();
    return outcome;
}

}  // namespace dorado::odometry
