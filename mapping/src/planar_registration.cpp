// Scan-to-map registration in the plane (planar mode, 2D radars): see planar_registration.hpp.
#include "planar_registration.hpp"

#include <ceres/loss_function.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "local_map_impl.hpp"
#include "robust_loss.hpp"

namespace dorado::mapping {

Eigen::Isometry3d PlanarPlus(const Eigen::Isometry3d &T, const Eigen::Vector3d &d) {
    Vector6d xi = Vector6d::Zero();
    xi(0) = d(0);
    xi(1) = d(1);
    xi(5) = d(2);
    return T * ExpSE3(xi);
}

Eigen::Vector3d PlanarMinus(const Eigen::Isometry3d &T_a, const Eigen::Isometry3d &T_b) {
    const Vector6d xi = LogSE3(T_a.inverse() * T_b);
    return {xi(0), xi(1), xi(5)};
}

namespace {

using Clock = std::chrono::steady_clock;

Eigen::Matrix3d PlanarBlock(const Matrix6d &C) {
    Eigen::Matrix3d out;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out(i, j) = C(kPlanarAxes[i], kPlanarAxes[j]);
    return out;
}

// C with its planar block replaced by P and the planar-held cross terms zeroed.
Matrix6d WithPlanarBlock(Matrix6d C, const Eigen::Matrix3d &P) {
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 6; ++k) {
            C(kPlanarAxes[i], k) = 0.0;
            C(k, kPlanarAxes[i]) = 0.0;
        }
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) C(kPlanarAxes[i], kPlanarAxes[j]) = P(i, j);
    return C;
}

Eigen::Matrix3d Inverse(const Eigen::Matrix3d &C) {
    const Eigen::Matrix3d regularised = C + 1e-12 * Eigen::Matrix3d::Identity();
    return regularised.ldlt().solve(Eigen::Matrix3d::Identity());
}

struct Match {
    Eigen::Vector3d p_base;
    Eigen::Vector3d q_world;
};

struct Matches {
    std::vector<Match> matches;
    double sum_sq = 0.0;  ///< of the matched distances [m^2]
};

// The nearest map point within the threshold of every source point at T_world_base.
Matches FindMatches(const Eigen::Matrix3Xd &source_base, const Eigen::Isometry3d &T_world_base,
                    const LocalMap::Impl &map, double threshold_m) {
    Matches out;
    out.matches.reserve(static_cast<std::size_t>(source_base.cols()));
    for (Eigen::Index i = 0; i < source_base.cols(); ++i) {
        const LocalMap::Neighbour nn = map.Nearest(T_world_base * source_base.col(i), threshold_m);
        if (nn.index < 0) continue;
        out.matches.push_back({source_base.col(i), map.points_world[nn.index]});
        out.sum_sq += nn.distance_squared;
    }
    return out;
}

// One match's residual (world x, y) at T and its Jacobian in d = (rho_x, rho_y, phi_z):
// d (T Exp(xi) p) / d xi = R [I, -Hat(p)], so the columns are R e_x, R e_y and R (e_z x p).
void ResidualAndJacobian(const Match &m, const Eigen::Isometry3d &T, Eigen::Vector2d &r,
                         Eigen::Matrix<double, 2, 3> &J) {
    const Eigen::Matrix3d &R = T.linear();
    r = (T * m.p_base - m.q_world).head<2>();
    J.col(0) = R.col(0).head<2>();
    J.col(1) = R.col(1).head<2>();
    J.col(2) = (R * Eigen::Vector3d(-m.p_base.y(), m.p_base.x(), 0.0)).head<2>();
}

// One match's whitened squared residual s, the kernel's IRLS weight rho'(s), r and J at T.
double RobustWeight(const Match &m, const Eigen::Isometry3d &T, const ceres::LossFunction *loss,
                    double inv_var, Eigen::Vector2d &r, Eigen::Matrix<double, 2, 3> &J, double &s) {
    ResidualAndJacobian(m, T, r, J);
    s = r.squaredNorm() * inv_var;
    double rho[3] = {s, 1.0, 0.0};
    if (loss != nullptr) loss->Evaluate(s, rho);
    return rho[1];
}

// The registration's weighted normal equations at T (point-to-point in the plane, residuals
// whitened by point_sigma_m, the kernel's IRLS weight rho'(s)).
struct Normal {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    double weighted_sq = 0.0;  ///< sum of w s (whitened)
    double weights = 0.0;
};

Normal Accumulate(const std::vector<Match> &matches, const Eigen::Isometry3d &T,
                  const ceres::LossFunction *loss, double sigma_m) {
    Normal n;
    const double inv_var = 1.0 / (sigma_m * sigma_m);
    for (const Match &m : matches) {
        Eigen::Vector2d r;
        Eigen::Matrix<double, 2, 3> J;
        double s;
        const double w = RobustWeight(m, T, loss, inv_var, r, J, s);
        n.H += w * inv_var * J.transpose() * J;
        n.g += w * inv_var * J.transpose() * r;
        n.weighted_sq += w * s;
        n.weights += w;
    }
    return n;
}

// Where Solve ended: its last pose, and whether it converged there.
struct Solved {
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    bool converged = false;
};

// Gauss-Newton from T_world_base_initial over the registration residuals (re-associated each
// iteration) and, when given, a Gaussian prior in the plane. Not converged when a step had fewer
// than 3 matches or was not finite (the pose then stays at the last good step).
Solved Solve(const Eigen::Matrix3Xd &source_base, const LocalMap::Impl &map, double threshold_m,
             const ceres::LossFunction *loss, const MapperConfig &config, int iterations,
             const MotionPrior *prior, const Eigen::Isometry3d &T_world_base_initial) {
    const Eigen::Matrix3d prior_information =
        prior != nullptr ? Inverse(PlanarBlock(prior->covariance)) : Eigen::Matrix3d::Zero();
    Solved out{T_world_base_initial, false};
    Eigen::Isometry3d &T = out.T_world_base;
    for (int it = 0; it < iterations; ++it) {
        const std::vector<Match> matches = FindMatches(source_base, T, map, threshold_m).matches;
        if (matches.size() < 3) return out;
        Normal n = Accumulate(matches, T, loss, config.point_sigma_m);
        if (prior != nullptr) {
            // e = PlanarMinus(prior, T Exp(d)) ~ e0 + d (first order in the plane).
            const Eigen::Vector3d e0 = PlanarMinus(prior->T_world_base, T);
            n.H += prior_information;
            n.g += prior_information * e0;
        }
        const Eigen::Vector3d d = -n.H.ldlt().solve(n.g);
        if (!d.allFinite()) return out;
        T = PlanarPlus(T, d);
        if (d.head<2>().norm() < 1e-4 && std::abs(d(2)) < 1e-6) break;
    }
    out.converged = T.matrix().allFinite();
    return out;
}

// lambda_min / lambda_max of the matched points' 2-D scatter (world frame).
double Observability(const std::vector<Match> &matches) {
    if (matches.size() < 3) return 0.0;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const Match &m : matches) mean += m.q_world.head<2>();
    mean /= static_cast<double>(matches.size());
    Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
    for (const Match &m : matches) {
        const Eigen::Vector2d e = m.q_world.head<2>() - mean;
        S += e * e.transpose();
    }
    const Eigen::Vector2d lambda =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(S, Eigen::EigenvaluesOnly).eigenvalues();
    return lambda(1) > 0.0 ? std::max(0.0, lambda(0)) / lambda(1) : 0.0;
}

// The registration's covariance in the plane, with the numbers behind it.
struct PlanarCovariance {
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();  ///< of (rho_x, rho_y, phi_z)
    double residual_scale = 0.0;                  ///< whitened residual RMS
    int clusters = 0;                             ///< clustered model: groups of residuals
};

// The registration's covariance in the plane at T, by the configured model, plus its floor:
// independent (H^-1), residual_scale (H^-1 times the whitened residuals' variance) or clustered
// (H^-1 (sum_c g_c g_c^T) H^-1, the residuals grouped by the map cell of registration_cluster_m
// they fall in, with the small-sample factor C / (C - 1)).
PlanarCovariance RegistrationCovariancePlanar(const std::vector<Match> &matches,
                                              const Eigen::Isometry3d &T,
                                              const ceres::LossFunction *loss,
                                              const MapperConfig &config) {
    const double inv_var = 1.0 / (config.point_sigma_m * config.point_sigma_m);
    const Normal n = Accumulate(matches, T, loss, config.point_sigma_m);
    const Eigen::Matrix3d H_inv = Inverse(n.H);
    const double residual_scale = n.weights > 0.0 ? std::sqrt(n.weighted_sq / n.weights) : 0.0;
    int clusters = 0;
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    switch (config.registration_covariance) {
        case RegistrationCovarianceModel::kIndependent:
            C = H_inv;
            break;
        case RegistrationCovarianceModel::kResidualScale:
            C = residual_scale * residual_scale * H_inv;
            break;
        case RegistrationCovarianceModel::kClustered: {
            std::map<std::pair<long, long>, Eigen::Vector3d> g_of;
            const double cell = config.registration_cluster_m;
            for (const Match &m : matches) {
                Eigen::Vector2d r;
                Eigen::Matrix<double, 2, 3> J;
                double s;
                const double w = RobustWeight(m, T, loss, inv_var, r, J, s);
                const std::pair<long, long> key{std::lround(std::floor(m.q_world.x() / cell)),
                                                std::lround(std::floor(m.q_world.y() / cell))};
                auto [it, inserted] = g_of.try_emplace(key, Eigen::Vector3d::Zero());
                it->second += w * inv_var * J.transpose() * r;
            }
            Eigen::Matrix3d meat = Eigen::Matrix3d::Zero();
            for (const auto &[key, g] : g_of) meat += g * g.transpose();
            clusters = static_cast<int>(g_of.size());
            const double small_sample = clusters > 1 ? clusters / (clusters - 1.0) : 1.0;
            C = small_sample * H_inv * meat * H_inv;
            break;
        }
    }
    const double ft = config.registration_floor_sigma_translation_m;
    const double fr = config.registration_floor_sigma_rotation_rad;
    C += Eigen::Vector3d(ft * ft, ft * ft, fr * fr).asDiagonal();
    return {0.5 * (C + C.transpose()), residual_scale, clusters};
}

}  // namespace

PlanarRegistration RegisterPlanar(const Eigen::Matrix3Xd &source_base,
                                  const MotionPrior &prediction, const LocalMap &local_map,
                                  const MapperConfig &config, double threshold_m) {
    PlanarRegistration out;
    const LocalMap::Impl &map = local_map.impl();
    const auto loss = MakeLoss(config.kernel, config.kernel_scale);
    const auto t_align = Clock::now();

    // 1. Alignment from the prediction: the registration alone (the 3-D path's PCL ICP).
    const Solved aligned = Solve(source_base, map, threshold_m, loss.get(), config,
                                 config.max_iterations, nullptr, prediction.T_world_base);
    const bool converged = aligned.converged;
    const Eigen::Isometry3d &T_world_base_aligned = aligned.T_world_base;
    out.alignment_ms = MillisecondsSince(t_align);
    const Matches found =
        converged ? FindMatches(source_base, T_world_base_aligned, map, threshold_m) : Matches{};
    const std::vector<Match> &matches = found.matches;
    out.count = static_cast<int>(matches.size());
    out.rms_m =
        matches.empty() ? 0.0 : std::sqrt(found.sum_sq / static_cast<double>(matches.size()));
    out.observability = Observability(matches);
    out.registration_ms = MillisecondsSince(t_align);
    out.T_world_base_aligned = T_world_base_aligned;

    if (!converged) {
        out.cause = FallbackCause::kNotConverged;
    } else if (out.count < config.min_correspondences) {
        out.cause = FallbackCause::kTooFewCorrespondences;
        out.detail = std::to_string(out.count);
    } else if (out.rms_m > config.max_rms_m) {
        out.cause = FallbackCause::kBadFitness;
        out.detail = "rms " + std::to_string(out.rms_m) + " m";
    } else if (out.observability < config.min_observability) {
        out.cause = FallbackCause::kDegenerate;
        out.detail = "observability " + std::to_string(out.observability);
    }
    if (out.cause != FallbackCause::kNone) return out;

    const auto t_refine = Clock::now();
    // 2. The registered pose: registration + the prediction.
    Eigen::Isometry3d T_map_base = T_world_base_aligned;
    const Solved refined = Solve(source_base, map, threshold_m, loss.get(), config,
                                 config.refine_max_iterations, &prediction, T_map_base);
    if (refined.converged) T_map_base = refined.T_world_base;
    const std::vector<Match> final_matches =
        FindMatches(source_base, T_map_base, map, threshold_m).matches;
    const PlanarCovariance registration =
        RegistrationCovariancePlanar(final_matches, T_map_base, loss.get(), config);
    const Eigen::Matrix3d &C_reg = registration.C;
    RegisteredPose &registered = out.registered;
    registered.residual_scale = registration.residual_scale;
    registered.clusters = registration.clusters;
    registered.valid = final_matches.size() >= 3 && C_reg.allFinite();
    registered.T_world_base = T_map_base;
    registered.covariance = WithPlanarBlock(prediction.covariance, C_reg);
    registered.information = WithPlanarBlock(Matrix6d::Zero(), Inverse(C_reg));
    if (!registered.valid) out.cause = FallbackCause::kUnrefined;
    out.refinement_ms = MillisecondsSince(t_refine);
    return out;
}

}  // namespace dorado::mapping
