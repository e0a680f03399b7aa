// The planar twist filter (derivation in planar_twist_filter.hpp).
#include "dorado/odometry/planar_twist_filter.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dorado/core/angles.hpp"
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
    positive(mount_yaw_sigma_deg, "mount_yaw_sigma_deg");
    if (!(std::isfinite(mount_yaw_walk_deg_per_sqrt_h) && mount_yaw_walk_deg_per_sqrt_h >= 0.0))
        throw std::invalid_argument("twist filter: mount_yaw_walk_deg_per_sqrt_h must be >= 0");
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
                                     VehicleVelocityPrior velocity_prior,
                                     std::vector<Eigen::Isometry3d> T_base_radars)
    : config_(config), velocity_prior_(velocity_prior), T_base_radars_(std::move(T_base_radars)) {
    config_.Validate();
    if (T_base_radars_.empty()) throw std::invalid_argument("twist filter: no radar mount");
    const Eigen::Index n =
        3 + (config_.calibrate_mount_yaw ? static_cast<Eigen::Index>(T_base_radars_.size()) : 0);
    x_ = Eigen::VectorXd::Zero(n);
    P_ = Eigen::MatrixXd::Zero(n, n);
    const double sigma_yaw = DegToRad(config_.mount_yaw_sigma_deg);
    for (Eigen::Index i = 3; i < n; ++i) P_(i, i) = sigma_yaw * sigma_yaw;
    Restart();
}

// The twist starts over; the mounts' offsets (the radars did not move) are kept.
void PlanarTwistFilter::Restart() {
    x_.head<3>().setZero();
    P_.topRows<3>().setZero();
    P_.leftCols<3>().setZero();
    P_.topLeftCorner<3, 3>() =
        Eigen::Vector3d(kInitialSigmaVelocityMps * kInitialSigmaVelocityMps,
                        kInitialSigmaVelocityMps * kInitialSigmaVelocityMps,
                        kInitialSigmaYawRateRadps * kInitialSigmaYawRateRadps)
            .asDiagonal();
    gated_in_a_row_ = 0;
}

Eigen::Index PlanarTwistFilter::OffsetIndex(std::size_t radar) const {
    return config_.calibrate_mount_yaw ? 3 + static_cast<Eigen::Index>(radar) : -1;
}

double PlanarTwistFilter::mount_yaw_offset_rad(std::size_t radar) const {
    const Eigen::Index i = OffsetIndex(radar);
    return i < 0 ? 0.0 : x_(i);
}

double PlanarTwistFilter::mount_yaw_sigma_rad(std::size_t radar) const {
    const Eigen::Index i = OffsetIndex(radar);
    return i < 0 ? 0.0 : std::sqrt(P_(i, i));
}

Eigen::Isometry3d PlanarTwistFilter::T_base_radar(std::size_t radar) const {
    Eigen::Isometry3d T = T_base_radars_.at(radar);
    T.linear() =
        T.linear() *
        Eigen::AngleAxisd(mount_yaw_offset_rad(radar), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
}

Eigen::Vector3d PlanarTwistFilter::RadarVelocity(std::size_t radar) const {
    const Eigen::Isometry3d T = T_base_radar(radar);
    const Eigen::Vector3d s = T.translation();
    const Eigen::Vector3d v_base(x_(0) - x_(2) * s.y(), x_(1) + x_(2) * s.x(), 0.0);
    return T.linear().transpose() * v_base;
}

Vector6d PlanarTwistFilter::MotionOver(double dt_s) const {
    Vector6d xi = Vector6d::Zero();
    xi << x_(0) * dt_s, x_(1) * dt_s, 0.0, 0.0, 0.0, x_(2) * dt_s;
    return xi;
}

TwistUpdate PlanarTwistFilter::Update(int64_t stamp_ns, std::size_t radar,
                                      const EgoVelocityResult &ego) {
    const Eigen::Isometry3d &T = T_base_radars_.at(radar);
    if (stamp_ns_ && stamp_ns < *stamp_ns_) return TwistUpdate::kOutOfOrder;
    const Eigen::Index n = x_.size();
    // Predict: the twist walks (and the mounts, when they may).
    if (stamp_ns_) {
        const double dt = NanosToSeconds(stamp_ns - *stamp_ns_);
        const double qv = config_.velocity_walk_mps * config_.velocity_walk_mps * dt;
        const double qw = config_.yaw_rate_walk_radps * config_.yaw_rate_walk_radps * dt;
        P_.topLeftCorner<3, 3>() += Eigen::Vector3d(qv, qv, qw).asDiagonal().toDenseMatrix();
        const double walk = DegToRad(config_.mount_yaw_walk_deg_per_sqrt_h);
        for (Eigen::Index i = 3; i < n; ++i) P_(i, i) += walk * walk * dt / 3600.0;
    }
    stamp_ns_ = stamp_ns;
    if (!ego.valid() || !ego.v_radar_mps.allFinite() || !ego.cov_v_radar.allFinite())
        return TwistUpdate::kInvalid;

    // The measurement: the radar's (v_x, v_y) in its frame, h = R(-delta) R^T M x, and the rear
    // axle's lateral velocity (0) when the vehicle's velocity prior is on.
    const Eigen::Matrix2d R = T.linear().topLeftCorner<2, 2>();
    const Eigen::Vector3d s = T.translation();
    Eigen::Matrix<double, 2, 3> M;  // the radar's velocity in the base frame = M x
    M << 1.0, 0.0, -s.y(), 0.0, 1.0, s.x();
    const Eigen::Index k = OffsetIndex(radar);
    const int rows = velocity_prior_.enabled ? 3 : 2;
    Eigen::MatrixXd H(rows, n);
    Eigen::VectorXd innovation(rows);
    const auto linearise = [&] {  // at the current state
        const double delta = k < 0 ? 0.0 : x_(k);
        const double c = std::cos(delta), sn = std::sin(delta);
        Eigen::Matrix2d R_minus_delta, dR_minus_delta;
        R_minus_delta << c, sn, -sn, c;
        dR_minus_delta << -sn, c, -c, -sn;
        const Eigen::Vector2d u = R.transpose() * M * x_.head<3>();
        H.setZero();
        H.topLeftCorner(2, 3) = R_minus_delta * R.transpose() * M;
        if (k >= 0) H.block(0, k, 2, 1) = dR_minus_delta * u;
        innovation.head<2>() = ego.v_radar_mps.head<2>() - R_minus_delta * u;
        if (velocity_prior_.enabled) {
            H(2, 1) = 1.0;
            innovation(2) = -x_(1);
        }
    };
    linearise();
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(rows, rows);
    C.topLeftCorner<2, 2>() =
        ego.cov_v_radar.topLeftCorner<2, 2>() +
        Eigen::Matrix2d::Identity() * config_.min_radar_sigma_mps * config_.min_radar_sigma_mps;
    if (velocity_prior_.enabled)
        C(2, 2) = velocity_prior_.sigma_lateral_mps * velocity_prior_.sigma_lateral_mps;
    // The gate looks at the radar's own rows (the lateral prior is not a sensor).
    const Eigen::MatrixXd H2 = H.topRows(2);
    const Eigen::Matrix2d S2 = H2 * P_ * H2.transpose() + C.topLeftCorner(2, 2);
    const Eigen::Vector2d nu = innovation.head<2>();
    last_nis_ = nu.dot(S2.ldlt().solve(nu));
    TwistUpdate outcome = TwistUpdate::kTaken;
    if (config_.gate_chi2 > 0.0 && last_nis_ > config_.gate_chi2) {
        if (++gated_in_a_row_ < config_.max_gated_in_a_row) return TwistUpdate::kGated;
        Restart();
        linearise();
        outcome = TwistUpdate::kRestarted;
    }
    gated_in_a_row_ = 0;
    const Eigen::MatrixXd S = H * P_ * H.transpose() + C;
    const Eigen::MatrixXd K =
        P_ * H.transpose() * S.ldlt().solve(Eigen::MatrixXd::Identity(rows, rows));
    x_ += K * innovation;
    // Joseph form: stays symmetric and positive.
    const Eigen::MatrixXd I_KH = Eigen::MatrixXd::Identity(n, n) - K * H;
    P_ = I_KH * P_ * I_KH.transpose() + K * C * K.transpose();
    return outcome;
}

}  // namespace dorado::odometry
