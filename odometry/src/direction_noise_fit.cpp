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

#include "dorado/core/angles.hpp"
#include "robust_fit.hpp"
#include "simd4.hpp"

namespace dorado::odometry::internal {
namespace {

// Columns of ws.direction_noise, one row per point: its noise scale k^2, the covariance C of its
// measured direction (upper triangle) and the diagonal of S^-1 (x and y share one value).
enum Column { kK2, kCxx, kCxy, kCxz, kCyy, kCyz, kCzz, kSinvH, kSinvV, kColumns };

// The direction-noise terms depend on the point alone: computed once per scan (the rounds below
// only re-weight them), as columns that the rounds' loops read in order.
void ComputeDirectionNoise(const DopplerSystem &s, double k2_scale, double sigma_az,
                           double sigma_el, Eigen::ArrayXXd &out) {
    const Eigen::Index n = s.size();
    out.resize(n, kColumns);
    const double se2 = sigma_el * sigma_el, sa2 = sigma_az * sigma_az;
    for (Eigen::Index i = 0; i < n; ++i) {
        const double dx = s.A(i, 0), dy = s.A(i, 1), dz = s.A(i, 2);
        const double cos_el = std::sqrt(dx * dx + dy * dy), sin_el = dz;  // d is a unit vector
        const double cos_az = cos_el > 1e-12 ? dx / cos_el : 1.0;
        const double sin_az = cos_el > 1e-12 ? dy / cos_el : 0.0;
        // e_el = (-sin_el cos_az, -sin_el sin_az, cos_el), e_az = (-sin_az, cos_az, 0).
        const double ex = -sin_el * cos_az, ey = -sin_el * sin_az, ez = cos_el;
        const double ax = -sin_az, ay = cos_az;
        const double k2 = s.gate2[i] * k2_scale;
        const double e = k2 * se2, a = k2 * sa2 * cos_el * cos_el;
        out(i, kK2) = k2;
        out(i, kCxx) = e * ex * ex + a * ax * ax;
        out(i, kCxy) = e * ex * ey + a * ax * ay;
        out(i, kCxz) = e * ex * ez;
        out(i, kCyy) = e * ey * ey + a * ay * ay;
        out(i, kCyz) = e * ey * ez;
        out(i, kCzz) = e * ez * ez;
        out(i, kSinvH) = std::exp(0.5 * (k2 * se2 + k2 * sa2));
        out(i, kSinvV) = std::exp(0.5 * k2 * se2);
    }
}

// The estimating equation's matrix M = sum_i w_i (d_i d_i^T - C_i) S_i^-1, A^T W A and A^T W b
// over `weighted`, in one pass, 4 points at a time (simd4.hpp; the last < 4 points padded with
// zero weights).
DORADO_SIMD_CLONES
void AccumulateRound(const DopplerSystem &s, const Eigen::ArrayXXd &dn,
                     const Eigen::VectorXd &weighted, Eigen::Matrix3d &M, Eigen::Matrix3d &AtWA,
                     Eigen::Vector3d &g) {
    using simd::Load;
    using simd::Sum;
    using simd::Vec4;
    constexpr int kIn = 13;  // d x, y, z, b, w, C (6), S^-1 (h, v)
    const Eigen::Index n = s.size();
    const double *in[kIn] = {s.A.col(0).data(),    s.A.col(1).data(),   s.A.col(2).data(),
                             s.b.data(),           weighted.data(),     dn.col(kCxx).data(),
                             dn.col(kCxy).data(),  dn.col(kCxz).data(), dn.col(kCyy).data(),
                             dn.col(kCyz).data(),  dn.col(kCzz).data(), dn.col(kSinvH).data(),
                             dn.col(kSinvV).data()};
    // H = sum w h (dd^T - C) gives M's columns x and y, V = sum w v (dd^T - C) its column z.
    Vec4 hxx{}, hxy{}, hxz{}, hyy{}, hyz{}, vxz{}, vyz{}, vzz{};
    Vec4 axx{}, axy{}, axz{}, ayy{}, ayz{}, azz{}, gx{}, gy{}, gz{};
    double tail[kIn][simd::kLanes] = {};
    for (Eigen::Index i = 0; i < n; i += simd::kLanes) {
        Vec4 x[kIn];
        if (i + simd::kLanes <= n) {
            for (int c = 0; c < kIn; ++c) x[c] = Load(in[c] + i);
        } else {  // zero weight in the padding lanes: they add nothing
            for (int c = 0; c < kIn; ++c)
                for (Eigen::Index l = 0; l < n - i; ++l) tail[c][l] = in[c][i + l];
            for (int c = 0; c < kIn; ++c) x[c] = Load(tail[c]);
        }
        const Vec4 dx = x[0], dy = x[1], dz = x[2], w = x[4];
        const Vec4 wh = w * x[11], wv = w * x[12];
        const Vec4 pxx = dx * dx - x[5], pxy = dx * dy - x[6], pxz = dx * dz - x[7];
        const Vec4 pyy = dy * dy - x[8], pyz = dy * dz - x[9], pzz = dz * dz - x[10];
        hxx += wh * pxx, hxy += wh * pxy, hxz += wh * pxz, hyy += wh * pyy, hyz += wh * pyz;
        vxz += wv * pxz, vyz += wv * pyz, vzz += wv * pzz;
        const Vec4 wx = w * dx, wy = w * dy, wz = w * dz;
        axx += wx * dx, axy += wx * dy, axz += wx * dz;
        ayy += wy * dy, ayz += wy * dz, azz += wz * dz;
        gx += wx * x[3], gy += wy * x[3], gz += wz * x[3];
    }
    M << Sum(hxx), Sum(hxy), Sum(vxz),  //
        Sum(hxy), Sum(hyy), Sum(vyz),   //
        Sum(hxz), Sum(hyz), Sum(vzz);
    AtWA << Sum(axx), Sum(axy), Sum(axz), Sum(axy), Sum(ayy), Sum(ayz), Sum(axz), Sum(ayz),
        Sum(azz);
    g << Sum(gx), Sum(gy), Sum(gz);
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
    Eigen::ArrayXXd &dn = ws.direction_noise;
    ComputeDirectionNoise(s, 1.0 / (gate0 * gate0), DegToRad(config.sensor.azimuth_sigma_deg),
                          DegToRad(config.sensor.elevation_sigma_deg), dn);
    ws.weighted.resize(n);
    int previous = -1;
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    const double gate_scale = config.gate_sigmas * config.gate_sigmas;
    for (int round = 0; round < std::max(config.refit_iterations, 1) + 1; ++round) {
        // Gates from the total variance at the current velocity, sigma_d^2 k^2 + v^T C v. The
        // weights stay eq. (2)'s (Doppler only): weights from the total variance would depend on
        // the measured direction, hence on its noise, and bias the fit again (measured: +0.03 m/s
        // v_z at 12 m/s, 2 deg).
        const double xx = v.x() * v.x(), yy = v.y() * v.y(), zz = v.z() * v.z();
        const double xy = 2.0 * v.x() * v.y(), xz = 2.0 * v.x() * v.z(), yz = 2.0 * v.y() * v.z();
        s.gate2 = gate_scale *
                  (sigma_d * sigma_d * dn.col(kK2) + xx * dn.col(kCxx) + yy * dn.col(kCyy) +
                   zz * dn.col(kCzz) + xy * dn.col(kCxy) + xz * dn.col(kCxz) + yz * dn.col(kCyz))
                      .matrix();
        const int count = ClassifyInliers(s, v, ws, ws.mask);
        ws.weighted = s.w.cwiseProduct(ws.mask);
        Eigen::Vector3d g;
        AccumulateRound(s, dn, ws.weighted, M, AtWA, g);
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
    double mxx = 0, mxy = 0, mxz = 0, myy = 0, myz = 0, mzz = 0;
    int inliers = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
        const double w = ws.weighted[i];
        if (w == 0.0) continue;
        ++inliers;
        const double dx = s.A(i, 0), dy = s.A(i, 1), dz = s.A(i, 2);
        // u = S^-1 v; (d d^T - C) u = d (d . u) - C u.
        const double ux = dn(i, kSinvH) * v.x(), uy = dn(i, kSinvH) * v.y();
        const double uz = dn(i, kSinvV) * v.z();
        const double du = dx * ux + dy * uy + dz * uz;
        const double cx = dn(i, kCxx) * ux + dn(i, kCxy) * uy + dn(i, kCxz) * uz;
        const double cy = dn(i, kCxy) * ux + dn(i, kCyy) * uy + dn(i, kCyz) * uz;
        const double cz = dn(i, kCxz) * ux + dn(i, kCyz) * uy + dn(i, kCzz) * uz;
        const double px = w * (dx * s.b[i] - (dx * du - cx));
        const double py = w * (dy * s.b[i] - (dy * du - cy));
        const double pz = w * (dz * s.b[i] - (dz * du - cz));
        mxx += px * px, mxy += px * py, mxz += px * pz;
        myy += py * py, myz += py * pz, mzz += pz * pz;
    }
    Eigen::Matrix3d meat;
    meat << mxx, mxy, mxz, mxy, myy, myz, mxz, myz, mzz;
    const Eigen::Matrix3d M_inv = M.inverse();
    const double small_sample = static_cast<double>(inliers) / std::max(inliers - 3, 1);
    covariance = small_sample * M_inv * meat * M_inv.transpose();
    covariance = 0.5 * (covariance + covariance.transpose()).eval();
    return covariance.allFinite();
}

}  // namespace dorado::odometry::internal
