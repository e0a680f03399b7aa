#pragma once
// Internal: the information (inverse covariance) that each side of the refinement brings about the
// new pose, in one tangent convention: the right perturbation xi = [rho; phi] of T_world_base,
// T_true = T * ExpSE3(xi), i.e. expressed in the base frame (MotionPrior's convention).
//
// The registration's information is the part that is easy to over-count: a few hundred point
// residuals whitened by a per-point noise model are not a few hundred independent measurements
// (neighbouring points see the same map surface and share its error, the map itself carries the
// errors of the poses it was built from). RegistrationCovariance estimates it from the residuals
// (mapping/include/dorado/mapping/radar_mapper.hpp: RegistrationCovarianceModel).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "dorado/core/lie.hpp"
#include "registration.hpp"

namespace ceres {
class LossFunction;
}

namespace dorado::mapping {

/// d(t, q)/d(xi) for the right perturbation of a pose stored as t (3) and an Eigen quaternion
/// q (x, y, z, w): t' = t + R rho, q' = q (x) [phi / 2; 1]. A 7 x 6 matrix.
[[nodiscard]] Eigen::Matrix<double, 7, 6> RightPerturbationLift(const Eigen::Quaterniond &q);

/// The registered pose T_world_base (a minimum of its residuals) with its covariance from its
/// matches, robustified by loss (nullptr = none), by the configured model, plus the registration's
/// own floor (registration_floor_sigma_*: what no single scan's residuals can show, e.g. the map's
/// error). Not valid with fewer than 3 matches or a singular information.
[[nodiscard]] RegisteredPose RegistrationCovariance(const Eigen::Isometry3d &T_world_base,
                                                    const std::vector<Correspondence> &matches,
                                                    const ceres::LossFunction *loss,
                                                    const MapperConfig &config);

/// Information of the Doppler residuals about the pose (sum of J^T w J in the xi convention).
[[nodiscard]] Matrix6d DopplerInformation(const Eigen::Isometry3d &T_world_base,
                                          const std::vector<DopplerObservation> &doppler,
                                          const Eigen::Isometry3d &T_world_base_prev,
                                          const Eigen::Isometry3d &T_base_radar, double dt_s,
                                          const ceres::LossFunction *loss,
                                          const MapperConfig &config);

/// Ad(T) in the xi = [rho; phi] convention: T ExpSE3(xi) = ExpSE3(Ad(T) xi) T.
[[nodiscard]] Matrix6d AdjointSE3(const Eigen::Isometry3d &T);

/// (sum of the informations)^-1, symmetrised; a covariance of zeros-to-infinity is never returned:
/// the sum is regularised by 1e-12 on its diagonal.
[[nodiscard]] Matrix6d CovarianceFromInformation(const Matrix6d &information);

}  // namespace dorado::mapping
