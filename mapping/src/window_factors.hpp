#pragma once
// Internal: the fixed-lag smoother's Ceres factors, after Ceres' pose_graph_3d. A state
// is a pose (p: 3, q: 4 in Eigen's x y z w order on ceres::EigenQuaternionManifold, T_world_base)
// and a body twist (v: 3, w: 3, the base frame's linear and angular velocity in the base frame).
// Every residual is whitened (r^T r = squared Mahalanobis norm) and every Jacobian is analytic
// (tests/mapping/test_window_factors.cpp checks them with ceres::GradientChecker).

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dorado/core/lie.hpp"

namespace dorado::mapping {

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

// Doppler residual of one static point on the twist of its scan (paper eq. 1 and 3):
//   v_radar = R_base_radar^T (v + w x t_base_radar),   r = (doppler + d_radar . v_radar) / sigma.
// Linear in (v, w): dr/dv = d^T R^T / sigma, dr/dw = -d^T R^T [t]x / sigma (w x t = -[t]x w).
class TwistDopplerError : public ceres::SizedCostFunction<1, 3, 3> {
  public:
    TwistDopplerError(const Eigen::Vector3d &d_radar, double doppler_mps,
                      const Eigen::Isometry3d &T_base_radar, double sigma_mps)
        : doppler_mps_(doppler_mps), inv_sigma_(1.0 / sigma_mps) {
        g_v_ = T_base_radar.linear() * d_radar;  // d^T R^T as a column
        g_w_ = -Hat(T_base_radar.translation()).transpose() * g_v_;
    }

    bool Evaluate(double const *const *parameters, double *residuals,
                  double **jacobians) const override {
        Eigen::Map<const Eigen::Vector3d> v(parameters[0]), w(parameters[1]);
        residuals[0] = (doppler_mps_ + g_v_.dot(v) + g_w_.dot(w)) * inv_sigma_;
        if (jacobians == nullptr) return true;
        if (jacobians[0] != nullptr) Eigen::Map<Eigen::Vector3d>{jacobians[0]} = g_v_ * inv_sigma_;
        if (jacobians[1] != nullptr) Eigen::Map<Eigen::Vector3d>{jacobians[1]} = g_w_ * inv_sigma_;
        return true;
    }

  private:
    double doppler_mps_, inv_sigma_;
    Eigen::Vector3d g_v_, g_w_;
};

// The paper's kinematic model (eq. 3-4 and omega_x = 0) as a soft factor, in the base frame (origin
// at the rear-axle centre): the rear axle has no lateral velocity, the Y-ICR point (m, 0, z) no
// vertical velocity, the body no roll rate,
//   e = [v_y;  v_z - m w_y;  w_x],   r = diag(1 / sigma) e,
// with the sigmas of vehicle.model_noise (KinematicModelNoise) evaluated at the state's initial
// twist (their speed and yaw-rate terms), so the factor stays linear.
class KinematicError : public ceres::SizedCostFunction<3, 3, 3> {
  public:
    KinematicError(double half_wheelbase_m, const Eigen::Vector3d &sigmas)
        : m_(half_wheelbase_m), inv_sigma_(sigmas.cwiseInverse()) {}

    bool Evaluate(double const *const *parameters, double *residuals,
                  double **jacobians) const override {
        Eigen::Map<const Eigen::Vector3d> v(parameters[0]), w(parameters[1]);
        residuals[0] = v.y() * inv_sigma_(0);
        residuals[1] = (v.z() - m_ * w.y()) * inv_sigma_(1);
        residuals[2] = w.x() * inv_sigma_(2);
        if (jacobians == nullptr) return true;
        if (jacobians[0] != nullptr) {
            Eigen::Map<RowMajor3> J(jacobians[0]);
            J.setZero();
            J(0, 1) = inv_sigma_(0);
            J(1, 2) = inv_sigma_(1);
        }
        if (jacobians[1] != nullptr) {
            Eigen::Map<RowMajor3> J(jacobians[1]);
            J.setZero();
            J(1, 1) = -m_ * inv_sigma_(1);
            J(2, 0) = inv_sigma_(2);
        }
        return true;
    }

  private:
    double m_;
    Eigen::Vector3d inv_sigma_;
};

// Gyro factor: the mean gyro rate of the scan interval, rotated into the base frame, measures the
// body rate plus the gyro bias: r = (gyro_base - w - b) / sigma.
class GyroError : public ceres::SizedCostFunction<3, 3, 3> {
  public:
    GyroError(const Eigen::Vector3d &gyro_base_radps, double sigma_radps)
        : gyro_(gyro_base_radps), inv_sigma_(1.0 / sigma_radps) {}

    bool Evaluate(double const *const *parameters, double *residuals,
                  double **jacobians) const override {
        Eigen::Map<const Eigen::Vector3d> w(parameters[0]), b(parameters[1]);
        Eigen::Map<Eigen::Vector3d>{residuals} = (gyro_ - w - b) * inv_sigma_;
        for (int k = 0; k < 2 && jacobians != nullptr; ++k)
            if (jacobians[k] != nullptr)
                Eigen::Map<RowMajor3>{jacobians[k]} = -inv_sigma_ * Eigen::Matrix3d::Identity();
        return true;
    }

  private:
    Eigen::Vector3d gyro_;
    double inv_sigma_;
};

// A Gaussian prior on a 3-vector (the gyro bias): r = (x - mean) / sigma.
class VectorPriorError : public ceres::SizedCostFunction<3, 3> {
  public:
    VectorPriorError(const Eigen::Vector3d &mean, double sigma) : mean_(mean), inv_(1.0 / sigma) {}
    bool Evaluate(double const *const *parameters, double *residuals,
                  double **jacobians) const override {
        Eigen::Map<Eigen::Vector3d>{residuals} =
            (Eigen::Map<const Eigen::Vector3d>(parameters[0]) - mean_) * inv_;
        if (jacobians != nullptr && jacobians[0] != nullptr)
            Eigen::Map<RowMajor3>{jacobians[0]} = inv_ * Eigen::Matrix3d::Identity();
        return true;
    }

  private:
    Eigen::Vector3d mean_;
    double inv_;
};

// White-noise-on-acceleration motion prior between consecutive states i and j (as in steam_icp /
// Barfoot's continuous-time estimation: the body twist is a random walk driven by white
// acceleration of power spectral density Qc = diag(qc_v, qc_w)). With dt = t_j - t_i,
//
//   e_t = R_i^T (p_j - p_i) - dt v_i - dt^2/2 (w_i x v_i)   (translation of T_i^-1 T_j against a
//                                                            constant twist, to second order)
//   e_r = 2 vec(q_i^* q_j) - dt w_i                          (~ Log(R_i^T R_j) - dt w_i; the sign
//   of
//                                                            q_i^* q_j is taken with w >= 0)
//   e_v = v_j - v_i,   e_w = w_j - w_i                       (J_r^-1(xi) ~ I within a scan)
//
//   Q = [dt^3/3 Qc, dt^2/2 Qc; dt^2/2 Qc, dt Qc],   r = L^-1 [e_t; e_r; e_v; e_w],   Q = L L^T.
//
// Parameter blocks: p_i, q_i, v_i, w_i, p_j, q_j, v_j, w_j. The rotation derivatives use, for the
// conjugate rotation of a by q = (u, s):  R^T a = a - 2 s (u x a) + 2 u x (u x a),
//   d/du = 2 s [a]x + 2 ((u.a) I + u a^T - 2 a u^T),   d/ds = -2 (u x a),
// and for c = a (x) b:  d vec c / d vec b = a_w I + [a_vec]x,  d vec c / d b_w = a_vec,
//                       d vec c / d vec a = b_w I - [b_vec]x,  d vec c / d a_w = b_vec.
class WnoaError : public ceres::SizedCostFunction<12, 3, 4, 3, 3, 3, 4, 3, 3> {
  public:
    using Matrix12 = Eigen::Matrix<double, 12, 12>;

    WnoaError(double dt_s, const Vector6d &qc_diag);

    // The covariance Q above (tests compare it with a simulated random walk).
    static Matrix12 Covariance(double dt_s, const Vector6d &qc_diag);

    bool Evaluate(double const *const *parameters, double *residuals,
                  double **jacobians) const override;

  private:
    double dt_s_;
    Matrix12 sqrt_information_;
};

}  // namespace dorado::mapping
