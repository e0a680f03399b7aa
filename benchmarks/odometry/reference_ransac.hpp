#pragma once
// The paper's reference ego-velocity algorithm (section III-A; the public doppler_odometry node
// runs a plain RANSAC), re-implemented here as the speed and accuracy baseline: a fixed number of
// iterations, each solving eq. (1) exactly on a minimal sample of 3 points and counting the
// outliers (|d_i . v + doppler_i| > threshold) over ALL points; the velocity is the best sample's
// solution, with no refit on its inliers, no weights and no pre-filter beyond finite values.
// (The public node draws 6 points and solves them by least squares; the issue asks for minimal
// samples, which is what this does. Both have no refit.)

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <random>

#include "dorado/core/radar_scan.hpp"

namespace dorado::benchmarks {

struct ReferenceRansacOptions {
    int iterations = 100;
    double threshold_mps = 0.15;  ///< the inlier gate (dorado's: 3 x 0.05 m/s)
    uint64_t seed = 42;
};

/// Buffers kept across scans (the reference code builds a std::vector<Vector4d> per scan; so does
/// this, into a reused buffer).
struct ReferenceRansac {
    ReferenceRansacOptions options;
    Eigen::Matrix<double, Eigen::Dynamic, 3> A;
    Eigen::VectorXd b;

    /// The radar velocity; false when no sample was solvable.
    bool Estimate(const RadarScan &scan, Eigen::Vector3d &v_radar) {
        const Eigen::Index N = scan.size();
        A.resize(N, 3);
        b.resize(N);
        Eigen::Index n = 0;
        for (Eigen::Index i = 0; i < N; ++i) {
            const Eigen::Vector3d p = scan.xyz_radar.col(i);
            const double range = p.norm();
            if (!(range > 0.0) || !std::isfinite(scan.doppler_mps[i])) continue;
            A.row(n) = p.transpose() / range;
            b[n++] = -scan.doppler_mps[i];
        }
        if (n < 3) return false;
        std::mt19937 rng(static_cast<std::mt19937::result_type>(options.seed));
        std::uniform_int_distribution<Eigen::Index> pick(0, n - 1);
        Eigen::Index best_outliers = n + 1;
        for (int it = 0; it < options.iterations; ++it) {
            Eigen::Index s[3] = {pick(rng), pick(rng), pick(rng)};
            while (s[1] == s[0]) s[1] = pick(rng);
            while (s[2] == s[0] || s[2] == s[1]) s[2] = pick(rng);
            Eigen::Matrix3d M;
            for (int k = 0; k < 3; ++k) M.row(k) = A.row(s[k]);
            const Eigen::Vector3d v =
                M.partialPivLu().solve(Eigen::Vector3d(b[s[0]], b[s[1]], b[s[2]]));
            if (!v.allFinite()) continue;
            Eigen::Index outliers = 0;
            for (Eigen::Index i = 0; i < n; ++i)
                outliers += std::abs(A.row(i).dot(v) - b[i]) > options.threshold_mps;
            if (outliers < best_outliers) {
                best_outliers = outliers;
                v_radar = v;
            }
        }
        return best_outliers <= n;
    }
};

}  // namespace dorado::benchmarks
