// Sensor ego-velocity from one scan (paper section III-A): pre-filters, weights, robust fit,
// covariance, validity.
#include "dorado/odometry/ego_velocity.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "dorado/core/angles.hpp"
#include "dorado/core/require.hpp"
#include "robust_fit.hpp"
#include "simd4.hpp"
#include "validity.hpp"
#include "weights_and_gates.hpp"

namespace dorado::odometry {
namespace {

// The pre-filter's per-point arithmetic for every point, in place: row i of s.A = d_i (or NaNs),
// b_i = -doppler_i, w_i = power_i, keep_i = 1 where the range, power and finiteness checks pass.
// A branch-free loop the compiler vectorises (both clones; this file is compiled with
// -fno-math-errno so that sqrt is the vector instruction); the angle checks are separate.
DORADO_SIMD_CLONES void DirectionsAndChecks(Eigen::Index N, const double *xyz,
                                            const double *doppler, const double *power,
                                            double min_range, double max_range, double min_power,
                                            double *dx, double *dy, double *dz, double *b,
                                            double *w, double *keep) {
    for (Eigen::Index i = 0; i < N; ++i) {
        const double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
        const double range = std::sqrt(x * x + y * y + z * z);
        const double p = power[i];
        // Comparisons are false for NaN: a non-finite coordinate makes range NaN or inf.
        constexpr double kInf = std::numeric_limits<double>::infinity();
        const bool ok = (range >= min_range) & (range <= max_range) & (range > 0.0) &
                        (range < kInf) & (p >= min_power) & (std::abs(p) < kInf) &
                        (std::abs(doppler[i]) < kInf);
        keep[i] = ok ? 1.0 : 0.0;
        dx[i] = x / range;
        dy[i] = y / range;
        dz[i] = z / range;
        b[i] = -doppler[i];  // eq. (1): -doppler_i = d_i . v_radar
        w[i] = p;
    }
}

// Pre-filters every point and builds eq. (1) for those that pass. Labels the rest kFiltered.
void BuildSystem(const EgoVelocityConfig &config, const RadarScan &scan, internal::Workspace &ws,
                 std::vector<PointLabel> &labels) {
    const Eigen::Index N = scan.size();
    const bool check_azimuth = config.min_azimuth_deg > -180.0 || config.max_azimuth_deg < 180.0;
    const bool check_elevation =
        config.min_elevation_deg > -90.0 || config.max_elevation_deg < 90.0;
    internal::DopplerSystem &s = ws.system;
    s.Resize(N);
    ws.used_to_input.resize(N);
    ws.keep.resize(static_cast<std::size_t>(N));
    // Missing power or Doppler columns: zeros (power) and NaN (Doppler, every point filtered).
    const double *power = scan.power_db.data(), *doppler = scan.doppler_mps.data();
    if (scan.power_db.size() != N) power = ws.zeros.setZero(N).data();
    if (scan.doppler_mps.size() != N) doppler = ws.nans.setConstant(N, NAN).data();
    DirectionsAndChecks(N, scan.xyz_radar.data(), doppler, power, config.min_range_m,
                        config.max_range_m, config.min_power_db, s.A.col(0).data(),
                        s.A.col(1).data(), s.A.col(2).data(), s.b.data(), s.w.data(),
                        ws.keep.data());
    // Compaction: row n <= i, so moving rows down in place is safe.
    Eigen::Index n = 0;
    for (Eigen::Index i = 0; i < N; ++i) {
        if (!(ws.keep[i] > 0.0)) continue;
        const Eigen::Vector3d p = scan.xyz_radar.col(i);
        if (check_azimuth) {
            const double az = std::atan2(p.y(), p.x());
            if (az < DegToRad(config.min_azimuth_deg) || az > DegToRad(config.max_azimuth_deg))
                continue;
        }
        if (check_elevation) {
            const double el = std::asin(p.z() / p.norm());
            if (el < DegToRad(config.min_elevation_deg) || el > DegToRad(config.max_elevation_deg))
                continue;
        }
        if (n != i) {
            s.A.row(n) = s.A.row(i);
            s.b[n] = s.b[i];
            s.w[n] = s.w[i];
        }
        ws.used_to_input[n] = i;
        labels[i] = PointLabel::kDynamic;  // until proven static
        ++n;
    }
    s.alias_span = 2.0 * config.sensor.doppler_unambiguous_mps;
    ws.subset.alias_span = s.alias_span;
    // Shrinking keeps the first n rows of every column (conservativeResize).
    s.A.conservativeResize(n, 3);
    s.b.conservativeResize(n);
    s.w.conservativeResize(n);
    s.gate2.conservativeResize(n);
    s.cell.conservativeResize(n);
    ws.used_to_input.resize(n);
}

// Covariance of v (eq. 6 or the sandwich form) on the inliers; residuals in ws.residual.
Eigen::Matrix3d Covariance(const EgoVelocityConfig &config, internal::Workspace &ws,
                           const Eigen::Matrix3d &AtWA, int inliers, double &residual_sigma) {
    const internal::DopplerSystem &s = ws.system;
    const Eigen::Matrix3d H_inv = AtWA.inverse();
    const double dof = std::max(inliers - 3, 1);
    // ws.weighted = w_i * mask_i from the last SolveWeighted on the same mask; one pass gives
    // rWr and the sandwich's meat sum (w_i r_i)^2 d_i d_i^T.
    double rWr = 0.0;
    const Eigen::Matrix3d meat = internal::ResidualMoments(s, ws.weighted, ws.residual, rWr).AtWA();
    residual_sigma = std::sqrt(rWr / dof);
    const double gate_factor = config.method == RobustMethod::kRansac
                                   ? internal::GateConsistencyFactor(config.gate_sigmas)
                                   : 1.0;
    if (config.covariance == CovarianceModel::kResidualScaled)
        return gate_factor * rWr / dof * H_inv;
    // Sandwich: H^-1 (sum (w_i r_i)^2 d_i d_i^T) H^-1, small-sample factor N / (N - 3).
    return gate_factor * (static_cast<double>(inliers) / dof) * H_inv * meat * H_inv;
}

}  // namespace

void EgoVelocityConfig::Validate() const {
    Require(min_range_m >= 0.0, "ego_velocity.min_range_m", "must be >= 0");
    Require(max_range_m > min_range_m, "ego_velocity.max_range_m", "must be > min_range_m");
    Require(
        min_azimuth_deg >= -180.0 && min_azimuth_deg < max_azimuth_deg && max_azimuth_deg <= 180.0,
        "ego_velocity.min_azimuth_deg", "need -180 <= min_azimuth_deg < max_azimuth_deg <= 180");
    Require(min_elevation_deg >= -90.0 && min_elevation_deg < max_elevation_deg &&
                max_elevation_deg <= 90.0,
            "ego_velocity.min_elevation_deg",
            "need -90 <= min_elevation_deg < max_elevation_deg <= 90");
    Require(!std::isnan(min_power_db), "ego_velocity.min_power_db",
            "must be a number (-inf allowed)");
    Require(std::isfinite(snr_reference_db), "ego_velocity.snr_reference_db", "must be finite");
    Require(std::isfinite(decibel_floor_db), "ego_velocity.decibel_floor_db", "must be finite");
    Require(doppler_sigma_mps > 0.0 && std::isfinite(doppler_sigma_mps),
            "ego_velocity.doppler_sigma_mps", "must be > 0");
    Require(gate_sigmas > 0.0 && std::isfinite(gate_sigmas), "ego_velocity.gate_sigmas",
            "must be > 0");
    Require(max_gate_scale >= 1.0, "ego_velocity.max_gate_scale", "must be >= 1");
    Require(ransac_success_probability > 0.0 && ransac_success_probability < 1.0,
            "ego_velocity.ransac_success_probability", "must be in (0, 1)");
    Require(ransac_min_iterations >= 1, "ego_velocity.ransac_min_iterations", "must be >= 1");
    Require(ransac_max_iterations >= ransac_min_iterations, "ego_velocity.ransac_max_iterations",
            "must be >= ransac_min_iterations");
    Require(ransac_score_points == 0 || ransac_score_points >= 16,
            "ego_velocity.ransac_score_points", "must be 0 (all points) or >= 16");
    Require(ransac_bailout_points >= 0, "ego_velocity.ransac_bailout_points",
            "must be >= 0 (0 = off)");
    Require(ransac_bailout_fraction >= 0.0 && ransac_bailout_fraction < 1.0,
            "ego_velocity.ransac_bailout_fraction", "must be in [0, 1)");
    Require(score_cells_azimuth >= 1 && score_cells_azimuth <= 256,
            "ego_velocity.score_cells_azimuth", "must be in [1, 256]");
    Require(score_cells_elevation >= 1 && score_cells_elevation <= 256,
            "ego_velocity.score_cells_elevation", "must be in [1, 256]");
    Require(refit_iterations >= 0, "ego_velocity.refit_iterations", "must be >= 0");
    Require(trim_mode != TrimMode::kPercent || (trim_value > 0.0 && trim_value <= 1.0),
            "ego_velocity.trim_value", "must be in (0, 1] for trim_mode percent");
    Require(trim_value > 0.0 && std::isfinite(trim_value), "ego_velocity.trim_value",
            "must be > 0");
    Require(irls_max_iterations >= 1, "ego_velocity.irls_max_iterations", "must be >= 1");
    Require(min_points >= 4, "ego_velocity.min_points",
            "must be >= 4 (3 unknowns + 1 for the covariance)");
    Require(min_inliers >= 4, "ego_velocity.min_inliers", "must be >= 4");
    Require(min_inlier_ratio >= 0.0 && min_inlier_ratio <= 1.0, "ego_velocity.min_inlier_ratio",
            "must be in [0, 1]");
    Require(max_condition_number > 1.0, "ego_velocity.max_condition_number", "must be > 1");
    Require(max_speed_mps > 0.0, "ego_velocity.max_speed_mps", "must be > 0");
    Require(stationary_speed_mps >= 0.0 && stationary_speed_mps < max_speed_mps,
            "ego_velocity.stationary_speed_mps", "must be in [0, max_speed_mps)");
    const auto finite_non_negative = [](double x) { return std::isfinite(x) && x >= 0.0; };
    Require(finite_non_negative(sensor.range_sigma_m), "ego_velocity.radar.range_sigma_m",
            "must be >= 0");
    Require(finite_non_negative(sensor.azimuth_sigma_deg) && sensor.azimuth_sigma_deg < 20.0,
            "ego_velocity.radar.azimuth_sigma_deg", "must be in [0, 20)");
    Require(finite_non_negative(sensor.elevation_sigma_deg) && sensor.elevation_sigma_deg < 20.0,
            "ego_velocity.radar.elevation_sigma_deg", "must be in [0, 20)");
    Require(finite_non_negative(sensor.doppler_unambiguous_mps),
            "ego_velocity.radar.doppler_unambiguous_mps", "must be >= 0 (0 = no aliasing)");
    Require(sensor.doppler_unambiguous_mps == 0.0 ||
                gate_sigmas * doppler_sigma_mps * max_gate_scale < sensor.doppler_unambiguous_mps,
            "ego_velocity.radar.doppler_unambiguous_mps",
            "must exceed the widest inlier gate gate_sigmas * doppler_sigma_mps * max_gate_scale");
}

struct EgoVelocityEstimator::Workspace : internal::Workspace {};

EgoVelocityEstimator::EgoVelocityEstimator(EgoVelocityConfig config)
    : config_(std::move(config)), workspace_(std::make_unique<Workspace>()) {
    config_.Validate();
}
EgoVelocityEstimator::~EgoVelocityEstimator() = default;
EgoVelocityEstimator::EgoVelocityEstimator(EgoVelocityEstimator &&) noexcept = default;
EgoVelocityEstimator &EgoVelocityEstimator::operator=(EgoVelocityEstimator &&) noexcept = default;

EgoVelocityResult EgoVelocityEstimator::Estimate(const RadarScan &scan_radar) {
    return EstimateWithin(scan_radar, std::nullopt);
}

EgoVelocityResult EgoVelocityEstimator::Estimate(const RadarScan &scan_radar,
                                                 const VelocityPrediction &prediction) {
    return EstimateWithin(scan_radar, prediction);
}

const char *ToString(PredictionUse use) {
    switch (use) {
        case PredictionUse::kNone:
            return "none";
        case PredictionUse::kInside:
            return "inside";
        case PredictionUse::kReleased:
            return "released";
    }
    return "?";
}

EgoVelocityResult EgoVelocityEstimator::EstimateWithin(
    const RadarScan &scan_radar, const std::optional<VelocityPrediction> &prediction) {
    EgoVelocityResult result;
    internal::Workspace &ws = *workspace_;
    result.labels.assign(scan_radar.size(), PointLabel::kFiltered);
    if (scan_radar.empty()) {
        result.failure = EgoVelocityFailure::kEmptyScan;
        return result;
    }
    BuildSystem(config_, scan_radar, ws, result.labels);
    const Eigen::Index n = ws.system.size();
    result.points_used = static_cast<int>(n);
    if (n < config_.min_points) {
        result.failure = EgoVelocityFailure::kTooFewPoints;
        result.failure_detail =
            std::to_string(n) + " < min_points " + std::to_string(config_.min_points);
        return result;
    }
    internal::AssignWeightsAndGates(config_, scan_radar.has_power, ws.system.w, ws.system.gate2);
    if (!(ws.system.w.maxCoeff() > 0.0)) {
        result.failure = EgoVelocityFailure::kZeroWeight;
        return result;
    }

    ws.rng.seed(config_.seed);
    Eigen::Vector3d v;
    bool solved = false;
    switch (config_.method) {
        case RobustMethod::kRansac:
            solved = internal::Ransac(config_, ws, v, result.iterations, prediction);
            if (prediction) {
                const double inliers = solved ? ws.mask.sum() : 0.0;
                if (inliers >= config_.min_inliers &&
                    inliers >= config_.min_inlier_ratio * static_cast<double>(n)) {
                    result.prediction = PredictionUse::kInside;
                } else {  // nothing inside explains the scan: perhaps the prediction is wrong
                    result.prediction = PredictionUse::kReleased;
                    ws.rng.seed(config_.seed);
                    int more = 0;
                    solved = internal::Ransac(config_, ws, v, more);
                    result.iterations += more;
                }
            }
            break;
        case RobustMethod::kTrimmedIrls:
            solved = internal::TrimmedIrls(config_, ws, v, result.iterations);
            break;
        case RobustMethod::kNone:
            ws.mask.setOnes(n);
            result.iterations = 1;
            break;
    }
    // Final fit on the final inlier set, so that v and its covariance describe the same points.
    // With direction noise, after RANSAC: the bias-compensated fit (direction_noise_fit.cpp).
    Eigen::Matrix3d AtWA, cov_eiv;
    const bool eiv = config_.compensate_direction_noise && config_.sensor.has_direction_noise() &&
                     config_.method == RobustMethod::kRansac;
    if (eiv) {
        solved = solved && internal::FitWithDirectionNoise(config_, ws, v, AtWA, cov_eiv);
        result.direction_noise_compensated = solved;
    } else if (solved && config_.method == RobustMethod::kRansac) {
        // RANSAC's last pass summed the normal equations of exactly this mask (ws.weighted too).
        AtWA = ws.mask_equations.AtWA();
        solved = internal::SolveNormalEquations(ws.mask_equations, v);
    } else {
        solved = (solved || config_.method == RobustMethod::kNone) &&
                 internal::SolveWeighted(ws.system, ws.mask, ws, v, AtWA);
    }
    if (!solved) {
        result.failure = EgoVelocityFailure::kDegenerateGeometry;
        result.failure_detail = "the point directions do not span 3-D";
        return result;
    }
    ws.residual.noalias() = ws.system.A * v;
    ws.residual -= ws.system.b;
    result.inliers = static_cast<int>(ws.mask.sum());
    const double span = ws.system.alias_span;
    for (Eigen::Index k = 0; k < n; ++k) {
        if (!(ws.mask[k] > 0.0)) continue;
        result.labels[ws.used_to_input[k]] = PointLabel::kStatic;
        // b_k = -doppler + j * span after unwrapping: count the static points with j != 0.
        if (span > 0.0 &&
            std::abs(ws.system.b[k] + scan_radar.doppler_mps[ws.used_to_input[k]]) > 0.5 * span)
            ++result.unwrapped;
    }

    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(AtWA, Eigen::EigenvaluesOnly);
    const double lambda_min = eig.eigenvalues()[0], lambda_max = eig.eigenvalues()[2];
    result.condition_number = lambda_min > 0.0 ? std::sqrt(lambda_max / lambda_min)
                                               : std::numeric_limits<double>::infinity();
    result.v_radar_mps = v;
    if (eiv) {
        const double rWr = (ws.weighted.array() * ws.residual.array().square()).sum();
        result.residual_sigma_mps = std::sqrt(rWr / std::max(result.inliers - 3, 1));
        result.cov_v_radar = internal::GateConsistencyFactor(config_.gate_sigmas) * cov_eiv;
    } else {
        result.cov_v_radar =
            Covariance(config_, ws, AtWA, result.inliers, result.residual_sigma_mps);
    }
    result.stationary = v.norm() < config_.stationary_speed_mps;

    internal::Invalidity invalidity = internal::CheckValidity(
        config_, result.inliers, static_cast<long>(n), result.condition_number,
        v.allFinite() && result.cov_v_radar.allFinite(), v.norm());
    result.failure = invalidity.failure;
    result.failure_detail = std::move(invalidity.detail);
    return result;
}

Eigen::Matrix3d VelocityCramerRaoBound(const Eigen::Matrix3Xd &directions,
                                       const Eigen::VectorXd &sigma_mps) {
    const Eigen::Matrix3Xd weighted =
        directions.array().rowwise() * sigma_mps.array().square().inverse().transpose();
    const Eigen::Matrix3d fisher = weighted * directions.transpose();
    return fisher.inverse();
}

}  // namespace dorado::odometry
