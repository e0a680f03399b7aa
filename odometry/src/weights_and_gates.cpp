#include "weights_and_gates.hpp"

#include <cmath>

namespace dorado::odometry::internal {

void AssignWeightsAndGates(const EgoVelocityConfig &config, bool has_power,
                           Eigen::Ref<Eigen::VectorXd> w, Eigen::Ref<Eigen::VectorXd> gate2) {
    const double gate = config.gate_sigmas * config.doppler_sigma_mps;
    gate2.setConstant(gate * gate);
    if (!config.use_power || !has_power) {
        w.setOnes();
        return;
    }
    switch (config.power_weighting) {
        case PowerWeighting::kSnr: {
            // sigma_i^2 = sigma^2 (1 + N/S): w_i = sigma^2 / sigma_i^2 = 1 / (1 + 10^((ref-p)/10)).
            const double ln10_10 = std::log(10.0) / 10.0;
            w = 1.0 / (1.0 + ((config.snr_reference_db - w.array()) * ln10_10).exp());
            const double max_scale2 = config.max_gate_scale * config.max_gate_scale;
            gate2.array() *= w.array().inverse().min(max_scale2);
            break;
        }
        case PowerWeighting::kLinear: {
            const double p_max = w.maxCoeff();
            w = ((w.array() - p_max) * (std::log(10.0) / 10.0)).exp();
            break;
        }
        case PowerWeighting::kDecibel:
            w = (w.array() - config.decibel_floor_db).max(0.0);
            break;
    }
    const double w_max = w.size() > 0 ? w.maxCoeff() : 0.0;
    if (w_max > 0.0) w /= w_max;
}

// Rejecting by residual makes the estimator a "skipped mean" with psi(z) = z 1{|z| < k}; its
// asymptotic variance is sigma^2 E[psi^2] / E[psi']^2 with E[psi^2] = E[psi'] = P - 2 k phi(k),
// P = P(|z| < k), while eq. (6) on the inliers estimates sigma^2 (P - 2 k phi(k)) / P^2.
// The ratio (P / (P - 2 k phi(k)))^2 is 1.056 for k = 3 (measured: NEES 3.2 instead of 3).
double GateConsistencyFactor(double k) {
    const double P = std::erf(k / std::sqrt(2.0));
    const double m2 = P - 2.0 * k * std::exp(-0.5 * k * k) / std::sqrt(2.0 * M_PI);
    return m2 > 0.0 ? (P / m2) * (P / m2) : 1.0;
}

}  // namespace dorado::odometry::internal
