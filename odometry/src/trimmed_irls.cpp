// The paper reference implementation's alternative to RANSAC: trimmed iteratively-reweighted
// least squares. It starts from every point, so a moving crowd of a quarter of the scan or more
// pulls the first fit towards itself and the trimming then keeps the crowd: prefer RANSAC.
#include <algorithm>
#include <cmath>

#include "robust_fit.hpp"

namespace dorado::odometry::internal {
namespace {

// k-th smallest of values (copied into the buffer).
double KthSmallest(const Eigen::VectorXd &values, Eigen::Index k, Eigen::VectorXd &buffer) {
    buffer = values;
    std::nth_element(buffer.data(), buffer.data() + k, buffer.data() + buffer.size());
    return buffer[k];
}

// The trimming threshold on |residual| for the configured rule.
double TrimThreshold(const EgoVelocityConfig &config, const Eigen::VectorXd &abs_residual,
                     Eigen::VectorXd &buffer) {
    const Eigen::Index n = abs_residual.size();
    switch (config.trim_mode) {
        case TrimMode::kPercent: {
            const auto k = std::clamp<Eigen::Index>(
                static_cast<Eigen::Index>(std::floor(config.trim_value * n)), 0, n - 1);
            return KthSmallest(abs_residual, k, buffer);
        }
        case TrimMode::kMad: {
            const double median = KthSmallest(abs_residual, n / 2, buffer);
            Eigen::VectorXd deviation = (abs_residual.array() - median).abs();
            const double mad = KthSmallest(deviation, n / 2, buffer);
            return median + config.trim_value * mad;
        }
        case TrimMode::kFixed:
            return config.trim_value;
    }
    return config.trim_value;
}

}  // namespace

bool TrimmedIrls(const EgoVelocityConfig &config, Workspace &ws, Eigen::Vector3d &v,
                 int &iterations) {
    const DopplerSystem &s = ws.system;
    ws.mask.setOnes(s.size());
    Eigen::Matrix3d AtWA;
    Eigen::Vector3d previous = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    iterations = 0;
    for (; iterations < config.irls_max_iterations; ++iterations) {
        if (!SolveWeighted(s, ws.mask, ws, v, AtWA)) return false;
        if ((v - previous).norm() < 1e-6) break;
        previous = v;
        ws.residual.noalias() = s.A * v;
        ws.residual -= s.b;
        const Eigen::VectorXd abs_residual = ws.residual.cwiseAbs();
        const double threshold = TrimThreshold(config, abs_residual, ws.sort_buffer);
        // The reference keeps r < threshold for "percent" and r <= threshold otherwise.
        if (config.trim_mode == TrimMode::kPercent)
            ws.mask = (abs_residual.array() < threshold).cast<double>().matrix();
        else
            ws.mask = (abs_residual.array() <= threshold).cast<double>().matrix();
        if (ws.mask.sum() < 3) return false;
    }
    ws.residual.noalias() = s.A * v;
    ws.residual -= s.b;
    return true;
}

}  // namespace dorado::odometry::internal
