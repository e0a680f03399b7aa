#include "dorado/odometry/calibration.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dorado::odometry {
namespace {

double Median(std::vector<double> values) {
    const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    return *mid;
}

void RequireSamples(std::size_t n, const char *what) {
    if (n < 3)
        throw std::invalid_argument(std::string(what) + ": need at least 3 valid scans, got " +
                                    std::to_string(n));
}

}  // namespace

double LongRunVariance(const std::vector<double> &scores, int lag) {
    const std::size_t n = scores.size();
    double variance = 0.0;
    for (const double s : scores) variance += s * s;
    for (int l = 1; l <= lag && static_cast<std::size_t>(l) < n; ++l) {
        double cross = 0.0;
        for (std::size_t i = static_cast<std::size_t>(l); i < n; ++i)
            cross += scores[i] * scores[i - static_cast<std::size_t>(l)];
        variance += 2.0 * (1.0 - l / (lag + 1.0)) * cross;
    }
    return std::max(variance, 0.0);
}

RotationCalibration CalibrateRotation(const std::vector<Eigen::Vector3d> &v_radar,
                                      const Eigen::Matrix3d &R_base_radar_guess,
                                      int correlation_lag) {
    RequireSamples(v_radar.size(), "rotation calibration");
    // Principal axis of the velocities: straight driving forward and backward puts every v_radar
    // on the line of the base X axis.
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const auto &v : v_radar) scatter += v * v.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
    if (!(eig.eigenvalues()[2] > 0.0))
        throw std::invalid_argument("rotation calibration: the radar did not move");
    Eigen::Vector3d forward_radar = eig.eigenvectors().col(2);
    const Eigen::Vector3d guess_forward_radar = R_base_radar_guess.transpose().col(0);
    if (forward_radar.dot(guess_forward_radar) < 0.0) forward_radar = -forward_radar;
    // The smallest rotation (in the base frame) that takes the guessed image of the forward axis
    // onto X: keeps the guess's roll.
    const Eigen::Quaterniond q_fix = Eigen::Quaterniond::FromTwoVectors(
        R_base_radar_guess * forward_radar, Eigen::Vector3d::UnitX());
    RotationCalibration out;
    out.R_base_radar = q_fix.toRotationMatrix() * R_base_radar_guess;
    out.samples = static_cast<int>(v_radar.size());
    double sum_perp2 = 0.0;
    for (const auto &v : v_radar) sum_perp2 += (out.R_base_radar * v).tail<2>().squaredNorm();
    out.rms_residual_mps = std::sqrt(sum_perp2 / (2.0 * out.samples));
    // Small-angle least squares: each angle is a slope perp = angle * |v| with per-axis noise rms.
    out.sigma_rad = out.rms_residual_mps / std::sqrt(eig.eigenvalues()[2]);
    if (correlation_lag > 0) {
        // Each angle's score is perp_k * v_x: correlated errors add their cross terms.
        double sum_u2 = 0.0;
        std::vector<double> yaw_scores, pitch_scores;
        for (const auto &v : v_radar) {
            const Eigen::Vector3d w = out.R_base_radar * v;
            sum_u2 += w.x() * w.x();
            yaw_scores.push_back(w.y() * w.x());
            pitch_scores.push_back(w.z() * w.x());
        }
        const double worst = std::max(LongRunVariance(yaw_scores, correlation_lag),
                                      LongRunVariance(pitch_scores, correlation_lag));
        out.sigma_rad = std::max(out.sigma_rad, std::sqrt(worst) / sum_u2);
    }
    return out;
}

RotationCalibration CalibrateRoll(const std::vector<Eigen::Vector3d> &v_radar,
                                  const Eigen::Matrix3d &R_base_radar) {
    RequireSamples(v_radar.size(), "roll calibration");
    // z after a roll alpha about X: sin(alpha) w_y + cos(alpha) w_z; minimise its sum of squares
    // over the unit vector (sin, cos): the eigenvector of the smallest eigenvalue.
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto &v : v_radar) {
        const Eigen::Vector2d yz = (R_base_radar * v).tail<2>();
        scatter += yz * yz.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    const double n = static_cast<double>(v_radar.size());
    // Without turns (or slopes) the Y-Z velocities are noise only: isotropic, no direction.
    if (!(eig.eigenvalues()[1] > 1e-6 * n && eig.eigenvalues()[1] > 10.0 * eig.eigenvalues()[0]))
        throw std::invalid_argument(
            "roll calibration: no lateral or vertical motion in the radar velocities (drive with "
            "turns on flat ground)");
    Eigen::Vector2d sc = eig.eigenvectors().col(0);  // (sin alpha, cos alpha)
    if (sc.y() < 0.0) sc = -sc;                      // |alpha| <= pi/2: closer to no change
    const double alpha = std::atan2(sc.x(), sc.y());
    RotationCalibration out;
    out.R_base_radar = Eigen::AngleAxisd(alpha, Eigen::Vector3d::UnitX()) * R_base_radar;
    out.samples = static_cast<int>(v_radar.size());
    out.rms_residual_mps = std::sqrt(std::max(eig.eigenvalues()[0], 0.0) / n);
    out.sigma_rad = std::sqrt(std::max(eig.eigenvalues()[0], 0.0) / std::max(n - 1.0, 1.0)) /
                    std::sqrt(eig.eigenvalues()[1]);
    return out;
}

SxCalibration CalibrateSx(const std::vector<Eigen::Vector3d> &v_sensor_base,
                          const std::vector<double> &yaw_rate_base_radps, int correlation_lag) {
    if (v_sensor_base.size() != yaw_rate_base_radps.size())
        throw std::invalid_argument("s_x calibration: velocities and yaw rates differ in count");
    RequireSamples(v_sensor_base.size(), "s_x calibration");
    const std::size_t n = v_sensor_base.size();
    std::vector<bool> keep(n, true);
    SxCalibration out;
    out.samples = static_cast<int>(n);
    for (int round = 0; round < 5; ++round) {
        double sww = 0.0, swv = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            if (!keep[i]) continue;
            sww += yaw_rate_base_radps[i] * yaw_rate_base_radps[i];
            swv += yaw_rate_base_radps[i] * v_sensor_base[i].y();
        }
        if (!(sww > 1e-9))
            throw std::invalid_argument(
                "s_x calibration: no yaw motion in the gyro data (drive in a circle)");
        out.s_x_m = swv / sww;  // v_sy = omega_z s_x, least squares through the origin
        std::vector<double> abs_residual;
        double sum_r2 = 0.0;
        int count = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const double r = v_sensor_base[i].y() - yaw_rate_base_radps[i] * out.s_x_m;
            abs_residual.push_back(std::abs(r));
            if (keep[i]) sum_r2 += r * r, ++count;
        }
        out.inliers = count;
        out.rms_residual_mps = std::sqrt(sum_r2 / std::max(count - 1, 1));
        out.sigma_m = out.rms_residual_mps / std::sqrt(sww);
        const double robust_sigma = 1.4826 * Median(abs_residual);
        bool changed = false;
        for (std::size_t i = 0; i < n; ++i) {
            const bool k = abs_residual[i] <= 3.0 * robust_sigma + 1e-12;
            changed |= k != keep[i];
            keep[i] = k;
        }
        if (!changed) break;
    }
    if (correlation_lag > 0) {
        // The inliers' scores omega * residual in time order, their correlation kept.
        double sww = 0.0;
        std::vector<double> scores;
        for (std::size_t i = 0; i < n; ++i) {
            if (!keep[i]) continue;
            const double w = yaw_rate_base_radps[i];
            sww += w * w;
            scores.push_back(w * (v_sensor_base[i].y() - w * out.s_x_m));
        }
        if (sww > 0.0)
            out.sigma_m =
                std::max(out.sigma_m, std::sqrt(LongRunVariance(scores, correlation_lag)) / sww);
    }
    return out;
}

}  // namespace dorado::odometry
