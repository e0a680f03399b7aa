#include "dorado/odometry/ground_plane.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "dorado/core/angles.hpp"

namespace dorado::odometry {

namespace {

/// Weighted least squares of z = h + a x + b y on the points in `idx`: returns [h, a, b], the
/// normal matrix and the weighted residual sum of squares.
struct PlaneFit {
    Eigen::Vector3d theta = Eigen::Vector3d::Zero();
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    double weighted_rss = 0.0;
    bool ok = false;
};

PlaneFit WeightedPlane(const Eigen::Matrix3Xd &p, const std::vector<int> &idx,
                       const std::vector<double> &w) {
    PlaneFit fit;
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < idx.size(); ++k) {
        const Eigen::Vector3d a(1.0, p(0, idx[k]), p(1, idx[k]));
        fit.normal += w[k] * a * a.transpose();
        rhs += w[k] * a * p(2, idx[k]);
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(fit.normal);
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-10)) return fit;
    fit.theta = ldlt.solve(rhs);
    for (std::size_t k = 0; k < idx.size(); ++k) {
        const double r =
            p(2, idx[k]) - fit.theta.dot(Eigen::Vector3d(1.0, p(0, idx[k]), p(1, idx[k])));
        fit.weighted_rss += w[k] * r * r;
    }
    fit.ok = fit.theta.allFinite();
    return fit;
}

/// Distance of point i to the plane z = h + a x + b y along its normal.
double PlaneDistance(const Eigen::Vector3d &theta, const Eigen::Vector3d &p) {
    return (p.z() - theta.dot(Eigen::Vector3d(1.0, p.x(), p.y()))) /
           std::sqrt(1.0 + theta.tail<2>().squaredNorm());
}

/// 3-point RANSAC over the candidates: the plane with the most inliers within the tilt gate.
bool RansacPlane(const GroundPlaneConfig &c, const Eigen::Matrix3Xd &p,
                 const std::vector<int> &candidates, Eigen::Vector3d &best_theta) {
    std::mt19937_64 rng(c.seed);
    std::uniform_int_distribution<std::size_t> pick(0, candidates.size() - 1);
    const double max_slope = std::tan(DegToRad(c.max_tilt_deg));
    int best = 0;
    for (int it = 0; it < c.ransac_iterations; ++it) {
        const Eigen::Vector3d p0 = p.col(candidates[pick(rng)]), p1 = p.col(candidates[pick(rng)]),
                              p2 = p.col(candidates[pick(rng)]);
        Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
        if (!(std::abs(n.z()) > 1e-9)) continue;
        // n . (q - p0) = 0  =>  z = p0.z - (n_x (x - p0.x) + n_y (y - p0.y)) / n_z
        const double a = -n.x() / n.z(), b = -n.y() / n.z();
        if (std::hypot(a, b) > max_slope) continue;
        const Eigen::Vector3d theta(p0.z() - a * p0.x() - b * p0.y(), a, b);
        int count = 0;
        for (int i : candidates)
            count += std::abs(PlaneDistance(theta, p.col(i))) < c.inlier_threshold_m;
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
    std::vector<int> candidates;
    for (Eigen::Index i = 0; i < p.cols(); ++i) {
        if (static_cast<std::size_t>(i) >= use.size() || !use[static_cast<std::size_t>(i)])
            continue;
        if (!p.col(i).allFinite()) continue;
        const double s = p.col(i).head<2>().norm();
        if (s < c.min_distance_m || s > c.max_distance_m) continue;
        if (std::abs(p(2, i) + c.base_height_m) > c.height_window_m + s * tan_tilt) continue;
        candidates.push_back(static_cast<int>(i));
    }
    obs.candidates = static_cast<int>(candidates.size());
    const auto fail = [&](GroundFallback why) {
        obs.valid = false;
        obs.fallback = why;
        return obs;
    };
    if (obs.candidates < c.min_points) return fail(GroundFallback::kFewCandidates);
    Eigen::Vector3d theta;
    if (!RansacPlane(c, p, candidates, theta)) return fail(GroundFallback::kNoPlane);

    // Refit: weighted least squares on the inliers, a point's weight the inverse of its vertical
    // variance (floor + range * elevation noise); three rounds of regating at the inlier
    // threshold scaled like the point's own noise.
    const double sigma_el = DegToRad(c.elevation_sigma_deg);
    const double floor2 = 0.25 * c.inlier_threshold_m * c.inlier_threshold_m;
    PlaneFit fit;
    std::vector<int> inliers;
    std::vector<double> w;
    double scale = 1.0;  // the residuals' variance relative to the model's, from the last round
    for (int round = 0; round < 3; ++round) {
        inliers.clear();
        w.clear();
        for (int i : candidates) {
            const double r = p.col(i).norm();
            const double var = floor2 + r * r * sigma_el * sigma_el;
            const double gate = std::max(c.inlier_threshold_m, 3.0 * std::sqrt(scale * var));
            if (std::abs(PlaneDistance(theta, p.col(i))) > gate) continue;
            inliers.push_back(i);
            w.push_back(floor2 / var);
        }
        if (static_cast<int>(inliers.size()) < c.min_points) return fail(GroundFallback::kNoPlane);
        fit = WeightedPlane(p, inliers, w);
        if (!fit.ok) return fail(GroundFallback::kDegenerate);
        theta = fit.theta;
        scale = std::clamp(fit.weighted_rss / std::max<double>(1.0, inliers.size() - 3.0) / floor2,
                           0.1, 10.0);
    }
    obs.inliers = static_cast<int>(inliers.size());
    // A band of points at one distance fixes the plane's roll but hardly its pitch (the band of a
    // road steeper than the window at its near end looks like a flatter plane).
    std::vector<double> distances;
    for (int i : inliers) distances.push_back(p.col(i).head<2>().norm());
    std::sort(distances.begin(), distances.end());
    const std::size_t n = distances.size();
    if (distances[n * 95 / 100] - distances[n * 5 / 100] < c.min_depth_spread_m)
        return fail(GroundFallback::kDegenerate);
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
