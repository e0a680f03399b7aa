#pragma once
// Internal: the pose graph's Ceres cost functors (named as in Ceres' examples/slam/pose_graph_3d).
// A node is a position p (3) and a unit quaternion q (4, Eigen's x y z w order, on
// ceres::EigenQuaternionManifold), T_world_node = (q, p). Residuals are whitened: r^T r is the
// squared Mahalanobis norm of the edge's error.

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dorado/core/lie.hpp"

namespace dorado::loops {

// A relative pose measured between nodes a and b, T_ab_measured, with the information Lambda of
// its error xi, the right perturbation in b's frame (T_ab_true = T_ab_measured ExpSE3(xi)):
//
//   T_ab_estimated = T_world_a^-1 T_world_b:  q_ab = q_a^-1 q_b,  p_ab = q_a^-1 (p_b - p_a),
//   dT = T_ab_measured^-1 T_ab_estimated:     dq = q_ab_measured^-1 q_ab,
//                                             dp = q_ab_measured^-1 (p_ab - p_ab_measured),
//   e = [dp; 2 vec(dq)]  (= LogSE3(dT) to first order; dq taken with w >= 0),
//   r = U e,  U^T U = Lambda  (U the transposed Cholesky factor: r^T r = e^T Lambda e).
//
// Unlike Ceres' example (whose errors are in a's frame), e is in b's frame: the convention of the
// mapper's written covariances, which are the right perturbation of the later pose.
class PoseGraph3dErrorTerm {
  public:
    PoseGraph3dErrorTerm(const Eigen::Isometry3d &T_ab_measured, const Matrix6d &sqrt_information)
        : p_ab_measured_(T_ab_measured.translation()),
          q_ab_measured_(T_ab_measured.rotation()),
          sqrt_information_(sqrt_information) {}

    template <typename T>
    bool operator()(const T *p_a_ptr, const T *q_a_ptr, const T *p_b_ptr, const T *q_b_ptr,
                    T *residuals_ptr) const {
        Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(p_a_ptr), p_b(p_b_ptr);
        Eigen::Map<const Eigen::Quaternion<T>> q_a(q_a_ptr), q_b(q_b_ptr);
        const Eigen::Quaternion<T> q_a_inverse = q_a.conjugate();
        const Eigen::Quaternion<T> q_ab = q_a_inverse * q_b;
        const Eigen::Matrix<T, 3, 1> p_ab = q_a_inverse * (p_b - p_a);
        const Eigen::Quaternion<T> q_measured_inverse = q_ab_measured_.conjugate().cast<T>();
        Eigen::Quaternion<T> dq = q_measured_inverse * q_ab;
        if (dq.w() < T(0)) dq.coeffs() = -dq.coeffs();  // the same rotation, the short way
        Eigen::Matrix<T, 6, 1> error;
        error.template head<3>() = q_measured_inverse * (p_ab - p_ab_measured_.cast<T>());
        error.template tail<3>() = T(2.0) * dq.vec();
        Eigen::Map<Eigen::Matrix<T, 6, 1>> residuals(residuals_ptr);
        residuals = sqrt_information_.cast<T>() * error;
        return true;
    }

    static ceres::CostFunction *Create(const Eigen::Isometry3d &T_ab_measured,
                                       const Matrix6d &sqrt_information) {
        return new ceres::AutoDiffCostFunction<PoseGraph3dErrorTerm, 6, 3, 4, 3, 4>(
            new PoseGraph3dErrorTerm(T_ab_measured, sqrt_information));
    }

    EIGEN_MAKE_ALIGNED_OPERATOR_NEW

  private:
    Eigen::Vector3d p_ab_measured_;
    Eigen::Quaterniond q_ab_measured_;
    Matrix6d sqrt_information_;
};

// A loop edge that can be switched off (switchable constraints, Suenderhauf and Protzel, IROS
// 2012): PoseGraph3dErrorTerm's residual scaled by the edge's switch s in [0, 1] (the bounds are
// the problem's), r = s U e. Alone it would be minimised by s = 0: SwitchPriorErrorTerm holds s
// near 1, so an edge stays on unless its error costs more than the switch's prior.
class SwitchableLoopErrorTerm {
  public:
    SwitchableLoopErrorTerm(const Eigen::Isometry3d &T_ab_measured,
                            const Matrix6d &sqrt_information)
        : edge_(T_ab_measured, sqrt_information) {}

    template <typename T>
    bool operator()(const T *p_a, const T *q_a, const T *p_b, const T *q_b, const T *s,
                    T *residuals_ptr) const {
        if (!edge_(p_a, q_a, p_b, q_b, residuals_ptr)) return false;
        Eigen::Map<Eigen::Matrix<T, 6, 1>> residuals(residuals_ptr);
        residuals *= s[0];
        return true;
    }

    static ceres::CostFunction *Create(const Eigen::Isometry3d &T_ab_measured,
                                       const Matrix6d &sqrt_information) {
        return new ceres::AutoDiffCostFunction<SwitchableLoopErrorTerm, 6, 3, 4, 3, 4, 1>(
            new SwitchableLoopErrorTerm(T_ab_measured, sqrt_information));
    }

  private:
    PoseGraph3dErrorTerm edge_;
};

// The prior of a loop edge's switch: r = (1 - s) / sigma.
class SwitchPriorErrorTerm {
  public:
    explicit SwitchPriorErrorTerm(double sigma) : sigma_(sigma) {}

    template <typename T>
    bool operator()(const T *s, T *residual) const {
        residual[0] = (T(1.0) - s[0]) / T(sigma_);
        return true;
    }

    static ceres::CostFunction *Create(double sigma) {
        return new ceres::AutoDiffCostFunction<SwitchPriorErrorTerm, 1, 1>(
            new SwitchPriorErrorTerm(sigma));
    }

  private:
    double sigma_;
};

// The whitening factor U of an information matrix Lambda = U^T U (upper Cholesky factor).
inline Matrix6d SqrtInformation(const Matrix6d &information) {
    return information.llt().matrixU();
}

}  // namespace dorado::loops
