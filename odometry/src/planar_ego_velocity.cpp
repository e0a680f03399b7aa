// The ego-velocity of a 2D radar (paper section III-A in the radar's plane): pre-filters,
// eq. (2) weights, 2-point RANSAC, refit, eq. (6) covariance in 2-D, validity.
#include "dorado/odometry/planar_ego_velocity.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "dorado/core/angles.hpp"
#include "validity.hpp"
#include "weights_and_gates.hpp"

namespace dorado::odometry {
namespace {

// Eq. (1) in the plane for every point that passed the pre-filters: d_i . v = b_i = -doppler_i.
struct PlanarSystem {
    std::vector<Eigen::Vector2d> d;
    std::vector<double> b, w, gate2;
    std::vector<int> cell;            // azimuth cell, for spread-aware scoring
    std::vector<Eigen::Index> input;  // index of the point in the scan
    [[nodiscard]] std::size_t size() const { return b.size(); }
};

PlanarSystem BuildSystem(const EgoVelocityConfig &c, const RadarScan &scan,
                         std::vector<PointLabel> &labels) {
    PlanarSystem s;
    const Eigen::Index N = scan.size();
    const bool has_power = scan.power_db.size() == N;
    const bool has_doppler = scan.doppler_mps.size() == N;
    const int cells = c.score_cells_azimuth;
    for (Eigen::Index i = 0; i < N && has_doppler; ++i) {
        const Eigen::Vector3d p = scan.xyz_radar.col(i);
        const double power = has_power ? scan.power_db[i] : 0.0;
        const double doppler = scan.doppler_mps[i];
        if (!p.allFinite() || !std::isfinite(doppler) || !std::isfinite(power)) continue;
        const double range = p.norm(), planar_range = std::hypot(p.x(), p.y());
        if (range < c.min_range_m || range > c.max_range_m || !(planar_range > 0.0)) continue;
        if (power < c.min_power_db) continue;
        const double az = std::atan2(p.y(), p.x());
        if (az < DegToRad(c.min_azimuth_deg) || az > DegToRad(c.max_azimuth_deg)) continue;
        s.d.emplace_back(p.x() / planar_range, p.y() / planar_range);
        s.b.push_back(-doppler);  // eq. (1): -doppler_i = d_i . v_radar
        s.w.push_back(power);
        s.cell.push_back(
            std::clamp(static_cast<int>((az + M_PI) / (2.0 * M_PI) * cells), 0, cells - 1));
        s.input.push_back(i);
        labels[i] = PointLabel::kDynamic;  // until proven static
    }
    return s;
}

// eq. (2) on the mask: v = (sum w d d^T)^-1 sum w d b. False when the directions are parallel.
bool Solve(const PlanarSystem &s, const std::vector<char> &mask, Eigen::Vector2d &v,
           Eigen::Matrix2d &H) {
    H.setZero();
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (!mask[i]) continue;
        H += s.w[i] * s.d[i] * s.d[i].transpose();
        g += s.w[i] * s.b[i] * s.d[i];
    }
    const double trace = H.trace();
    if (!(trace > 0.0) || !(H.determinant() > 1e-12 * trace * trace)) return false;
    v = H.inverse() * g;
    return v.allFinite();
}

// Marks the points within their gate of v; returns the spread-aware score (sum over azimuth
// cells of sqrt(inliers in the cell)) and the inlier count.
double Classify(const PlanarSystem &s, const Eigen::Vector2d &v, int cells, std::vector<char> &mask,
                int &inliers) {
    std::vector<int> per_cell(cells, 0);
    inliers = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const double r = s.d[i].dot(v) - s.b[i];
        mask[i] = r * r <= s.gate2[i];
        if (mask[i]) {
            ++inliers;
            ++per_cell[s.cell[i]];
        }
    }
    double score = 0.0;
    for (int count : per_cell) score += std::sqrt(static_cast<double>(count));
    return score;
}

// 2-point RANSAC: each hypothesis solves two points' eq. (1) exactly; the best by spread-aware
// score is refit and regated refit_iterations times. Leaves the final inliers in `mask`.
bool Ransac(const EgoVelocityConfig &c, const PlanarSystem &s, std::vector<char> &mask,
            int &iterations) {
    const int n = static_cast<int>(s.size());
    std::mt19937_64 rng(c.seed);
    std::uniform_int_distribution<int> pick(0, n - 1);
    std::vector<char> trial(s.size());
    double best_score = -1.0;
    Eigen::Vector2d best = Eigen::Vector2d::Zero();
    int needed = c.ransac_max_iterations;
    const double min_sin = std::sin(DegToRad(2.0));  // reject near-parallel pairs
    for (iterations = 0; iterations < std::max(needed, c.ransac_min_iterations); ++iterations) {
        const int i = pick(rng), j = pick(rng);
        Eigen::Matrix2d D;
        D << s.d[i].transpose(), s.d[j].transpose();
        if (i == j || std::abs(D.determinant()) < min_sin) continue;
        const Eigen::Vector2d v = D.inverse() * Eigen::Vector2d(s.b[i], s.b[j]);
        if (!(v.norm() <= c.max_speed_mps)) continue;
        int inliers = 0;
        const double score = Classify(s, v, c.score_cells_azimuth, trial, inliers);
        if (score <= best_score) continue;
        best_score = score;
        best = v;
        const double eps = std::clamp(static_cast<double>(inliers) / n, 1e-3, 1.0 - 1e-9);
        const double k = std::log(1.0 - c.ransac_success_probability) / std::log(1.0 - eps * eps);
        needed = static_cast<int>(std::min<double>(std::ceil(k), c.ransac_max_iterations));
    }
    if (best_score < 0.0) return false;
    int inliers = 0;
    Classify(s, best, c.score_cells_azimuth, mask, inliers);
    for (int round = 0; round < c.refit_iterations; ++round) {
        Eigen::Vector2d v;
        Eigen::Matrix2d H;
        if (inliers < 2 || !Solve(s, mask, v, H)) break;
        Classify(s, v, c.score_cells_azimuth, mask, inliers);
    }
    return true;
}

}  // namespace

bool IsPlanarScan(const RadarScan &scan_radar) {
    return scan_radar.size() >= 3 && (scan_radar.xyz_radar.row(2).array() == 0.0).all();
}

PlanarEgoVelocityEstimator::PlanarEgoVelocityEstimator(EgoVelocityConfig config)
    : config_(std::move(config)) {
    config_.Validate();
}

EgoVelocityResult PlanarEgoVelocityEstimator::Estimate(const RadarScan &scan_radar) const {
    const EgoVelocityConfig &c = config_;
    EgoVelocityResult result;
    result.labels.assign(scan_radar.size(), PointLabel::kFiltered);
    if (scan_radar.empty()) {
        result.failure = EgoVelocityFailure::kEmptyScan;
        return result;
    }
    PlanarSystem s = BuildSystem(c, scan_radar, result.labels);
    const int n = static_cast<int>(s.size());
    result.points_used = n;
    if (n < c.min_points) {
        result.failure = EgoVelocityFailure::kTooFewPoints;
        result.failure_detail = std::to_string(n) + " < min_points " + std::to_string(c.min_points);
        return result;
    }
    s.gate2.resize(s.size());
    internal::AssignWeightsAndGates(
        c, scan_radar.has_power,
        Eigen::Map<Eigen::VectorXd>(s.w.data(), static_cast<Eigen::Index>(s.size())),
        Eigen::Map<Eigen::VectorXd>(s.gate2.data(), static_cast<Eigen::Index>(s.size())));
    std::vector<char> mask(s.size(), 1);
    bool solved = true;
    if (c.method == RobustMethod::kNone)
        result.iterations = 1;
    else
        solved = Ransac(c, s, mask, result.iterations);
    // The final fit on the final inliers, so that v and its covariance describe the same points.
    Eigen::Vector2d v;
    Eigen::Matrix2d H;
    if (!solved || !Solve(s, mask, v, H)) {
        result.failure = EgoVelocityFailure::kDegenerateGeometry;
        result.failure_detail = "the point directions do not span the plane";
        return result;
    }
    double rWr = 0.0;
    Eigen::Matrix2d meat = Eigen::Matrix2d::Zero();
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (!mask[i]) continue;
        ++result.inliers;
        result.labels[s.input[i]] = PointLabel::kStatic;
        const double r = s.d[i].dot(v) - s.b[i];
        rWr += s.w[i] * r * r;
        meat += (s.w[i] * r) * (s.w[i] * r) * s.d[i] * s.d[i].transpose();
    }
    const double dof = std::max(result.inliers - 2, 1);
    const Eigen::Matrix2d H_inv = H.inverse();
    const double gate_factor =
        c.method == RobustMethod::kNone ? 1.0 : internal::GateConsistencyFactor(c.gate_sigmas);
    // eq. (6) in 2-D, or the sandwich form (honest whatever the weights).
    const Eigen::Matrix2d cov =
        c.covariance == CovarianceModel::kResidualScaled
            ? Eigen::Matrix2d(gate_factor * rWr / dof * H_inv)
            : Eigen::Matrix2d(gate_factor * (result.inliers / dof) * H_inv * meat * H_inv);
    result.residual_sigma_mps = std::sqrt(rWr / dof);
    result.v_radar_mps << v, 0.0;
    result.cov_v_radar.topLeftCorner<2, 2>() = cov;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(H, Eigen::EigenvaluesOnly);
    result.condition_number = eig.eigenvalues()[0] > 0.0
                                  ? std::sqrt(eig.eigenvalues()[1] / eig.eigenvalues()[0])
                                  : std::numeric_limits<double>::infinity();
    result.stationary = v.norm() < c.stationary_speed_mps;

    internal::Invalidity invalidity =
        internal::CheckValidity(c, result.inliers, static_cast<long>(n), result.condition_number,
                                v.allFinite() && cov.allFinite(), v.norm());
    result.failure = invalidity.failure;
    result.failure_detail = std::move(invalidity.detail);
    return result;
}

}  // namespace dorado::odometry
