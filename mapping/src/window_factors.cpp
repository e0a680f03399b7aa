// The white-noise-on-acceleration factor (derivation in window_factors.hpp).
#include "window_factors.hpp"

#include "whitening.hpp"

namespace dorado::mapping {

namespace {

using RowMajor34 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;

// d (R(q)^T a) / d [u, s] for q = (u, s), Eigen's x y z w order.
RowMajor34 ConjugateRotationJacobian(const Eigen::Vector3d &u, double s, const Eigen::Vector3d &a) {
    RowMajor34 J;
    J.leftCols<3>() = 2.0 * s * Hat(a) + 2.0 * (u.dot(a) * Eigen::Matrix3d::Identity() +
                                                u * a.transpose() - 2.0 * a * u.transpose());
    J.col(3) = -2.0 * u.cross(a);
    return J;
}

}  // namespace

WnoaError::Matrix12 WnoaError::Covariance(double dt_s, const Vector6d &qc) {
    const Matrix6d Qc = qc.asDiagonal();
    Matrix12 Q;
    Q << dt_s * dt_s * dt_s / 3.0 * Qc, dt_s * dt_s / 2.0 * Qc,  //
        dt_s * dt_s / 2.0 * Qc, dt_s * Qc;
    return Q;
}

WnoaError::WnoaError(double dt_s, const Vector6d &qc_diag)
    : dt_s_(dt_s), sqrt_information_(InverseCholeskyFactor<12>(Covariance(dt_s, qc_diag))) {}

bool WnoaError::Evaluate(double const *const *parameters, double *residuals_ptr,
                         double **jacobians) const {
    Eigen::Map<const Eigen::Vector3d> p_i(parameters[0]), v_i(parameters[2]), w_i(parameters[3]);
    Eigen::Map<const Eigen::Vector3d> p_j(parameters[4]), v_j(parameters[6]), w_j(parameters[7]);
    const Eigen::Quaterniond q_i = Eigen::Map<const Eigen::Quaterniond>(parameters[1]);
    const Eigen::Quaterniond q_j = Eigen::Map<const Eigen::Quaterniond>(parameters[5]);
    const double dt = dt_s_;
    const Eigen::Vector3d a = p_j - p_i;
    const Eigen::Quaterniond c = q_i.conjugate() * q_j;
    // q and -q are the same rotation: take the shorter way round (w >= 0), else e_r flips sign when
    // a pose's quaternion crosses hemispheres (yaw through +-180 deg gave 5 deg RPE spikes).
    const double sign = c.w() < 0.0 ? -1.0 : 1.0;

    Eigen::Matrix<double, 12, 1> e;
    e.segment<3>(0) = q_i.conjugate() * a - dt * v_i - 0.5 * dt * dt * w_i.cross(v_i);
    e.segment<3>(3) = 2.0 * sign * c.vec() - dt * w_i;
    e.segment<3>(6) = v_j - v_i;
    e.segment<3>(9) = w_j - w_i;
    Eigen::Map<Eigen::Matrix<double, 12, 1>> residuals(residuals_ptr);
    residuals = sqrt_information_ * e;
    if (jacobians == nullptr) return true;

    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d R_i_T = q_i.conjugate().toRotationMatrix();
    // Raw Jacobians of e (12 x block size), whitened on the way out.
    auto write = [&](int k, const auto &E) {
        if (jacobians[k] == nullptr) return;
        constexpr int kCols = std::decay_t<decltype(E)>::ColsAtCompileTime;
        Eigen::Map<Eigen::Matrix<double, 12, kCols, Eigen::RowMajor>> J(jacobians[k]);
        J = sqrt_information_ * E;
    };
    Eigen::Matrix<double, 12, 3> E3;
    Eigen::Matrix<double, 12, 4> E4;

    E3.setZero();  // p_i
    E3.block<3, 3>(0, 0) = -R_i_T;
    write(0, E3);
    E4.setZero();  // q_i: conjugate rotation of a, and vec(q_i^* q_j) through a = q_i^*
    E4.block<3, 4>(0, 0) = ConjugateRotationJacobian(q_i.vec(), q_i.w(), a);
    E4.block<3, 3>(3, 0) = -2.0 * sign * (q_j.w() * I - Hat(q_j.vec()));
    E4.block<3, 1>(3, 3) = 2.0 * sign * q_j.vec();
    write(1, E4);
    E3.setZero();  // v_i
    E3.block<3, 3>(0, 0) = -dt * I - 0.5 * dt * dt * Hat(w_i);
    E3.block<3, 3>(6, 0) = -I;
    write(2, E3);
    E3.setZero();  // w_i
    E3.block<3, 3>(0, 0) = 0.5 * dt * dt * Hat(v_i);
    E3.block<3, 3>(3, 0) = -dt * I;
    E3.block<3, 3>(9, 0) = -I;
    write(3, E3);
    E3.setZero();  // p_j
    E3.block<3, 3>(0, 0) = R_i_T;
    write(4, E3);
    E4.setZero();  // q_j
    E4.block<3, 3>(3, 0) = 2.0 * sign * (q_i.w() * I - Hat(q_i.vec()));
    E4.block<3, 1>(3, 3) = -2.0 * sign * q_i.vec();
    write(5, E4);
    E3.setZero();  // v_j
    E3.block<3, 3>(6, 0) = I;
    write(6, E3);
    E3.setZero();  // w_j
    E3.block<3, 3>(9, 0) = I;
    write(7, E3);
    return true;
}

}  // namespace dorado::mapping
