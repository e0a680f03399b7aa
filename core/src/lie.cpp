#include "dorado/core/lie.hpp"

#include <algorithm>
#include <cmath>

namespace dorado {

namespace {
// Below this angle the closed forms lose precision: use their Taylor series.
constexpr double kSmallAngle = 1e-6;
}  // namespace

Eigen::Matrix3d Hat(const Eigen::Vector3d &v) {
    Eigen::Matrix3d m;
    m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
    return m;
}

Eigen::Matrix3d ExpSO3(const Eigen::Vector3d &phi) {
    const double theta = phi.norm();
    const Eigen::Matrix3d K = Hat(phi);
    if (theta < kSmallAngle) return Eigen::Matrix3d::Identity() + K + 0.5 * K * K;
    // Rodrigues: R = I + sin(t)/t K + (1 - cos(t))/t^2 K^2
    return Eigen::Matrix3d::Identity() + (std::sin(theta) / theta) * K +
           ((1.0 - std::cos(theta)) / (theta * theta)) * K * K;
}

Eigen::Vector3d LogSO3(const Eigen::Matrix3d &R) {
    // The quaternion route is accurate near 0 and near pi alike.
    Eigen::Quaterniond q(R);
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    const double sin_half = q.vec().norm();
    if (sin_half < kSmallAngle) return 2.0 * q.vec() / q.w();
    const double theta = 2.0 * std::atan2(sin_half, q.w());
    return theta * q.vec() / sin_half;
}

Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d &phi) {
    const double theta = phi.norm();
    const Eigen::Matrix3d K = Hat(phi);
    if (theta < kSmallAngle) return Eigen::Matrix3d::Identity() + 0.5 * K + K * K / 6.0;
    const double t2 = theta * theta;
    return Eigen::Matrix3d::Identity() + ((1.0 - std::cos(theta)) / t2) * K +
           ((theta - std::sin(theta)) / (t2 * theta)) * K * K;
}

Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d &phi) {
    const double theta = phi.norm();
    const Eigen::Matrix3d K = Hat(phi);
    if (theta < kSmallAngle) return Eigen::Matrix3d::Identity() - 0.5 * K + K * K / 12.0;
    const double t2 = theta * theta;
    const double coeff = 1.0 / t2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
    return Eigen::Matrix3d::Identity() - 0.5 * K + coeff * K * K;
}

Eigen::Isometry3d ExpSE3(const Vector6d &xi) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d phi = xi.tail<3>();
    T.linear() = ExpSO3(phi);
    T.translation() = LeftJacobianSO3(phi) * xi.head<3>();
    return T;
}

Vector6d LogSE3(const Eigen::Isometry3d &T) {
    Vector6d xi;
    const Eigen::Vector3d phi = LogSO3(T.linear());
    xi.tail<3>() = phi;
    xi.head<3>() = LeftJacobianInverseSO3(phi) * T.translation();
    return xi;
}

Eigen::Isometry3d InterpolatePose(const Eigen::Isometry3d &T_a, const Eigen::Isometry3d &T_b,
                                  double alpha) {
    const Eigen::Quaterniond q_a(T_a.linear());
    const Eigen::Quaterniond q_b(T_b.linear());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q_a.slerp(alpha, q_b).normalized().toRotationMatrix();
    T.translation() = (1.0 - alpha) * T_a.translation() + alpha * T_b.translation();
    return T;
}

double RotationAngle(const Eigen::Matrix3d &R) {
    // Not acos((trace - 1) / 2): near 0 its resolution is sqrt(2 eps) = 2.1e-8 rad (one rounding
    // of the trace reads as 2e-8 rad), the quaternion route's is eps.
    return LogSO3(R).norm();
}

Eigen::Matrix3d RotationFromRollPitchYaw(const Eigen::Vector3d &rpy_rad) {
    return (Eigen::AngleAxisd(rpy_rad.z(), Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(rpy_rad.y(), Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(rpy_rad.x(), Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
}

Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d &R) {
    return {std::atan2(R(2, 1), R(2, 2)), -std::asin(std::clamp(R(2, 0), -1.0, 1.0)),
            std::atan2(R(1, 0), R(0, 0))};
}

}  // namespace dorado
