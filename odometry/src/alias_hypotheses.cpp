// The minimal RANSAC model when the Doppler is aliased (known modulo span = 2 v_unamb): each of
// the three sampled equations d_i . v = b_i + k_i span has its own unknown wrap k_i. The
// 27 wraps k in {-1, 0, 1}^3 give 27 velocities v_k = v_0 + span M^-1 k (one solve and three
// columns); each is pre-scored on a fixed stride of 32 points (wrapped residuals), and the best
// one below max_speed_mps is the hypothesis. Without this, a sample of aliased returns (the
// returns straight ahead at speed) yields a wrong velocity, and clean samples come only from the
// returns at the side, whose directions are nearly coplanar.
#include <Eigen/LU>
#include <cmath>

#include "robust_fit.hpp"

namespace dorado::odometry::internal {

bool SolveMinimalAliased(const DopplerSystem &s, Eigen::Index i, Eigen::Index j, Eigen::Index k,
                         double max_speed_mps, Eigen::Vector3d &v) {
    constexpr double kMinSampleVolume = 1e-4;  // as the unaliased minimal solver
    Eigen::Matrix3d M;
    M.row(0) = s.A.row(i);
    M.row(1) = s.A.row(j);
    M.row(2) = s.A.row(k);
    if (std::abs(M.determinant()) < kMinSampleVolume) return false;
    const Eigen::Matrix3d M_inv = M.inverse();
    const Eigen::Vector3d v0 = M_inv * Eigen::Vector3d(s.b[i], s.b[j], s.b[k]);
    const Eigen::Matrix3d step = s.alias_span * M_inv;
    const Eigen::Index n = s.size();
    const Eigen::Index stride = std::max<Eigen::Index>(1, n / 32);
    double best = -1.0;
    for (int code = 0; code < 27; ++code) {
        const Eigen::Vector3d wraps(code % 3 - 1, (code / 3) % 3 - 1, code / 9 - 1);
        const Eigen::Vector3d candidate = v0 + step * wraps;
        if (!(candidate.norm() <= max_speed_mps)) continue;
        double score = 0.0;
        for (Eigen::Index p = 0; p < n; p += stride) {
            double r = s.A.row(p).dot(candidate) - s.b[p];
            r -= s.alias_span * std::round(r / s.alias_span);
            const double q = 1.0 - r * r / s.gate2[p];
            if (q > 0.0) score += q;
        }
        if (score > best) {
            best = score;
            v = candidate;
        }
    }
    return best >= 0.0 && v.allFinite();
}

}  // namespace dorado::odometry::internal
