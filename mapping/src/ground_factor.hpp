#pragma once
// Internal: the ground's residual on the absolute roll and pitch of a pose (refinement.cpp).

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/measurements.hpp"
#include "whitening.hpp"

namespace dorado::mapping {

// The road's up-vector seen in the base frame, n_base (the plane fit's normal), against the one
// the pose implies, the world's Z axis in the base frame:
//
//   u(q) = R_world_base^T e_z = (-sin p, sin r cos p, cos r cos p)   (ZYX roll r, pitch p),
//   r = W (n_base - u(q))_xy,    W^T W = C^-1,
//
// C the covariance of n_base's x and y (the fit's and the road's slope about level). Yaw and
// position do not enter: the ground says nothing about them. Parameter: the quaternion (x y z w).
class GroundUpError {
  public:
    GroundUpError(const Eigen::Vector3d &up_base, const Eigen::Matrix2d &sqrt_information)
        : up_base_(up_base), sqrt_information_(sqrt_information) {}

    template <typename T>
    bool operator()(const T *const q_ptr, T *residuals_ptr) const {
        Eigen::Map<const Eigen::Quaternion<T>> q_world_base(q_ptr);
        const Eigen::Matrix<T, 3, 1> up_of_pose =
            q_world_base.conjugate() * Eigen::Matrix<T, 3, 1>(T(0), T(0), T(1));
        const Eigen::Matrix<T, 2, 1> e =
            up_base_.head<2>().cast<T>() - up_of_pose.template head<2>();
        Eigen::Map<Eigen::Matrix<T, 2, 1>> residuals(residuals_ptr);
        residuals = sqrt_information_.cast<T>() * e;
        return true;
    }

    static ceres::CostFunction *Create(const GroundUp &ground) {
        return new ceres::AutoDiffCostFunction<GroundUpError, 2, 4>(
            new GroundUpError(ground.up_base, InverseCholeskyFactor<2>(ground.covariance)));
    }

  private:
    Eigen::Vector3d up_base_;
    Eigen::Matrix2d sqrt_information_;
};

// The innovation test of a ground observation at a pose whose rotation has covariance
// cov_rotation (right perturbation R Exp(phi), base frame): with u = R^T e_z,
// du/dphi = [u]x, so the innovation's covariance is C + H cov_rotation H^T, H = [u]x's x, y rows.
// True when the squared Mahalanobis distance is within the observation's gate (or it has none).
inline bool GroundConsistent(const GroundUp &ground, const Eigen::Isometry3d &T_world_base,
                             const Eigen::Matrix3d &cov_rotation) {
    if (!(ground.max_innovation_chi2 > 0.0)) return true;
    const Eigen::Vector3d u = T_world_base.linear().transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector2d innovation = ground.up_base.head<2>() - u.head<2>();
    const Eigen::Matrix<double, 2, 3> H = Hat(u).topRows<2>();
    const Eigen::Matrix2d S = ground.covariance + H * cov_rotation * H.transpose();
    const double chi2 = innovation.dot(S.ldlt().solve(innovation));
    return chi2 <= ground.max_innovation_chi2;
}

}  // namespace dorado::mapping
