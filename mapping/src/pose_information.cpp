// The information each input of the refinement brings about the pose (pose_information.hpp).
#include "pose_information.hpp"

#include <ceres/loss_function.h>

#include <tsl/robin_map.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <memory>

#include "cost_functions.hpp"

namespace dorado::mapping {

namespace {

using Matrix36d = Eigen::Matrix<double, 3, 6>;

// IRLS weight rho'(s) of a robust loss at the squared residual s (1 without a loss).
double LossWeight(const ceres::LossFunction *loss, double s) {
    if (loss == nullptr) return 1.0;
    double rho[3];
    loss->Evaluate(s, rho);
    return rho[1];
}

// The residual and its Jacobian in xi of one registration match at the pose (t, q).
void RegistrationRow(const Correspondence &m, const double *t, const double *q,
                     const Eigen::Matrix<double, 7, 6> &lift, Eigen::Vector3d &r, Matrix36d &J) {
    const RegistrationError error(m.p_base, m.q_world, m.sqrt_information);
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> J_t;
    Eigen::Matrix<double, 3, 4, Eigen::RowMajor> J_q;
    const double *parameters[] = {t, q};
    double *jacobians[] = {J_t.data(), J_q.data()};
    error.Evaluate(parameters, r.data(), jacobians);
    J = J_t * lift.topRows<3>() + J_q * lift.bottomRows<4>();
}

// A cell of registration_cluster_m for the clustered model: residuals whose map point falls in
// one cell share that surface (and its error).
int64_t ClusterKey(const Eigen::Vector3d &q_world, double cell_m) {
    const Eigen::Vector3d c = (q_world / cell_m).array().floor();
    const auto part = [](double v) { return static_cast<int64_t>(v) & 0x1FFFFF; };
    return (part(c.x()) << 42) | (part(c.y()) << 21) | part(c.z());
}

// The projector onto the directions the per-point information H observes: in each of its
// translation and rotation blocks (metres and radians do not compare), the eigenvectors whose
// eigenvalue is at least ratio times the block's largest (Zhang et al. ICRA 2016; X-ICP analyses
// the two blocks apart too), and how many are weak.
struct StrongDirections {
    Matrix6d projector = Matrix6d::Zero();
    int weak = 0;
};

StrongDirections StrongProjector(const Matrix6d &H, double ratio) {
    StrongDirections out;
    Matrix6d &Q = out.projector;
    int &weak = out.weak;
    for (int block = 0; block < 6; block += 3) {
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(H.block<3, 3>(block, block));
        const double largest = eig.eigenvalues()(2);
        for (int k = 0; k < 3; ++k) {
            if (eig.eigenvalues()(k) < ratio * largest) {
                ++weak;
                continue;
            }
            const Eigen::Vector3d u = eig.eigenvectors().col(k);
            Q.block<3, 3>(block, block) += u * u.transpose();
        }
    }
    return out;
}

Matrix6d FloorCovariance(const MapperConfig &config) {
    Vector6d sigma;
    sigma << Eigen::Vector3d::Constant(config.registration_floor_sigma_translation_m),
        Eigen::Vector3d::Constant(config.registration_floor_sigma_rotation_rad);
    return sigma.cwiseAbs2().asDiagonal();
}

}  // namespace

Eigen::Matrix<double, 7, 6> RightPerturbationLift(const Eigen::Quaterniond &q) {
    Eigen::Matrix<double, 7, 6> lift = Eigen::Matrix<double, 7, 6>::Zero();
    lift.block<3, 3>(0, 0) = q.toRotationMatrix();  // t' = t + R rho
    // q' = q (x) [phi/2; 1]: d vec/d phi = (w I + [vec]x) / 2, d w/d phi = -vec^T / 2.
    lift.block<3, 3>(3, 3) = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + Hat(q.vec()));
    lift.block<1, 3>(6, 3) = -0.5 * q.vec().transpose();
    return lift;
}

Matrix6d AdjointSE3(const Eigen::Isometry3d &T) {
    Matrix6d Ad = Matrix6d::Zero();
    const Eigen::Matrix3d R = T.linear();
    Ad.topLeftCorner<3, 3>() = R;
    Ad.topRightCorner<3, 3>() = Hat(T.translation()) * R;
    Ad.bottomRightCorner<3, 3>() = R;
    return Ad;
}

Matrix6d CovarianceFromInformation(const Matrix6d &information) {
    const Matrix6d regularised = information + 1e-12 * Matrix6d::Identity();
    const Matrix6d covariance = regularised.ldlt().solve(Matrix6d::Identity());
    return 0.5 * (covariance + covariance.transpose());
}

RegisteredPose RegistrationCovariance(const Eigen::Isometry3d &T_world_base,
                                      const std::vector<Correspondence> &matches,
                                      const ceres::LossFunction *loss, const MapperConfig &config) {
    RegisteredPose out;
    out.T_world_base = T_world_base;
    const int n = static_cast<int>(matches.size());
    if (n < 3) return out;
    const Eigen::Vector3d t = T_world_base.translation();
    const Eigen::Quaterniond q = Eigen::Quaterniond(T_world_base.linear()).normalized();
    const Eigen::Matrix<double, 7, 6> lift = RightPerturbationLift(q);

    // One pass: the model information H = sum w J^T J, the weighted residual sum of squares and
    // the per-cluster gradients g_c = sum w J^T r (IRLS weights of the robust loss).
    Matrix6d H = Matrix6d::Zero();
    double weighted_ss = 0.0;
    tsl::robin_map<int64_t, Vector6d> gradients;
    Eigen::Vector3d r;
    Matrix36d J;
    for (const Correspondence &m : matches) {
        RegistrationRow(m, t.data(), q.coeffs().data(), lift, r, J);
        const double w = LossWeight(loss, r.squaredNorm());
        H.noalias() += w * J.transpose() * J;
        weighted_ss += w * r.squaredNorm();
        if (config.registration_covariance == RegistrationCovarianceModel::kClustered) {
            auto [it, inserted] = gradients.try_emplace(
                ClusterKey(m.q_world, config.registration_cluster_m), Vector6d::Zero());
            it.value() += w * J.transpose() * r;
        }
    }
    out.residual_scale = std::sqrt(weighted_ss / std::max(1, 3 * n - 6));
    const Eigen::LDLT<Matrix6d> ldlt(H);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 1e-12).all()) return out;
    const Matrix6d H_inv = CovarianceFromInformation(H);

    Matrix6d model = H_inv;
    switch (config.registration_covariance) {
        case RegistrationCovarianceModel::kIndependent:
            break;
        case RegistrationCovarianceModel::kResidualScale:
            model = out.residual_scale * out.residual_scale * H_inv;
            break;
        case RegistrationCovarianceModel::kClustered: {
            Matrix6d B = Matrix6d::Zero();
            for (const auto &[key, g] : gradients) B.noalias() += g * g.transpose();
            out.clusters = static_cast<int>(gradients.size());
            // Small-sample correction of the cluster-robust estimator (G / (G - 1)), and never
            // more confident than the independent model.
            const double G = static_cast<double>(out.clusters);
            if (out.clusters > 1) B *= G / (G - 1.0);
            model = H_inv * B * H_inv;
            model = 0.5 * (model + model.transpose());
            // Element-wise max is not a covariance order; take the independent model where the
            // sandwich says less along its own axes (a scaling of H^-1's eigen-directions).
            const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(H_inv);
            Vector6d scale;
            for (int k = 0; k < 6; ++k) {
                const Vector6d u = eig.eigenvectors().col(k);
                scale(k) = std::max(1.0, u.dot(model * u) / std::max(eig.eigenvalues()(k), 1e-300));
            }
            model = eig.eigenvectors() * (scale.cwiseProduct(eig.eigenvalues())).asDiagonal() *
                    eig.eigenvectors().transpose();
            break;
        }
    }
    out.covariance = model + FloorCovariance(config);
    out.information = CovarianceFromInformation(out.covariance);
    if (config.registration_weak_ratio > 0.0) {
        const StrongDirections strong = StrongProjector(H, config.registration_weak_ratio);
        out.strong_projector = strong.projector;
        out.weak_directions = strong.weak;
        if (out.weak_directions > 0) {
            out.information = out.strong_projector * out.information * out.strong_projector;
            out.information = 0.5 * (out.information + out.information.transpose());
            out.covariance = CovarianceFromInformation(out.information);
        }
    }
    out.valid = out.covariance.allFinite() && out.information.allFinite();
    return out;
}

Matrix6d DopplerInformation(const Eigen::Isometry3d &T_world_base,
                            const std::vector<DopplerObservation> &doppler,
                            const Eigen::Isometry3d &T_world_base_prev,
                            const Eigen::Isometry3d &T_base_radar, double dt_s,
                            const ceres::LossFunction *loss, const MapperConfig &config) {
    Matrix6d information = Matrix6d::Zero();
    if (doppler.empty()) return information;
    const Eigen::Vector3d t = T_world_base.translation();
    const Eigen::Quaterniond q = Eigen::Quaterniond(T_world_base.linear()).normalized();
    const Eigen::Matrix<double, 7, 6> lift = RightPerturbationLift(q);
    const auto velocity =
        std::make_shared<SharedRadarVelocity>(T_base_radar, T_world_base_prev, dt_s);
    const double *parameters[] = {t.data(), q.coeffs().data()};
    for (const DopplerObservation &d : doppler) {
        const DopplerError error(d.d_radar, d.doppler_mps, velocity, config.doppler_sigma_mps);
        double r = 0.0;
        Eigen::RowVector3d J_p;
        Eigen::RowVector4d J_q;
        double *jacobians[] = {J_p.data(), J_q.data()};
        if (!error.Evaluate(parameters, &r, jacobians)) continue;
        const Eigen::Matrix<double, 1, 6> J = J_p * lift.topRows<3>() + J_q * lift.bottomRows<4>();
        information.noalias() += LossWeight(loss, r * r) * J.transpose() * J;
    }
    return information;
}

}  // namespace dorado::mapping
