// The final ego-velocity fit when the point directions are noisy (errors in variables).
//
// A point's measured direction is d~ = d + delta with Gaussian azimuth and elevation errors.
// Plain least squares on d~ is biased: E[d~ d~^T] = S d d^T S + C while E[d~ b] = S d d^T v,
// so noise in elevation (C's v_x-v_z coupling for returns below the horizon) pulls v_z
// by about -sigma_el^2 * mean(sin el cos el) / mean(sin^2 el) * v_x. Exactly, for Gaussian
// angles, E[d~] = S d with S = diag(e^(-(se^2+sa^2)/2), e^(-(se^2+sa^2)/2), e^(-se^2/2)), and to
// leading order C = se^2 e_el e_el^T + sa^2 cos^2(el) e_az e_az^T. The estimating equation
//   sum_i w_i (d~_i b_i - (d~_i d~_i^T - C_i) S_i^-1 v) = 0
// is therefore unbiased (up to O(sigma^4)): bias-compensated least squares. Its inlier gates use
// each point's total variance sigma_i^2 + v^T C_i v (the direction noise projected on the
// velocity grows with speed), and its covariance is the sandwich of the estimating function,
// which contains the direction noise whatever the weights.
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "robust_fit.hpp"

namespace dorado::odometry::internal {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// One point's direction-noise terms: C (covariance of d~), the diagonal of S^-1.
struct DirectionNoise {
    Eigen::Matrix3d C;
    Eigen::Vector3d S_inv;
};

DirectionNoise NoiseOf(const Eigen::Vector3d &d, double sigma_az, double sigma_el) {
    const double cos_el = std::hypot(d.x(), d.y());
    const double sin_el = d.z();
    const double cos_az = cos_el > 1e-12 ? d.x() / cos_el : 1.0;
    const double sin_az = cos_el > 1e-12 ? d.y() / cos_el : 0.0;
    const Eigen::Vector3d e_el(-sin_el * cos_az, -sin_el * sin_az, cos_el);
    const Eigen::Vector3d e_az(-sin_az, cos_az, 0.0);
    const double se2 = sigma_el * sigma_el, sa2 = sigma_az * sigma_az;
    DirectionNoise n;
    n.C = se2 * e_el * e_el.transpose() + sa2 * cos_el * cos_el * e_az * e_az.transpose();
    const double horizontal = std::exp(0.5 * (se2 + sa2)), vertical = std::exp(0.5 * se2);
    n.S_inv << horizontal, horizontal, vertical;
    return n;
}

}  // namespace

bool FitWithDirectionNoise(const EgoVelocityConfig &config, Workspace &ws, Eigen::Vector3d &v,
                           Eigen::Matrix3d &AtWA, Eigen::Matrix3d &covariance) {
    DopplerSystem &s = ws.system;
    const Eigen::Index n = s.size();
    const double sigma_d = config.doppler_sigma_mps;
    const double gate0 = config.gate_sigmas * sigma_d;
    // Each point's noise scale k_i^2 (weak returns are measured worse, directions as Doppler):
    // the ratio of its Doppler-only gate to a strong return's, set by AssignWeightsAndGates.
    ws.sort_buffer = s.gate2 / (gate0 * gate0);
    const Eigen::VectorXd &k2 = ws.sort_buffer;
    const double sa = config.sensor.azimuth_sigma_deg * kDegToRad;
    const double se = config.sensor.elevation_sigma_deg * kDegToRad;
    ws.weighted.resize(n);
    int previous = -1;
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (int round = 0; round < std::max(config.refit_iterations, 1) + 1; ++round) {
        // Gates from the total variance at the current velocity. The weights stay eq. (2)'s
        // (Doppler only): weights from the total variance would depend on the measured direction,
        // hence on its noise, and bias the fit again (measured: +0.03 m/s v_z at 12 m/s, 2 deg).
        for (Eigen::Index i = 0; i < n; ++i) {
            const double k = std::sqrt(k2[i]);
            const DirectionNoise dn = NoiseOf(s.A.row(i).transpose(), k * sa, k * se);
            const double total_var = sigma_d * sigma_d * k2[i] + v.dot(dn.C * v);
            s.gate2[i] = config.gate_sigmas * config.gate_sigmas * total_var;
        }
        const int count = ClassifyInliers(s, v, ws, ws.mask);
        M.setZero();
        AtWA.setZero();
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        for (Eigen::Index i = 0; i < n; ++i) {
            ws.weighted[i] = s.w[i] * ws.mask[i];
            if (ws.weighted[i] == 0.0) continue;
            const double k = std::sqrt(k2[i]);
            const Eigen::Vector3d d = s.A.row(i).transpose();
            const DirectionNoise dn = NoiseOf(d, k * sa, k * se);
            const Eigen::Matrix3d ddT = d * d.transpose();
            M += ws.weighted[i] * (ddT - dn.C) * dn.S_inv.asDiagonal();
            AtWA += ws.weighted[i] * ddT;
            g += ws.weighted[i] * s.b[i] * d;
        }
        const Eigen::FullPivLU<Eigen::Matrix3d> lu(M);
        if (count < 4 || !lu.isInvertible()) return false;
        const Eigen::Vector3d refit = lu.solve(g);
        if (!refit.allFinite()) return false;
        const bool settled = count == previous && (refit - v).norm() < 1e-9;
        v = refit;
        previous = count;
        if (settled) break;
    }
    // Residuals and the sandwich M^-1 (sum psi_i psi_i^T) M^-T on the final inliers, with
    // psi_i = w_i (d_i b_i - (d_i d_i^T - C_i) S_i^-1 v) (zero mean at the true v).
    ws.residual.noalias() = s.A * v;
    ws.residual -= s.b;
    Eigen::Matrix3d meat = Eigen::Matrix3d::Zero();
    int inliers = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
        if (ws.weighted[i] == 0.0) continue;
        ++inliers;
        const double k = std::sqrt(k2[i]);
        const Eigen::Vector3d d = s.A.row(i).transpose();
        const DirectionNoise dn = NoiseOf(d, k * sa, k * se);
        const Eigen::Vector3d psi =
            ws.weighted[i] * (d * s.b[i] - (d * d.transpose() - dn.C) * dn.S_inv.cwiseProduct(v));
        meat += psi * psi.transpose();
    }
    const Eigen::Matrix3d M_inv = M.inverse();
    const double small_sample = static_cast<double>(inliers) / std::max(inliers - 3, 1);
    covariance = small_sample * M_inv * meat * M_inv.transpose();
    covariance = 0.5 * (covariance + covariance.transpose()).eval();
    return covariance.allFinite();
}

}  // namespace dorado::odometry::internal
