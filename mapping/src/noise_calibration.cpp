#include "dorado/mapping/noise_calibration.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "dorado/core/require.hpp"

namespace dorado::mapping {

namespace {
constexpr int kScoringIterations = 8;
}  // namespace

void NoiseCalibrationConfig::Validate() const {
    Require(window_scans >= 2 && window_scans <= 100000, "mapper.noise_calibration.window_scans",
            "must be in [2, 100000]");
    Require(min_scans >= 0, "mapper.noise_calibration.min_scans", "must be >= 0");
    Require(std::isfinite(max_sample_nees) && max_sample_nees > 1.0,
            "mapper.noise_calibration.max_sample_nees", "must be > 1");
    Require(std::isfinite(min_scale) && min_scale > 0.0 && min_scale <= 1.0,
            "mapper.noise_calibration.min_scale", "must be in (0, 1]");
    Require(std::isfinite(max_scale) && max_scale >= 1.0, "mapper.noise_calibration.max_scale",
            "must be >= 1");
}

Matrix6d ScaleBlocks(const Matrix6d &C, const Eigen::Vector2d &scales) {
    Vector6d s;
    s << Eigen::Vector3d::Constant(std::sqrt(scales(0))),
        Eigen::Vector3d::Constant(std::sqrt(scales(1)));
    return s.asDiagonal() * C * s.asDiagonal();
}

NoiseCalibration::NoiseCalibration(const NoiseCalibrationConfig &config) : config_(config) {
    config_.Validate();
}

void NoiseCalibration::Add(const Vector6d &innovation, const Matrix6d &C_prior,
                           const Matrix6d &C_registration) {
    if (!config_.enabled || !innovation.allFinite() || !C_prior.allFinite() ||
        !C_registration.allFinite())
        return;
    Sample blocks[2];
    for (int b = 0; b < 2; ++b) {
        blocks[b] = {innovation.segment<3>(3 * b), C_prior.block<3, 3>(3 * b, 3 * b),
                     C_registration.block<3, 3>(3 * b, 3 * b)};
        if (Eigen::LLT<Eigen::Matrix3d>(blocks[b].C_prior).info() != Eigen::Success ||
            Eigen::LLT<Eigen::Matrix3d>(blocks[b].C_registration).info() != Eigen::Success)
            return;
    }
    for (int b = 0; b < 2; ++b) {
        // The guard: in the current metric, an innovation beyond the cap is shrunk to it.
        Sample &sample = blocks[b];
        const Eigen::Matrix3d S =
            scales_.prior(b) * sample.C_prior + scales_.registration(b) * sample.C_registration;
        const double nees = sample.y.dot(S.ldlt().solve(sample.y));
        const double cap = 3.0 * config_.max_sample_nees;
        if (nees > cap) sample.y *= std::sqrt(cap / nees);
        window_[b].push_back(sample);
        if (static_cast<int>(window_[b].size()) > config_.window_scans) window_[b].pop_front();
    }
    ++samples_;
    if (samples_ < config_.min_scans) return;
    for (int b = 0; b < 2; ++b) {
        const Eigen::Vector2d x =
            Solve(window_[b], Eigen::Vector2d(scales_.prior(b), scales_.registration(b)));
        scales_.prior(b) = x(0);
        scales_.registration(b) = x(1);
    }
}

Eigen::Vector2d NoiseCalibration::Solve(const std::deque<Sample> &samples,
                                        Eigen::Vector2d x) const {
    // The pull toward 1, worth one sample in each equation (in units of the mean information).
    for (int it = 0; it < kScoringIterations; ++it) {
        Eigen::Matrix2d N = Eigen::Matrix2d::Zero();
        Eigen::Vector2d z = Eigen::Vector2d::Zero();
        for (const Sample &s : samples) {
            const Eigen::Matrix3d W = (x(0) * s.C_prior + x(1) * s.C_registration).inverse();
            const Eigen::Matrix3d WP = W * s.C_prior, WR = W * s.C_registration;
            N(0, 0) += (WP * WP).trace();
            N(0, 1) += (WP * WR).trace();
            N(1, 1) += (WR * WR).trace();
            const Eigen::Vector3d Wy = W * s.y;
            z(0) += Wy.dot(s.C_prior * Wy);
            z(1) += Wy.dot(s.C_registration * Wy);
        }
        N(1, 0) = N(0, 1);
        const double n = static_cast<double>(samples.size());
        N(0, 0) += N(0, 0) / n;
        N(1, 1) += N(1, 1) / n;
        z(0) += N(0, 0) / (n + 1.0);
        z(1) += N(1, 1) / (n + 1.0);
        const Eigen::Vector2d next = N.ldlt().solve(z);
        if (!next.allFinite()) break;
        const Eigen::Vector2d clamped =
            next.cwiseMax(config_.min_scale).cwiseMin(config_.max_scale);
        const bool converged = ((clamped - x).array().abs() < 1e-3 * x.array()).all();
        x = clamped;
        if (converged) break;
    }
    return x;
}

}  // namespace dorado::mapping
