// The fixed-lag smoother (pose_smoother.hpp): Gauss-Newton on SE(3) over the window's poses.
//
// Factors, each a whitened residual r with its Jacobian J on the right perturbations xi_i:
//   anchor (oldest):  r = W_a Log(m^-1 T_0)               J_0 = W_a
//   motion (i-1, i):  r = W_i Log(D_i^-1 T_{i-1}^-1 T_i)  J_{i-1} = -W_i Ad(T_i^-1 T_{i-1}),
//                                                         J_i = W_i
//   registration (i): r = W_r Log(z_i^-1 T_i)             J_i = W_r
//   ground (i):       r = W_g (u_base - (R_i^T e_z))_xy   J_i = W_g [0 | -[u]x]_xy
// (first order: the Jacobians of Log at small residuals are the identity). The normal equations
// H dxi = -g are dense 6N x 6N (N ~ 10-20): an LDLT per iteration costs tens of microseconds.
// A pose leaves by the Schur complement of its block: the factors that touch it become one
// Gaussian on the next pose (the new anchor), exact for the linearised problem.
#include "dorado/mapping/pose_smoother.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pose_information.hpp"

namespace dorado::mapping {

namespace {

using MatrixXd = Eigen::MatrixXd;
using VectorXd = Eigen::VectorXd;

// W with W^T W = information (symmetric positive semi-definite; zero along its null space).
Matrix6d SqrtOfInformation(const Matrix6d &information) {
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(0.5 *
                                                      (information + information.transpose()));
    const Vector6d s = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    return s.asDiagonal() * eig.eigenvectors().transpose();
}

// W with W^T W = covariance^-1 (L^-1 for covariance = L L^T).
Matrix6d SqrtOfInverse(const Matrix6d &covariance) {
    const Eigen::LLT<Matrix6d> llt(0.5 * (covariance + covariance.transpose()));
    if (llt.info() != Eigen::Success)
        return SqrtOfInformation(CovarianceFromInformation(covariance));
    return llt.matrixL().solve(Matrix6d::Identity());
}

// The normal equations of the factors, accumulated block by block.
struct Normal {
    MatrixXd H;
    VectorXd g;
    double cost = 0.0;  ///< half the squared whitened residuals
    explicit Normal(int poses)
        : H(MatrixXd::Zero(6 * poses, 6 * poses)), g(VectorXd::Zero(6 * poses)) {}

    template <int Rows>
    void AddUnary(int i, const Eigen::Matrix<double, Rows, 6> &J,
                  const Eigen::Matrix<double, Rows, 1> &r) {
        H.block<6, 6>(6 * i, 6 * i) += J.transpose() * J;
        g.segment<6>(6 * i) += J.transpose() * r;
        cost += 0.5 * r.squaredNorm();
    }
    void AddBinary(int i, const Matrix6d &J_i, int j, const Matrix6d &J_j, const Vector6d &r) {
        H.block<6, 6>(6 * i, 6 * i) += J_i.transpose() * J_i;
        H.block<6, 6>(6 * j, 6 * j) += J_j.transpose() * J_j;
        H.block<6, 6>(6 * i, 6 * j) += J_i.transpose() * J_j;
        H.block<6, 6>(6 * j, 6 * i) += J_j.transpose() * J_i;
        g.segment<6>(6 * i) += J_i.transpose() * r;
        g.segment<6>(6 * j) += J_j.transpose() * r;
        cost += 0.5 * r.squaredNorm();
    }
};

// T * Exp(xi) with its rotation re-orthonormalised: products of many small steps drift off SO(3),
// and an isometry's inverse (the transpose) is then no inverse at all.
Eigen::Isometry3d Plus(const Eigen::Isometry3d &T, const Vector6d &xi) {
    Eigen::Isometry3d out = T * ExpSE3(xi);
    out.linear() = Eigen::Quaterniond(out.linear()).normalized().toRotationMatrix();
    return out;
}

// The ground's residual and Jacobian at R_world_base: u = R^T e_z, du/dphi = [u]x.
void AddGround(Normal &normal, int i, const GroundUp &ground, const Eigen::Matrix3d &R_world_base) {
    const Eigen::Vector3d u = R_world_base.transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::LLT<Eigen::Matrix2d> llt(ground.covariance);
    if (llt.info() != Eigen::Success) return;
    const Eigen::Matrix2d W = llt.matrixL().solve(Eigen::Matrix2d::Identity());
    Eigen::Matrix<double, 2, 6> J = Eigen::Matrix<double, 2, 6>::Zero();
    J.rightCols<3>() = -W * Hat(u).topRows<2>();
    const Eigen::Vector2d r = W * (ground.up_base.head<2>() - u.head<2>());
    normal.AddUnary<2>(i, J, r);
}

}  // namespace

void SmootherConfig::Validate() const {
    auto fail = [](const std::string &key, const std::string &why) {
        throw std::invalid_argument("mapper.smoother." + key + ": " + why);
    };
    if (!(std::isfinite(lag_s) && lag_s >= 0.0)) fail("lag_s", "must be finite and >= 0");
    if (!(std::isfinite(max_registration_chi2) && max_registration_chi2 > 0.0))
        fail("max_registration_chi2", "must be finite and > 0");
    if (max_iterations < 1) fail("max_iterations", "must be >= 1");
}

PoseSmoother::PoseSmoother(const SmootherConfig &config) : config_(config) {
    config_.Validate();
}

Eigen::Isometry3d PoseSmoother::Add(const SmootherScan &scan) {
    State state;
    state.scan = scan;
    if (states_.empty()) {
        // The first scan: the map's origin, held by a stiff anchor (the gauge).
        state.T_world_base = Plus(scan.motion, Vector6d::Zero());
        anchor_mean_ = state.T_world_base;
        anchor_sqrt_information_ = Matrix6d::Identity() * 1e6;
    } else {
        state.T_world_base = Plus(states_.back().T_world_base * scan.motion, Vector6d::Zero());
    }
    if (scan.T_world_base_registered)
        state.registration_sqrt_information = SqrtOfInformation(scan.registration_information);
    states_.push_back(std::move(state));
    Solve();
    while (states_.size() > 1 &&
           states_.back().scan.time_s - states_.front().scan.time_s > config_.lag_s + 1e-9) {
        if (auto pose = PopOldest()) smoothed_.push_back(*pose);
        Solve();
    }
    return states_.back().T_world_base;
}

std::vector<SmoothedPose> PoseSmoother::TakeSmoothed() {
    std::vector<SmoothedPose> out;
    out.swap(smoothed_);
    return out;
}

std::vector<SmoothedPose> PoseSmoother::Flush() {
    while (!states_.empty()) {
        if (auto pose = PopOldest()) smoothed_.push_back(*pose);
        if (!states_.empty()) Solve();
    }
    anchor_sqrt_information_.setZero();
    return TakeSmoothed();
}

// Gauss-Newton over the window; then the covariances the outputs need (the newest pose's, the
// two oldest poses' joint).
void PoseSmoother::Solve() {
    const int n = static_cast<int>(states_.size());
    auto build = [&]() {
        Normal normal(n);
        normal.AddUnary<6>(
            0, anchor_sqrt_information_,
            anchor_sqrt_information_ * LogSE3(anchor_mean_.inverse() * states_[0].T_world_base));
        for (int i = 0; i < n; ++i) {
            const State &s = states_[static_cast<std::size_t>(i)];
            if (i > 0) {
                const State &p = states_[static_cast<std::size_t>(i - 1)];
                const Matrix6d W = SqrtOfInverse(s.scan.motion_covariance);
                const Vector6d r =
                    W * LogSE3(s.scan.motion.inverse() * p.T_world_base.inverse() * s.T_world_base);
                normal.AddBinary(i - 1, -W * AdjointSE3(s.T_world_base.inverse() * p.T_world_base),
                                 i, W, r);
            }
            if (s.scan.T_world_base_registered) {
                const Matrix6d &W = s.registration_sqrt_information;
                const Vector6d r =
                    W * LogSE3(s.scan.T_world_base_registered->inverse() * s.T_world_base);
                normal.AddUnary<6>(i, W, r);
            }
            if (s.scan.ground_base)
                AddGround(normal, i, *s.scan.ground_base, s.T_world_base.linear());
        }
        return normal;
    };
    // Levenberg-Marquardt: a Gauss-Newton step, damped until the cost goes down (a registration
    // far from the others makes the first-order Jacobians poor).
    std::vector<Eigen::Isometry3d> poses(static_cast<std::size_t>(n));
    for (int iteration = 0; iteration < config_.max_iterations; ++iteration) {
        const Normal normal = build();
        for (int i = 0; i < n; ++i) poses[i] = states_[static_cast<std::size_t>(i)].T_world_base;
        double lambda = 0.0;
        bool improved = false;
        VectorXd dx;
        for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
            MatrixXd H = normal.H;
            H.diagonal() += lambda * normal.H.diagonal();
            dx = -Eigen::LDLT<MatrixXd>(H).solve(normal.g);
            if (!dx.allFinite()) break;
            for (int i = 0; i < n; ++i)
                states_[static_cast<std::size_t>(i)].T_world_base =
                    Plus(poses[i], dx.segment<6>(6 * i));
            improved = build().cost <= normal.cost * (1.0 + 1e-12) + 1e-15;
            lambda = lambda == 0.0 ? 1e-3 : 10.0 * lambda;
        }
        if (!improved) {  // no step lowers the cost: the window stays where it was
            for (int i = 0; i < n; ++i)
                states_[static_cast<std::size_t>(i)].T_world_base = poses[i];
            break;
        }
        if (dx.lpNorm<Eigen::Infinity>() < 1e-9) break;
    }
    const Normal normal = build();
    const Eigen::LDLT<MatrixXd> ldlt(normal.H);
    const int m = std::min(n, 2);
    const MatrixXd columns = ldlt.solve(MatrixXd::Identity(6 * n, 6 * n).leftCols(6 * m));
    oldest_pair_covariance_.setZero();
    oldest_pair_covariance_.topLeftCorner(6 * m, 6 * m) = columns.topRows(6 * m);
    const MatrixXd newest = ldlt.solve(MatrixXd::Identity(6 * n, 6 * n).rightCols(6));
    newest_covariance_ = newest.bottomRows<6>();
    newest_covariance_ = 0.5 * (newest_covariance_ + newest_covariance_.transpose()).eval();
}

// The oldest pose leaves: written with the motion covariance from the previous one, its factors
// marginalised into an anchor on the next pose.
std::optional<SmoothedPose> PoseSmoother::PopOldest() {
    if (states_.empty()) return std::nullopt;
    const State &oldest = states_.front();
    SmoothedPose out;
    out.stamp_ns = oldest.scan.stamp_ns;
    out.T_world_base = oldest.T_world_base;
    out.motion_covariance = next_motion_covariance_;
    if (states_.size() >= 2) {
        const State &next = states_[1];
        const Eigen::Isometry3d D = next.T_world_base.inverse() * oldest.T_world_base;
        Eigen::Matrix<double, 6, 12> J;
        J << -AdjointSE3(D), Matrix6d::Identity();
        next_motion_covariance_ = J * oldest_pair_covariance_ * J.transpose();
        // Schur complement of the oldest pose's block in the factors that touch it.
        Normal local(2);
        local.AddUnary<6>(
            0, anchor_sqrt_information_,
            anchor_sqrt_information_ * LogSE3(anchor_mean_.inverse() * oldest.T_world_base));
        if (oldest.scan.T_world_base_registered) {
            const Matrix6d &W = oldest.registration_sqrt_information;
            local.AddUnary<6>(
                0, W,
                W * LogSE3(oldest.scan.T_world_base_registered->inverse() * oldest.T_world_base));
        }
        if (oldest.scan.ground_base)
            AddGround(local, 0, *oldest.scan.ground_base, oldest.T_world_base.linear());
        const Matrix6d W = SqrtOfInverse(next.scan.motion_covariance);
        local.AddBinary(0, -W * AdjointSE3(D), 1, W,
                        W * LogSE3(next.scan.motion.inverse() * oldest.T_world_base.inverse() *
                                   next.T_world_base));
        const Matrix6d H00 = local.H.topLeftCorner<6, 6>();
        const Eigen::LDLT<Matrix6d> H00_ldlt(H00);
        const Matrix6d H_p = local.H.bottomRightCorner<6, 6>() -
                             local.H.block<6, 6>(6, 0) * H00_ldlt.solve(local.H.block<6, 6>(0, 6));
        const Vector6d g_p =
            local.g.tail<6>() - local.H.block<6, 6>(6, 0) * H00_ldlt.solve(local.g.head<6>());
        const Matrix6d H_sym = 0.5 * (H_p + H_p.transpose());
        const Vector6d shift = -H_sym.ldlt().solve(g_p);
        anchor_mean_ = Plus(next.T_world_base, shift.allFinite() ? shift : Vector6d::Zero());
        anchor_sqrt_information_ = SqrtOfInformation(H_sym);
    }
    states_.pop_front();
    return out;
}

}  // namespace dorado::mapping
