#pragma once
// Internal: Ceres cost functors of the pose refinement (after Ceres' examples/slam/pose_graph_3d).
// Each pose is a position p (3) and a unit quaternion q (4, Eigen order x y z w, on
// ceres::EigenQuaternionManifold). Residuals are whitened: r^T r is the squared Mahalanobis norm.

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>

#include "dorado/core/lie.hpp"
#include "whitening.hpp"

namespace dorado::mapping {

// Registration residual of one correspondence: a scan point p_base (base frame) should lie on the
// local distribution of the map around q_world (world frame):
//
//   e = R_world_base * p_base + t_world_base - q_world,     r = W e,
//
// with W = L^-1, C = L L^T the covariance of e (the map neighbourhood's GICP-regularised shape
// scaled by the point noise). For a flat neighbourhood this is a soft point-to-plane distance.
//
// Analytic Jacobians (the residual is evaluated for hundreds of matches per Ceres iteration;
// automatic differentiation made it half the refinement's cost). With q = (u, w), Eigen's rotation
// of p is
//   f(u, w) = p + 2 w (u x p) + 2 u x (u x p) = p + 2 w (u x p) + 2 (u (u.p) - p (u.u)),
//   df/dw = 2 (u x p),   df/du = -2 w [p]x + 2 ((u.p) I + u p^T - 2 p u^T),
// and dr/dt = W, dr/dq = W [df/du | df/dw] (Eigen's x y z w order), as ceres::AutoDiff would give.
class RegistrationError : public ceres::SizedCostFunction<3, 3, 4> {
  public:
    RegistrationError(const Eigen::Vector3d &p_base, const Eigen::Vector3d &q_world,
                      const Eigen::Matrix3d &sqrt_information)
        : p_base_(p_base), q_world_(q_world), sqrt_information_(sqrt_information) {}

    bool Evaluate(double const *const *parameters, double *residuals_ptr,
                  double **jacobians) const override {
        Eigen::Map<const Eigen::Vector3d> t_world_base(parameters[0]);
        Eigen::Map<const Eigen::Vector3d> u(parameters[1]);
        const double w = parameters[1][3];
        const Eigen::Vector3d &p = p_base_;
        const Eigen::Vector3d u_x_p = u.cross(p);
        const Eigen::Vector3d rotated = p + 2.0 * w * u_x_p + 2.0 * u.cross(u_x_p);
        Eigen::Map<Eigen::Vector3d> residuals(residuals_ptr);
        residuals = sqrt_information_ * (rotated + t_world_base - q_world_);
        if (jacobians == nullptr) return true;
        if (jacobians[0] != nullptr) {
            Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J_t(jacobians[0]);
            J_t = sqrt_information_;
        }
        if (jacobians[1] != nullptr) {
            Eigen::Matrix<double, 3, 4> df_dq;
            df_dq.leftCols<3>() =
                -2.0 * w * Hat(p) + 2.0 * (u.dot(p) * Eigen::Matrix3d::Identity() +
                                           u * p.transpose() - 2.0 * p * u.transpose());
            df_dq.col(3) = 2.0 * u_x_p;
            Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> J_q(jacobians[1]);
            J_q = sqrt_information_ * df_dq;
        }
        return true;
    }

    static ceres::CostFunction *Create(const Eigen::Vector3d &p_base,
                                       const Eigen::Vector3d &q_world,
                                       const Eigen::Matrix3d &sqrt_information) {
        return new RegistrationError(p_base, q_world, sqrt_information);
    }

  private:
    Eigen::Vector3d p_base_;
    Eigen::Vector3d q_world_;
    Eigen::Matrix3d sqrt_information_;
};

// The radar velocity a candidate pose implies (Doppler-ICP made kinematic). The pose's motion
// since the previous (fixed) pose, T_rel = T_prev^-1 T, is read as a constant body twist over dt:
//
//   [rho; phi] = LogSE3(T_rel),   v_base = rho / dt,   omega_base = phi / dt   (base frame),
//   v_radar = R_base_radar^T (v_base + omega_base x t_base_radar)    (rigid body, paper eq. 5).
class RadarVelocityOfPose {
  public:
    RadarVelocityOfPose(const Eigen::Isometry3d &T_base_radar,
                        const Eigen::Isometry3d &T_world_base_prev, double dt_s)
        : R_base_radar_(T_base_radar.linear()),
          t_base_radar_(T_base_radar.translation()),
          q_world_prev_(T_world_base_prev.linear()),
          t_world_prev_(T_world_base_prev.translation()),
          dt_s_(dt_s) {}

    template <typename T>
    bool operator()(const T *const p_ptr, const T *const q_ptr, T *v_radar_ptr) const {
        using Vec3 = Eigen::Matrix<T, 3, 1>;
        Eigen::Map<const Vec3> t_world_base(p_ptr);
        Eigen::Map<const Eigen::Quaternion<T>> q_world_base(q_ptr);
        const Eigen::Quaternion<T> q_prev_inv = q_world_prev_.conjugate().cast<T>();
        const Eigen::Quaternion<T> q_rel = q_prev_inv * q_world_base;
        const Vec3 t_rel = q_prev_inv * (t_world_base - t_world_prev_.cast<T>());
        const Vec3 phi = LogQuaternion(q_rel);
        const Vec3 rho = LeftJacobianInverseTimes(phi, t_rel);
        const T inv_dt = T(1.0 / dt_s_);
        const Vec3 v_base = rho * inv_dt;
        const Vec3 omega_base = phi * inv_dt;
        Eigen::Map<Vec3> v_radar(v_radar_ptr);
        v_radar = R_base_radar_.transpose().cast<T>() *
                  (v_base + omega_base.cross(t_base_radar_.cast<T>()));
        return true;
    }

    // Rotation vector of a unit quaternion (the shorter way round).
    template <typename T>
    static Eigen::Matrix<T, 3, 1> LogQuaternion(Eigen::Quaternion<T> q) {
        if (q.w() < T(0)) q.coeffs() = -q.coeffs();
        const T sin_half_sq = q.vec().squaredNorm();
        if (sin_half_sq < T(1e-16)) return T(2.0) * q.vec() / q.w();  // Taylor, avoids sqrt(0)
        const T sin_half = sqrt(sin_half_sq);
        return (T(2.0) * atan2(sin_half, q.w()) / sin_half) * q.vec();
    }

    // J_l(phi)^-1 * t: the translation part of LogSE3 (closed form, Barfoot eq. 7.95).
    template <typename T>
    static Eigen::Matrix<T, 3, 1> LeftJacobianInverseTimes(const Eigen::Matrix<T, 3, 1> &phi,
                                                           const Eigen::Matrix<T, 3, 1> &t) {
        const T theta_sq = phi.squaredNorm();
        T coeff = T(1.0 / 12.0);
        if (theta_sq > T(1e-10)) {
            const T theta = sqrt(theta_sq);
            coeff = T(1.0) / theta_sq - (T(1.0) + cos(theta)) / (T(2.0) * theta * sin(theta));
        }
        const Eigen::Matrix<T, 3, 1> phi_x_t = phi.cross(t);
        return t - T(0.5) * phi_x_t + coeff * phi.cross(phi_x_t);
    }

  private:
    Eigen::Matrix3d R_base_radar_;
    Eigen::Vector3d t_base_radar_;
    Eigen::Quaterniond q_world_prev_;
    Eigen::Vector3d t_world_prev_;
    double dt_s_;
};

// RadarVelocityOfPose and its Jacobian, evaluated once per candidate pose: all the Doppler
// residuals of one refinement share it (they differ only in the ray and the measurement), so a
// Ceres iteration pays for one automatic differentiation of the pose's velocity, not one per
// point. Not thread-safe: the refinement runs Ceres with one thread.
class SharedRadarVelocity {
  public:
    using JacobianP = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
    using JacobianQ = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;

    SharedRadarVelocity(const Eigen::Isometry3d &T_base_radar,
                        const Eigen::Isometry3d &T_world_base_prev, double dt_s)
        : velocity_(new RadarVelocityOfPose(T_base_radar, T_world_base_prev, dt_s)) {}

    // The radar velocity at the pose (p, q); its Jacobians too when asked. False if Ceres'
    // automatic differentiation failed.
    bool Evaluate(const double *p, const double *q, bool with_jacobians) {
        const bool same_pose = valid_ && std::equal(p, p + 3, p_) && std::equal(q, q + 4, q_);
        if (same_pose && (has_jacobians_ || !with_jacobians)) return true;
        const double *parameters[] = {p, q};
        double *jacobians[] = {J_p_.data(), J_q_.data()};
        valid_ =
            velocity_.Evaluate(parameters, v_radar_.data(), with_jacobians ? jacobians : nullptr);
        has_jacobians_ = valid_ && with_jacobians;
        std::copy(p, p + 3, p_);
        std::copy(q, q + 4, q_);
        return valid_;
    }
    const Eigen::Vector3d &v_radar() const { return v_radar_; }
    const JacobianP &J_p() const { return J_p_; }
    const JacobianQ &J_q() const { return J_q_; }

  private:
    ceres::AutoDiffCostFunction<RadarVelocityOfPose, 3, 3, 4> velocity_;
    bool valid_ = false, has_jacobians_ = false;
    double p_[3] = {0, 0, 0}, q_[4] = {0, 0, 0, 0};
    Eigen::Vector3d v_radar_ = Eigen::Vector3d::Zero();
    JacobianP J_p_ = JacobianP::Zero();
    JacobianQ J_q_ = JacobianQ::Zero();
};

// Doppler residual of one static point:
//
//   predicted Doppler = -d_radar . v_radar(T)      (paper eq. 1, v_radar from the pose above),
//   r = (measured - predicted) / sigma = (measured + d_radar . v_radar) / sigma.
//
// Linear in v_radar, so its Jacobian is d^T dv_radar/d(p, q) / sigma from the shared velocity.
class DopplerError : public ceres::SizedCostFunction<1, 3, 4> {
  public:
    DopplerError(const Eigen::Vector3d &d_radar, double doppler_mps,
                 std::shared_ptr<SharedRadarVelocity> velocity, double sigma_mps)
        : d_radar_(d_radar),
          doppler_mps_(doppler_mps),
          velocity_(std::move(velocity)),
          sigma_mps_(sigma_mps) {}

    bool Evaluate(double const *const *parameters, double *residuals,
                  double **jacobians) const override {
        if (!velocity_->Evaluate(parameters[0], parameters[1], jacobians != nullptr)) return false;
        const double inv_sigma = 1.0 / sigma_mps_;
        residuals[0] = (doppler_mps_ + d_radar_.dot(velocity_->v_radar())) * inv_sigma;
        if (jacobians != nullptr) {
            if (jacobians[0] != nullptr) {
                Eigen::Map<Eigen::RowVector3d> J_p(jacobians[0]);
                J_p = inv_sigma * d_radar_.transpose() * velocity_->J_p();
            }
            if (jacobians[1] != nullptr) {
                Eigen::Map<Eigen::RowVector4d> J_q(jacobians[1]);
                J_q = inv_sigma * d_radar_.transpose() * velocity_->J_q();
            }
        }
        return true;
    }

    // One residual with its own velocity (tests); the refinement shares one velocity among all.
    static ceres::CostFunction *Create(const Eigen::Vector3d &d_radar, double doppler_mps,
                                       const Eigen::Isometry3d &T_base_radar,
                                       const Eigen::Isometry3d &T_world_base_prev, double dt_s,
                                       double sigma_mps) {
        return new DopplerError(
            d_radar, doppler_mps,
            std::make_shared<SharedRadarVelocity>(T_base_radar, T_world_base_prev, dt_s),
            sigma_mps);
    }

  private:
    Eigen::Vector3d d_radar_;
    double doppler_mps_;
    std::shared_ptr<SharedRadarVelocity> velocity_;
    double sigma_mps_;
};

// Prior residual (pose_graph_3d's relative-pose error against the predicted pose):
//
//   delta = T_prior^-1 T,   e = [delta_p; 2 vec(delta_q)]  (~ [rho; phi] to first order),
//   r = L^-1 e,  with C = L L^T the prior covariance (its Cholesky factor): r^T r = e^T C^-1 e.
class PriorError {
  public:
    PriorError(const Eigen::Isometry3d &T_world_base_prior, const Matrix6d &sqrt_information)
        : q_prior_(T_world_base_prior.linear()),
          t_prior_(T_world_base_prior.translation()),
          sqrt_information_(sqrt_information) {}

    template <typename T>
    bool operator()(const T *const p_ptr, const T *const q_ptr, T *residuals_ptr) const {
        Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_world_base(p_ptr);
        Eigen::Map<const Eigen::Quaternion<T>> q_world_base(q_ptr);
        Eigen::Map<Eigen::Matrix<T, 6, 1>> residuals(residuals_ptr);
        const Eigen::Quaternion<T> q_prior_inv = q_prior_.conjugate().cast<T>();
        const Eigen::Quaternion<T> delta_q = q_prior_inv * q_world_base;
        residuals.template head<3>() = q_prior_inv * (t_world_base - t_prior_.cast<T>());
        residuals.template tail<3>() = T(2.0) * delta_q.vec();
        residuals.applyOnTheLeft(sqrt_information_.template cast<T>());
        return true;
    }

    static ceres::CostFunction *Create(const Eigen::Isometry3d &T_world_base_prior,
                                       const Matrix6d &sqrt_information) {
        return new ceres::AutoDiffCostFunction<PriorError, 6, 3, 4>(
            new PriorError(T_world_base_prior, sqrt_information));
    }

  private:
    Eigen::Quaterniond q_prior_;
    Eigen::Vector3d t_prior_;
    Matrix6d sqrt_information_;
};

}  // namespace dorado::mapping
