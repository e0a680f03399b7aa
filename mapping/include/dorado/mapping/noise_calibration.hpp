#pragma once
/// @file noise_calibration.hpp
/// Online covariance matching (Mehra 1972; Mohamed and Schwarz 1999) of the two estimates the
/// mapper fuses, so that each is weighed by the error it shows on the data at hand rather than
/// the one its model claims. Per 3-dof block b (translation, rotation) the innovation
/// y = Log(T_prior^-1 T_registered) has, for independent errors,
///     E[y_b y_b^T] = alpha_b C_prior,b + beta_b C_registration,b,
/// with alpha_b = beta_b = 1 when both models are honest. Over the last window_scans scans,
/// (alpha, beta) maximise the Gaussian likelihood of the innovations, by Fisher scoring (Helmert's
/// variance component estimation, iterated): with S_k = alpha C_p,k + beta C_r,k, W_k = S_k^-1,
///     sum_k tr(W Cp W Cp) alpha + tr(W Cp W Cr) beta = sum_k y^T W Cp W y,
///     sum_k tr(W Cr W Cp) alpha + tr(W Cr W Cr) beta = sum_k y^T W Cr W y.
/// The two separate only where the covariances' ratio or shape varies from scan to scan (for a
/// constant ratio the system is singular): a weak pull toward 1 (one scan's worth) keeps the
/// scales at the models' own until the data tell them apart.
///
/// Guards, so that a bad registration cannot teach the mapper that registrations are good: only
/// scans whose registration passed every check count, each innovation is shrunk to at most
/// max_sample_nees x dof in the current metric (a single outlier moves the scales by about
/// cap / window), and the scales stay within [min_scale, max_scale].

#include <Eigen/Core>
#include <deque>

#include "dorado/core/lie.hpp"

namespace dorado::mapping {

struct NoiseCalibrationConfig {
    bool enabled = false;
    /// The scans the estimate is made over (the last ones).
    int window_scans = 100;
    /// Scans before the scales are applied (before: 1).
    int min_scans = 20;
    /// A scan's whitened moment y^T C^-1 y is capped at this many times its dof.
    double max_sample_nees = 10.0;
    double min_scale = 0.01;
    double max_scale = 100.0;

    /// Throws std::invalid_argument naming the first bad key.
    void Validate() const;
};

/// Scales of the prior's and the registration's covariances, per block.
struct NoiseScales {
    Eigen::Vector2d prior = Eigen::Vector2d::Ones();         ///< translation, rotation
    Eigen::Vector2d registration = Eigen::Vector2d::Ones();  ///< translation, rotation
};

/// C with its translation block and the cross terms scaled by the block scales (s_t, s_r):
/// S C S with S = diag(sqrt(s_t) I3, sqrt(s_r) I3), positive definite when C is.
[[nodiscard]] Matrix6d ScaleBlocks(const Matrix6d &C, const Eigen::Vector2d &scales);

class NoiseCalibration {
  public:
    explicit NoiseCalibration(const NoiseCalibrationConfig &config = {});

    /// One registered scan: the innovation (xi convention of MotionPrior) and the two covariances
    /// as their models give them (unscaled).
    void Add(const Vector6d &innovation, const Matrix6d &C_prior, const Matrix6d &C_registration);
    /// The current scales (all 1 before min_scans samples, or when disabled).
    [[nodiscard]] const NoiseScales &scales() const { return scales_; }
    [[nodiscard]] int samples() const { return samples_; }
    /// Whether Add learns anything (config enabled): callers skip computing its inputs otherwise.
    [[nodiscard]] bool enabled() const { return config_.enabled; }

  private:
    struct Sample {
        Eigen::Vector3d y;
        Eigen::Matrix3d C_prior, C_registration;
    };
    /// Fisher scoring of one block's scales from its samples, starting at `scales`.
    Eigen::Vector2d Solve(const std::deque<Sample> &samples, Eigen::Vector2d scales) const;

    NoiseCalibrationConfig config_;
    NoiseScales scales_;
    int samples_ = 0;
    std::deque<Sample> window_[2];  ///< per block (translation, rotation), the last window_scans
};

}  // namespace dorado::mapping
