#pragma once
// Internal: scan-to-map registration in the plane for 2D radars (planar mode): 3 degrees of
// freedom (x, y, yaw) as the right perturbation xi = (rho_x, rho_y, phi_z) of a pose, whose z,
// roll and pitch are the prior's (held). The same steps as the 3-D path (radar_mapper.cpp):
// alignment from the prior (here a point-to-point ICP in the plane, Gauss-Newton with the robust
// kernel's weights), the checks, the registered pose (registration + the prediction) and the
// registration's clustered covariance, which the smoother weighs it by. The Doppler enters
// through the prior (doppler, imu+doppler) and the static mask, as in 3-D.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "dorado/mapping/local_map.hpp"
#include "dorado/mapping/motion_prior.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::mapping {

/// The 3 planar components (x, y, yaw) of a 6-vector or 6x6 matrix in the xi = [rho; phi] order.
inline constexpr int kPlanarAxes[3] = {0, 1, 5};

/// T * Exp(xi) with xi = (rho_x, rho_y, 0, 0, 0, phi_z): a move in the base's own plane.
[[nodiscard]] Eigen::Isometry3d PlanarPlus(const Eigen::Isometry3d &T, const Eigen::Vector3d &d);

/// (rho_x, rho_y, phi_z) of Log(T_a^-1 T_b): how far b is from a in a's plane.
[[nodiscard]] Eigen::Vector3d PlanarMinus(const Eigen::Isometry3d &T_a,
                                          const Eigen::Isometry3d &T_b);

struct PlanarRegistration {
    FallbackCause cause = FallbackCause::kNone;  ///< kNone: registered
    std::string detail;
    int count = 0;  ///< matches within the threshold at the aligned pose
    double rms_m = 0.0;
    /// lambda_min / lambda_max of the matched points' 2-D scatter (0: all on one line).
    double observability = 0.0;
    /// The registered pose; its covariance's held axes are the prediction's, its information
    /// zero there.
    RegisteredPose registered;
    Eigen::Isometry3d T_world_base_aligned = Eigen::Isometry3d::Identity();  ///< the ICP alone
    double alignment_ms = 0.0, registration_ms = 0.0, refinement_ms = 0.0;
};

/// One scan's planar registration from the prediction (the alignment's start and the registered
/// pose's prior).
[[nodiscard]] PlanarRegistration RegisterPlanar(const Eigen::Matrix3Xd &source_base,
                                                const MotionPrior &prediction, const LocalMap &map,
                                                const MapperConfig &config, double threshold_m);

}  // namespace dorado::mapping
