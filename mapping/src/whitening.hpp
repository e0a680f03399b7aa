#pragma once
// Internal: whitening matrices from covariances.

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace dorado::mapping {

/// L^-1 for C = L L^T (a whitening matrix: |L^-1 e|^2 = e^T C^-1 e).
template <int N>
Eigen::Matrix<double, N, N> InverseCholeskyFactor(const Eigen::Matrix<double, N, N> &covariance) {
    const Eigen::Matrix<double, N, N> L = covariance.llt().matrixL();
    return L.template triangularView<Eigen::Lower>().solve(Eigen::Matrix<double, N, N>::Identity());
}

}  // namespace dorado::mapping
