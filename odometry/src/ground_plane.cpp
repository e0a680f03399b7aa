#include "dorado/odometry/ground_plane.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "dorado/core/angles.hpp"
#include "plane_inliers.hpp"

namespace dorado::odometry {

namespace {

using internal::PlaneDistance;
using internal::PlaneNormalNorm;
using internal::PlanePoints;

/// The candidates beside their columns (plane_inliers.hpp): each one's range and horizontal
/// distance from the base origin.
struct Candidates {
    PlanePoints xyz;
    std::vector<double> range, horizontal;
};

/// Weighted least squares of z = h + a x + b y on the candidates in `idx`: returns [h, a, b], the
/// normal matrix and the weighted residual sum of squares.
struct PlaneFit {
    Eigen::Vector3d theta = Eigen::Vector3d::Zero();
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    double weighted_rss = 0.0;
    bool ok = false;
};

PlaneFit WeightedPlane(const PlanePoints &p, const std::vector<int> &idx,
                       const std::vector<double> &w) {
    // sum w a a^T and sum w a z with a = (1, x, y), each term rounded as (w a_i) a_j and
    // (w a_i) z (Eigen's outer product), the sums in the points' order.
    double n00 = 0.0, n01 = 0.0, n02 = 0.0, n11 = 0.0, n12 = 0.0, n21 = 0.0, n22 = 0.0;
    double r0 = 0.0, r1 = 0.0, r2 = 0.0;
    for (std::size_t k = 0; k < idx.size(); ++k) {
        const double x = p.x[idx[k]], y = p.y[idx[k]], z = p.z[idx[k]];
        const double wk = w[k], wx = wk * x, wy = wk * y;
        n00 += wk;
        n01 += wx;
        n02 += wy;
        n11 += wx * x;
        n12 += wx * y;
        n21 += wy * x;
        n22 += wy * y;
        r0 += wk * z;
        r1 += wx * z;
        r2 += wy * z;
    }
    PlaneFit fit;
    fit.normal << n00, n01, n02, n01, n11, n12, n02, n21, n22;
    const Eigen::Vector3d rhs(r0, r1, r2);
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(fit.normal);
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-10)) return fit;
    fit.theta = ldlt.solve(rhs);
    for (std::size_t k = 0; k < idx.size(); ++k) {
        const double r = p.z[idx[k]] -
                         ((fit.theta[0] + fit.theta[1] * p.x[idx[k]]) + fit.theta[2] * p.y[idx[k]]);
        fit.weighted_rss += w[k] * r * r;
    }
    fit.ok = fit.theta.allFinite();
    return fit;
}

/// 3-point RANSAC over the candidates: the plane with the most inliers within the tilt gate.
bool RansacPlane(const GroundPlaneConfig &c, const PlanePoints &p, Eigen::Vector3d &best_theta) {
    std::mt19937_64 rng(c.seed);
    std::uniform_int_distribution<std::size_t> pick(0, p.size - 1);
    const double max_slope = std::tan(DegToRad(c.max_tilt_deg));
    const auto point = [&p](std::size_t i) { return Eigen::Vector3d(p.x[i], p.y[i], p.z[i]); };
    int best = 0;
    for (int it = 0; it < c.ransac_iterations; ++it) {
        const Eigen::Vector3d p0 = point(pick(rng)), p1 = point(pick(rng)), p2 = point(pick(rng));
        Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
        if (!(std::abs(n.z()) > 1e-9)) continue;
        // n . (q - p0) = 0  =>  z = p0.z - (n_x (x - p0.x) + n_y (y - p0.y)) / n_z
        const double a = -n.x() / n.z(), b = -n.y() / n.z();
        if (std::hypot(a, b) > max_slope) continue;
        const Eigen::Vector3d theta(p0.z() - a * p0.x() - b * p0.y(), a, b);
        const int count = internal::CountPlaneInliers(p, theta, c.inlier_threshold_m);
        if (count > best) {
            best = count;
            best_theta = theta;
        }
    }
    return best >= c.min_points;
}

}  // namespace

void GroundPlaneConfig::Validate() const {
    auto require = [](bool ok, const char *key, const char *what) {
        if (!ok) throw std::invalid_argument(std::string("ground.") + key + ": " + what);
    };
    // NaN = unknown (no observation, kNoBaseHeight); the dataset's reader checks a given one.
    require(std::isnan(base_height_m) || std::isfinite(base_height_m), "base_height_m",
            "must be finite");
    require(max_residual_sigma_m > 0.0, "max_residual_sigma_m", "must be > 0");
    require(height_window_m > 0.0, "height_window_m", "must be > 0");
    require(max_tilt_deg > 0.0 && max_tilt_deg < 60.0, "max_tilt_deg", "must be in (0, 60)");
    require(min_distance_m >= 0.0, "min_distance_m", "must be >= 0");
    require(max_distance_m > min_distance_m, "max_distance_m", "must be > min_distance_m");
    require(inlier_threshold_m > 0.0, "inlier_threshold_m", "must be > 0");
    require(ransac_iterations >= 1, "ransac_iterations", "must be >= 1");
    require(min_points >= 3, "min_points", "must be >= 3");
    require(min_depth_spread_m >= 0.0, "min_depth_spread_m", "must be >= 0");
    require(elevation_sigma_deg >= 0.0, "elevation_sigma_deg", "must be >= 0");
}

const char *ToString(GroundFallback reason) {
    switch (reason) {
        case GroundFallback::kNone:
            return "";
        case GroundFallback::kFewCandidates:
            return "few_ground_points";
        case GroundFallback::kNoPlane:
            return "no_plane";
        case GroundFallback::kTilted:
            return "tilted";
        case GroundFallback::kHeightMismatch:
            return "height_mismatch";
        case GroundFallback::kDegenerate:
            return "degenerate";
        case GroundFallback::kNoVelocity:
            return "no_velocity";
        case GroundFallback::kUneven:
            return "uneven";
        case GroundFallback::kInconsistent:
            return "inconsistent";
        case GroundFallback::kNoBaseHeight:
            return "no_base_height";
    }
    return "?";
}

Eigen::Vector2d RollPitchFromSlope(const Eigen::Vector2d &slope, Eigen::Matrix2d *jacobian) {
    const double a = slope.x(), b = slope.y();
    const double q = std::sqrt(1.0 + b * b), s = a * a + 1.0 + b * b;
    // normal ~ (-a, -b, 1): roll = atan2(n_y, n_z), pitch = atan2(-n_x, hypot(n_y, n_z)).
    if (jacobian) {
        *jacobian << 0.0, -1.0 / (1.0 + b * b),  //
            q / s, -a * b / (s * q);
    }
    return {std::atan2(-b, 1.0), std::atan2(a, q)};
}

GroundObservation FitGroundPlane(const GroundPlaneConfig &c, const Eigen::Matrix3Xd &p,
                                 const std::vector<bool> &use) {
    GroundObservation obs;
    if (!std::isfinite(c.base_height_m)) {
        obs.fallback = GroundFallback::kNoBaseHeight;
        return obs;
    }
    const double tan_tilt = std::tan(DegToRad(c.max_tilt_deg));
    Candidates candidates;
    candidates.xyz.Reserve(static_cast<std::size_t>(p.cols()));
    candidates.range.reserve(static_cast<std::size_t>(p.cols()));
    candidates.horizontal.reserve(static_cast<std::size_t>(p.cols()));
    for (Eigen::Index i = 0; i < p.cols(); ++i) {
        if (static_cast<std::size_t>(i) >= use.size() || !use[static_cast<std::size_t>(i)])
            continue;
        if (!p.col(i).allFinite()) continue;
        const double s = p.col(i).head<2>().norm();
        if (s < c.min_distance_m || s > c.max_distance_m) continue;
        if (std::abs(p(2, i) + c.base_height_m) > c.height_window_m + s * tan_tilt) continue;
        candidates.xyz.Add(p(0, i), p(1, i), p(2, i));
        candidates.range.push_back(p.col(i).norm());
        candidates.horizontal.push_back(s);
    }
    candidates.xyz.Pad();
    const PlanePoints &xyz = candidates.xyz;
    obs.candidates = static_cast<int>(xyz.size);
    const auto fail = [&](GroundFallback why) {
        obs.valid = false;
        obs.fallback = why;
        return obs;
    };
    if (obs.candidates < c.min_points) return fail(GroundFallback::kFewCandidates);
    Eigen::Vector3d theta;
    if (!RansacPlane(c, xyz, theta)) return fail(GroundFallback::kNoPlane);

    // Refit: weighted least squares on the inliers, a point's weight the inverse of its vertical
    // variance (floor + range * elevation noise); three rounds of regating at the inlier
    // threshold scaled like the point's own noise.
    const double sigma_el = DegToRad(c.elevation_sigma_deg);
    const double floor2 = 0.25 * c.inlier_threshold_m * c.inlier_threshold_m;
    std::vector<double> variance(xyz.size);
    for (std::size_t k = 0; k < xyz.size; ++k) {
        const double r = candidates.range[k];
        variance[k] = floor2 + r * r * sigma_el * sigma_el;
    }
    PlaneFit fit;
    std::vector<int> inliers;
    std::vector<double> w;
    inliers.reserve(xyz.size);
    w.reserve(xyz.size);
    double scale = 1.0;  // the residuals' variance relative to the model's, from the last round
    for (int round = 0; round < 3; ++round) {
        inliers.clear();
        w.clear();
        const double norm = PlaneNormalNorm(theta);
        for (std::size_t k = 0; k < xyz.size; ++k) {
            const double var = variance[k];
            const double gate = std::max(c.inlier_threshold_m, 3.0 * std::sqrt(scale * var));
            if (std::abs(PlaneDistance(theta, norm, xyz.x[k], xyz.y[k], xyz.z[k])) > gate) continue;
            inliers.push_back(static_cast<int>(k));
            w.push_back(floor2 / var);
        }
        if (static_cast<int>(inliers.size()) < c.min_points) return fail(GroundFallback::kNoPlane);
        fit = WeightedPlane(xyz, inliers, w);
        if (!fit.ok) return fail(GroundFallback::kDegenerate);
        theta = fit.theta;
        scale = std::clamp(fit.weighted_rss / std::max<double>(1.0, inliers.size() - 3.0) / floor2,
                           0.1, 10.0);
    }
    obs.inliers = static_cast<int>(inliers.size());
    // A band of points at one distance fixes the plane's roll but hardly its pitch (the band of a
    // road steeper than the window at its near end looks like a flatter plane): the 5th and 95th
    // percentiles of the inliers' horizontal distances.
    std::vector<double> distances;
    distances.reserve(inliers.size());
    for (int k : inliers) distances.push_back(candidates.horizontal[static_cast<std::size_t>(k)]);
    const std::size_t n = distances.size();
    const auto at = [&distances](std::size_t rank) {
        std::nth_element(distances.begin(), distances.begin() + rank, distances.end());
        return distances[rank];
    };
    const double near = at(n * 5 / 100), far = at(n * 95 / 100);
    if (far - near < c.min_depth_spread_m) return fail(GroundFallback::kDegenerate);
    obs.height_m = theta.x();
    obs.slope = theta.tail<2>();
    if (obs.slope.norm() > tan_tilt) return fail(GroundFallback::kTilted);
    if (std::abs(obs.height_m + c.base_height_m) > c.height_window_m)
        return fail(GroundFallback::kHeightMismatch);
    // Covariance of [h, a, b]: the residual-scaled inverse normal matrix (eq. 6's form; the
    // weights carry the relative variances, the residuals their scale).
    const double dof = std::max(1, obs.inliers - 3);
    const double sigma2 = fit.weighted_rss / dof;
    const Eigen::Matrix3d cov_theta = sigma2 * fit.normal.inverse();
    Eigen::Matrix2d J;
    obs.roll_pitch_rad = RollPitchFromSlope(obs.slope, &J);
    obs.cov_roll_pitch = J * cov_theta.bottomRightCorner<2, 2>() * J.transpose();
    obs.residual_sigma_m = std::sqrt(sigma2);
    if (!obs.cov_roll_pitch.allFinite()) return fail(GroundFallback::kDegenerate);
    if (obs.residual_sigma_m > c.max_residual_sigma_m) return fail(GroundFallback::kUneven);
    obs.valid = true;
    return obs;
}

}  // namespace dorado::odometry
