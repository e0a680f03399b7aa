// The vehicle constraint on the ego-velocity: a Kalman update with v_base,y = v_base,z = 0.
#include "dorado/odometry/vehicle_velocity_prior.hpp"

#include <Eigen/Cholesky>

namespace dorado::odometry {

ConstrainedVelocity ApplyVehicleVelocityPrior(const VehicleVelocityPrior &prior,
                                              const Eigen::Matrix3d &A, const Eigen::Vector3d &c,
                                              const Eigen::Vector3d &v_radar,
                                              const Eigen::Matrix3d &cov_v_radar) {
    ConstrainedVelocity out{v_radar, cov_v_radar};
    if (!prior.enabled) return out;
    const Eigen::Matrix<double, 2, 3> H = A.bottomRows<2>();
    const Eigen::Vector2d innovation = H * v_radar + c.tail<2>();  // predicted minus 0
    Eigen::Matrix2d S = H * cov_v_radar * H.transpose();
    S(0, 0) += prior.sigma_lateral_mps * prior.sigma_lateral_mps;
    S(1, 1) += prior.sigma_vertical_mps * prior.sigma_vertical_mps;
    // K = C H^T S^-1 (S is symmetric positive definite: the prior's variances are > 0).
    const Eigen::Matrix<double, 3, 2> K =
        S.ldlt().solve(H * cov_v_radar.transpose()).transpose();
    out.v_radar_mps = v_radar - K * innovation;
    const Eigen::Matrix3d C = cov_v_radar - K * H * cov_v_radar;
    out.cov_v_radar = 0.5 * (C + C.transpose());
    return out;
}

}  // namespace dorado::odometry
