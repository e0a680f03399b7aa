#include "dorado/mapping/motion_prior.hpp"

#include <cmath>
#include <stdexcept>

#include "dorado/core/require.hpp"
#include "dorado/core/time.hpp"

namespace dorado::mapping {

const char *ToString(PriorKind kind) {
    switch (kind) {
        case PriorKind::kNone:
            return "none";
        case PriorKind::kConstVel:
            return "constvel";
        case PriorKind::kImu:
            return "imu";
        case PriorKind::kDoppler:
            return "doppler";
        case PriorKind::kImuDoppler:
            return "imu+doppler";
    }
    return "?";
}

PriorKind ParsePriorKind(const std::string &name) {
    for (PriorKind kind : kAllPriorKinds) {
        if (name == ToString(kind)) return kind;
    }
    throw std::invalid_argument("'" + name +
                                "' is not one of: none, constvel, imu, doppler, imu+doppler");
}

const char *ToString(TwistIntegration integration) {
    switch (integration) {
        case TwistIntegration::kEndpoint:
            return "endpoint";
        case TwistIntegration::kTrapezoid:
            return "trapezoid";
    }
    return "?";
}

Twist TrapezoidTwist(const Twist &at_start, const Twist &at_end) {
    return {0.5 * (at_start.v_base_mps + at_end.v_base_mps),
            0.5 * (at_start.omega_base_radps + at_end.omega_base_radps),
            0.5 * (at_start.covariance + at_end.covariance)};
}

namespace {

Matrix6d BlockDiagonal(const Eigen::Matrix3d &cov_translation,
                       const Eigen::Matrix3d &cov_rotation) {
    Matrix6d cov = Matrix6d::Zero();
    cov.topLeftCorner<3, 3>() = cov_translation;
    cov.bottomRightCorner<3, 3>() = cov_rotation;
    return cov;
}

Eigen::Matrix3d Isotropic(double sigma) {
    return sigma * sigma * Eigen::Matrix3d::Identity();
}

void RequirePositive(double value, const char *key) {
    Require(std::isfinite(value) && value > 0.0, std::string("prior.") + key, "must be > 0");
}

void RequirePositiveInterval(double dt_s, const char *what) {
    if (!std::isfinite(dt_s) || dt_s <= 0.0)
        throw std::invalid_argument(std::string(what) + ": dt must be finite and > 0");
}

}  // namespace

void PriorNoiseConfig::Validate() const {
    RequirePositive(none_sigma_translation_m, "none_sigma_translation_m");
    RequirePositive(none_sigma_rotation_rad, "none_sigma_rotation_rad");
    RequirePositive(constvel_sigma_accel_mps2, "constvel_sigma_accel_mps2");
    RequirePositive(constvel_sigma_angular_accel_radps2, "constvel_sigma_angular_accel_radps2");
    RequirePositive(imu_gyro_sigma_radps, "imu_gyro_sigma_radps");
    RequirePositive(imu_accel_sigma_mps2, "imu_accel_sigma_mps2");
    RequirePositive(imu_velocity_sigma_mps, "imu_velocity_sigma_mps");
    RequirePositive(doppler_min_sigma_v_mps, "doppler_min_sigma_v_mps");
    for (int i = 0; i < 3; ++i)
        RequirePositive(doppler_min_sigma_omega_radps[i], "doppler_min_sigma_omega_radps");
    if (!gravity_world_mps2.allFinite())
        throw std::invalid_argument("prior.gravity_world_mps2: must be finite");
}

MotionPrior PriorFromPreviousPose(const Eigen::Isometry3d &T_world_base_prev,
                                  const PriorNoiseConfig &noise) {
    return {T_world_base_prev,
            BlockDiagonal(Isotropic(noise.none_sigma_translation_m),
                          Isotropic(noise.none_sigma_rotation_rad)),
            PriorKind::kNone};
}

MotionPrior PriorConstantVelocity(const Eigen::Isometry3d &T_world_base_prevprev,
                                  const Eigen::Isometry3d &T_world_base_prev, double dt_prev_s,
                                  double dt_s, const PriorNoiseConfig &noise) {
    RequirePositiveInterval(dt_prev_s, "constvel prior");
    RequirePositiveInterval(dt_s, "constvel prior");
    // The last relative motion as a constant twist, replayed over dt_s.
    const Vector6d xi =
        LogSE3(T_world_base_prevprev.inverse() * T_world_base_prev) * (dt_s / dt_prev_s);
    // An unmodelled acceleration a over dt moves the pose by about a dt^2 (velocity error a dt,
    // integrated over dt).
    return {T_world_base_prev * ExpSE3(xi),
            BlockDiagonal(Isotropic(noise.constvel_sigma_accel_mps2 * dt_s * dt_s),
                          Isotropic(noise.constvel_sigma_angular_accel_radps2 * dt_s * dt_s)),
            PriorKind::kConstVel};
}

std::optional<MotionPrior> PriorFromImu(const Eigen::Isometry3d &T_world_base_prev,
                                        const std::optional<Eigen::Vector3d> &v_world_prev_mps,
                                        const std::vector<ImuSample> &samples, int64_t t0_ns,
                                        int64_t t1_ns, const Eigen::Isometry3d &T_base_imu,
                                        const PriorNoiseConfig &noise) {
    if (t1_ns <= t0_ns) throw std::invalid_argument("imu prior: t1 must be after t0");
    const Eigen::Matrix3d R_base_imu = T_base_imu.linear();
    Eigen::Matrix3d R_world_base = T_world_base_prev.linear();
    Eigen::Vector3d p_world = T_world_base_prev.translation();
    Eigen::Vector3d v_world = v_world_prev_mps.value_or(Eigen::Vector3d::Zero());
    int64_t t_ns = t0_ns;
    bool any = false;
    // Zero-order hold of each sample from the previous time to its stamp; the last sample holds
    // until t1. Semi-implicit Euler on position with the exact constant-acceleration step.
    auto integrate = [&](const ImuSample &s, int64_t until_ns) {
        const double h = NanosToSeconds(until_ns - t_ns);
        if (h <= 0.0) return;
        const Eigen::Vector3d a_world =
            R_world_base * (R_base_imu * s.accel_imu_mps2) + noise.gravity_world_mps2;
        p_world += v_world * h + 0.5 * a_world * h * h;
        v_world += a_world * h;
        R_world_base = R_world_base * ExpSO3(R_base_imu * s.omega_imu_radps * h);
        t_ns = until_ns;
    };
    const ImuSample *last = nullptr;
    for (const auto &s : samples) {
        if (s.stamp_ns <= t0_ns) continue;
        if (s.stamp_ns > t1_ns) {
            if (any) break;
            // No sample inside the interval: the first one after it still describes it.
            integrate(s, t1_ns);
            last = &s;
            any = true;
            break;
        }
        integrate(s, s.stamp_ns);
        last = &s;
        any = true;
    }
    if (!any) return std::nullopt;
    integrate(*last, t1_ns);

    const double dt = NanosToSeconds(t1_ns - t0_ns);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R_world_base;
    T.translation() = p_world;
    const double sigma_t = v_world_prev_mps ? noise.imu_velocity_sigma_mps * dt +
                                                  0.5 * noise.imu_accel_sigma_mps2 * dt * dt
                                            : noise.none_sigma_translation_m;
    const double sigma_r = noise.imu_gyro_sigma_radps * dt;
    return MotionPrior{T, BlockDiagonal(Isotropic(sigma_t), Isotropic(sigma_r)), PriorKind::kImu};
}

MotionPrior PriorFromDoppler(const Eigen::Isometry3d &T_world_base_prev, const Twist &twist,
                             double dt_s, const PriorNoiseConfig &noise) {
    RequirePositiveInterval(dt_s, "doppler prior");
    Vector6d xi;
    xi << twist.v_base_mps * dt_s, twist.omega_base_radps * dt_s;
    const Eigen::Matrix3d cov_v =
        twist.covariance.topLeftCorner<3, 3>() + Isotropic(noise.doppler_min_sigma_v_mps);
    const Eigen::Matrix3d cov_omega =
        twist.covariance.bottomRightCorner<3, 3>() +
        Eigen::Vector3d(noise.doppler_min_sigma_omega_radps.array().square())
            .asDiagonal()
            .toDenseMatrix();
    // The right Jacobian of ExpSE3 at xi is ~identity for one radar interval; it is neglected.
    return {T_world_base_prev * ExpSE3(xi), BlockDiagonal(cov_v, cov_omega) * (dt_s * dt_s),
            PriorKind::kDoppler};
}

MotionPrior FusePriors(const MotionPrior &a, const MotionPrior &b) {
    const Vector6d xi = LogSE3(a.T_world_base.inverse() * b.T_world_base);
    const Matrix6d info_a = a.covariance.ldlt().solve(Matrix6d::Identity());
    const Matrix6d info_b = b.covariance.ldlt().solve(Matrix6d::Identity());
    Matrix6d covariance = (info_a + info_b).ldlt().solve(Matrix6d::Identity());
    covariance = 0.5 * (covariance + covariance.transpose());
    const Vector6d delta = covariance * info_b * xi;
    return {a.T_world_base * ExpSE3(delta), covariance, a.kind};
}

std::optional<MotionPrior> PriorFromImuAndDoppler(const Eigen::Isometry3d &T_world_base_prev,
                                                  const Twist &twist,
                                                  const std::vector<ImuSample> &samples,
                                                  int64_t t0_ns, int64_t t1_ns,
                                                  const Eigen::Isometry3d &T_base_imu, double dt_s,
                                                  const PriorNoiseConfig &noise) {
    RequirePositiveInterval(dt_s, "imu+doppler prior");
    const Eigen::Vector3d omega_imu = MeanAngularVelocity(samples, t0_ns, t1_ns);
    if (!omega_imu.allFinite()) return std::nullopt;
    Twist mixed = twist;
    mixed.omega_base_radps = T_base_imu.linear() * omega_imu;
    Vector6d xi;
    xi << mixed.v_base_mps * dt_s, mixed.omega_base_radps * dt_s;
    const Eigen::Matrix3d cov_v =
        twist.covariance.topLeftCorner<3, 3>() + Isotropic(noise.doppler_min_sigma_v_mps);
    return MotionPrior{T_world_base_prev * ExpSE3(xi),
                       BlockDiagonal(cov_v, Isotropic(noise.imu_gyro_sigma_radps)) * (dt_s * dt_s),
                       PriorKind::kImuDoppler};
}

double PriorMahalanobisSquared(const MotionPrior &prior, const Eigen::Isometry3d &T_world_base) {
    const Vector6d xi = LogSE3(prior.T_world_base.inverse() * T_world_base);
    return xi.dot(prior.covariance.ldlt().solve(xi));
}

}  // namespace dorado::mapping
