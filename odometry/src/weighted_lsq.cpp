// Weighted least squares of eq. (2) on a masked subset of the Doppler system.
#include <Eigen/Cholesky>
#include <cmath>

#include "robust_fit.hpp"

namespace dorado::odometry::internal {

void DopplerSystem::Resize(Eigen::Index n) {
    A.resize(n, 3);
    b.resize(n);
    w.resize(n);
    gate2.resize(n);
    cell.resize(n);
}

Eigen::Matrix3d Gram(const Eigen::Matrix<double, Eigen::Dynamic, 3> &X,
                     const Eigen::Matrix<double, Eigen::Dynamic, 3> &Y) {
    Eigen::Matrix3d G;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) G(i, j) = X.col(i).dot(Y.col(j));
    return G;
}

Eigen::Matrix3d SymmetricGram(const Eigen::Matrix<double, Eigen::Dynamic, 3> &X,
                              const Eigen::Matrix<double, Eigen::Dynamic, 3> &Y) {
    Eigen::Matrix3d G;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) G(i, j) = G(j, i) = X.col(i).dot(Y.col(j));
    return G;
}

namespace {

bool Solve(const DopplerSystem &system, const Eigen::VectorXd &mask, Eigen::VectorXd &weighted,
           Eigen::Matrix<double, Eigen::Dynamic, 3> &weighted_A, Eigen::Vector3d &v,
           Eigen::Matrix3d &AtWA) {
    const Eigen::Index n = system.size();
    weighted.resize(n);
    weighted_A.resize(n, 3);
    weighted.array() = system.w.head(n).array() * mask.head(n).array();
    // eq. (2): v = (A^T W A)^-1 (A^T W b), W = diag(w_i * mask_i).
    weighted_A = system.A.array().colwise() * weighted.array();
    AtWA = SymmetricGram(weighted_A, system.A);
    const Eigen::Vector3d AtWb(weighted_A.col(0).dot(system.b), weighted_A.col(1).dot(system.b),
                               weighted_A.col(2).dot(system.b));
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(AtWA);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
    // A pivot of ~0 means the weighted directions span less than 3-D.
    const double max_pivot = ldlt.vectorD().maxCoeff();
    if (!(ldlt.vectorD().minCoeff() > 1e-12 * max_pivot)) return false;
    v = ldlt.solve(AtWb);
    return v.allFinite();
}

int Classify(const DopplerSystem &system, const Eigen::Vector3d &v, Eigen::VectorXd &residual,
             Eigen::VectorXd &mask) {
    const Eigen::Index n = system.size();
    residual.resize(n);
    mask.resize(n);
    residual.noalias() = system.A * v;
    residual -= system.b;
    mask = (residual.array().square() < system.gate2.array()).cast<double>();
    return static_cast<int>(mask.sum());
}

}  // namespace

void Unwrap(DopplerSystem &system, const Eigen::Vector3d &v) {
    const double span = system.alias_span;
    if (!(span > 0.0)) return;
    const Eigen::Index n = system.size();
    for (Eigen::Index i = 0; i < n; ++i)
        system.b[i] += span * std::round((system.A.row(i).dot(v) - system.b[i]) / span);
}

bool SolveWeighted(const DopplerSystem &system, const Eigen::VectorXd &mask, Workspace &ws,
                   Eigen::Vector3d &v, Eigen::Matrix3d &AtWA) {
    return Solve(system, mask, ws.weighted, ws.weighted_A, v, AtWA);
}

bool SolveWeighted(const DopplerSystem &system, const Eigen::VectorXd &mask, Scratch &scratch,
                   Eigen::Vector3d &v, Eigen::Matrix3d &AtWA) {
    return Solve(system, mask, scratch.weighted, scratch.weighted_A, v, AtWA);
}

int ClassifyInliers(DopplerSystem &system, const Eigen::Vector3d &v, Workspace &ws,
                    Eigen::VectorXd &mask) {
    Unwrap(system, v);
    return Classify(system, v, ws.residual, mask);
}

int ClassifyInliers(DopplerSystem &system, const Eigen::Vector3d &v, Scratch &scratch) {
    Unwrap(system, v);
    return Classify(system, v, scratch.residual, scratch.mask);
}

}  // namespace dorado::odometry::internal
