// The planar twist from several radars' Doppler jointly (derivation in multi_radar_twist.hpp).
#include "dorado/odometry/multi_radar_twist.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace dorado::odometry {

const char *ToString(PlanarTwistFailure failure) {
    switch (failure) {
        case PlanarTwistFailure::kNone:
            return "";
        case PlanarTwistFailure::kNotEstimated:
            return "not estimated";
        case PlanarTwistFailure::kTooFewRadars:
            return "too few radars";
        case PlanarTwistFailure::kTooFewPoints:
            return "too few static points";
        case PlanarTwistFailure::kDegenerateGeometry:
            return "degenerate geometry";
        case PlanarTwistFailure::kNonFinite:
            return "non-finite twist";
    }
    return "?";
}

PlanarTwist EstimatePlanarTwist(const std::vector<RadarObservation> &radars) {
    PlanarTwist out;
    Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
    double btb = 0.0;
    std::vector<Eigen::Vector2d> positions;
    for (const RadarObservation &radar : radars) {
        if (radar.scan_radar == nullptr || radar.ego == nullptr || !radar.ego->valid()) continue;
        const RadarScan &scan = *radar.scan_radar;
        if (radar.ego->labels.size() != static_cast<std::size_t>(scan.size())) continue;
        const Eigen::Matrix3d R = radar.T_base_radar.linear();
        const Eigen::Vector3d s = radar.T_base_radar.translation();
        Eigen::Matrix<double, 2, 3> M;  // v_s (x, y) = M (v_x, v_y, omega_z)
        M << 1.0, 0.0, -s.y(), 0.0, 1.0, s.x();
        int used = 0;
        for (Eigen::Index i = 0; i < scan.size(); ++i) {
            if (radar.ego->labels[i] != PointLabel::kStatic) continue;
            const Eigen::Vector3d p = scan.xyz_radar.col(i);
            const double r = std::hypot(p.x(), p.y());
            if (!(r > 0.0) || !std::isfinite(scan.doppler_mps[i])) continue;
            const Eigen::Vector3d d_base = R * Eigen::Vector3d(p.x() / r, p.y() / r, 0.0);
            const Eigen::RowVector3d a = d_base.head<2>().transpose() * M;
            const double b = -scan.doppler_mps[i];
            AtA += a.transpose() * a;
            Atb += a.transpose() * b;
            btb += b * b;
            ++used;
        }
        if (used == 0) continue;
        ++out.radars_used;
        out.points_used += used;
        positions.push_back(s.head<2>());
    }
    bool distinct = false;
    for (std::size_t k = 1; k < positions.size(); ++k)
        distinct = distinct || (positions[k] - positions[0]).norm() > 0.1;
    if (out.radars_used < 2 || !distinct) {
        out.failure = PlanarTwistFailure::kTooFewRadars;
        out.failure_detail =
            "the yaw rate needs the static points of >= 2 radars at distinct positions (" +
            std::to_string(out.radars_used) + " radar(s) with a valid ego-velocity)";
        return out;
    }
    if (out.points_used < 4) {
        out.failure = PlanarTwistFailure::kTooFewPoints;
        out.failure_detail = std::to_string(out.points_used) + " < 4";
        return out;
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(AtA);
    const Eigen::Vector3d lambda =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(AtA, Eigen::EigenvaluesOnly).eigenvalues();
    if (!(lambda(0) > 1e-9 * lambda(2))) {
        out.failure = PlanarTwistFailure::kDegenerateGeometry;
        out.failure_detail = "the radars' directions do not observe the twist";
        return out;
    }
    out.twist = ldlt.solve(Atb);
    // Residual sum of squares = b^T b - x^T A^T b at the least-squares solution.
    const double rss = std::max(btb - out.twist.dot(Atb), 0.0);
    const double dof = std::max(out.points_used - 3, 1);
    out.residual_sigma_mps = std::sqrt(rss / dof);
    out.covariance = (rss / dof) * ldlt.solve(Eigen::Matrix3d::Identity());
    out.failure = out.twist.allFinite() && out.covariance.allFinite()
                      ? PlanarTwistFailure::kNone
                      : PlanarTwistFailure::kNonFinite;
    return out;
}

}  // namespace dorado::odometry
