#pragma once
/// @file mapper_fields.hpp
/// The mapper's configurable fields, listed once (core/config_fields.hpp): keys as in
/// configs/mapper.yaml's `mapper:` and `prior:` sections. The defaults are the structs'.

#include "dorado/core/config_fields.hpp"
#include "dorado/mapping/motion_prior.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::mapping {

inline Choices<RegistrationMethod> RegistrationMethodChoices() {
    return {{ToString(RegistrationMethod::kPointToPoint), RegistrationMethod::kPointToPoint},
            {ToString(RegistrationMethod::kPointToPlane), RegistrationMethod::kPointToPlane},
            {ToString(RegistrationMethod::kGicp), RegistrationMethod::kGicp}};
}
inline Choices<RobustKernel> RobustKernelChoices() {
    return {{ToString(RobustKernel::kNone), RobustKernel::kNone},
            {ToString(RobustKernel::kHuber), RobustKernel::kHuber},
            {ToString(RobustKernel::kCauchy), RobustKernel::kCauchy},
            {ToString(RobustKernel::kTukey), RobustKernel::kTukey}};
}
inline Choices<RegistrationCovarianceModel> RegistrationCovarianceChoices() {
    using M = RegistrationCovarianceModel;
    return {{ToString(M::kIndependent), M::kIndependent},
            {ToString(M::kResidualScale), M::kResidualScale},
            {ToString(M::kClustered), M::kClustered}};
}

/// The priors, in kAllPriorKinds' order (`dorado map --prior`, the bench's map_priors).
inline Choices<PriorKind> PriorKindChoices() {
    Choices<PriorKind> choices;
    for (const PriorKind kind : kAllPriorKinds) choices.emplace_back(ToString(kind), kind);
    return choices;
}

inline Choices<TwistIntegration> TwistIntegrationChoices() {
    return {{ToString(TwistIntegration::kTrapezoid), TwistIntegration::kTrapezoid},
            {ToString(TwistIntegration::kEndpoint), TwistIntegration::kEndpoint}};
}

template <typename Visitor>
void VisitFields(LocalMapConfig &c, Visitor &&v) {
    v("voxel_size_m", c.voxel_size_m, "map resolution and the cell of its search hash [m]");
    v("max_points_per_voxel", c.max_points_per_voxel, "points kept per map voxel");
    v("max_distance_m", c.max_distance_m,
      "voxels farther than this from the vehicle are dropped [m]");
}

template <typename Visitor>
void VisitFields(MoverConfig &c, Visitor &&v) {
    v("neighbour_radius_m", c.neighbour_radius_m,
      "points this close to a moving point of the same scan stay out of the map [m] (0: off)");
    v("memory_s", c.memory_s,
      "a map cell where something moved holds no point for this long [s] (0: off)");
    v("min_radial_speed_mps", c.min_radial_speed_mps,
      "a mask outlier is seen moving when its Doppler is this far from a static point's [m/s]");
    v("min_cluster_points", c.min_cluster_points,
      "...and this many such points lie within neighbour_radius_m");
}

template <typename Visitor>
void VisitFields(SmootherConfig &c, Visitor &&v) {
    v("lag_s", c.lag_s, "a pose is written (and enters the map) this long after its scan [s]");
    v("max_registration_chi2", c.max_registration_chi2,
      "a registration farther from the prediction (squared Mahalanobis) is down-weighted to "
      "this distance");
    v("max_iterations", c.max_iterations, "Gauss-Newton iterations per scan");
}

template <typename Visitor>
void VisitFields(MapperConfig &c, Visitor &&v) {
    v("min_range_m", c.min_range_m, "closer returns are dropped [m]");
    v("max_range_m", c.max_range_m, "farther returns are dropped [m]");
    v("scan_voxel_m", c.scan_voxel_m, "voxel of the downsampled scan that is registered [m]");
    v("max_source_points", c.max_source_points, "then evenly thinned to at most this many");
    VisitFields(c.map, Prefixed{"map.", v});
    VisitFields(c.movers, Prefixed{"movers.", v});
    v("keyframe_distance_m", c.keyframe_distance_m,
      "map updated after this distance [m] (0 and 0: every scan)");
    v("keyframe_angle_deg", c.keyframe_angle_deg, "...or this rotation [deg]");
    v("update_map_on_fallback", c.update_map_on_fallback,
      "a scan placed at the prior still fills the map");
    v("method", c.method, RegistrationMethodChoices(), "PCL registration");
    v("max_iterations", c.max_iterations, "PCL registration iterations");
    v("initial_threshold_m", c.initial_threshold_m,
      "adaptive correspondence threshold at the start [m]");
    v("min_threshold_m", c.min_threshold_m, "lower bound of the adaptive threshold [m]");
    v("min_motion_m", c.min_motion_m, "smaller corrections do not feed the adaptive threshold [m]");
    v("covariance_neighbours", c.covariance_neighbours,
      "k of the map's local planes (plane, GICP)");
    v("kernel", c.kernel, RobustKernelChoices(),
      "robust loss of the registration and Doppler residuals");
    v("kernel_scale", c.kernel_scale, "of the robust loss, in whitened units (sigmas)");
    v("point_sigma_m", c.point_sigma_m,
      "radar point noise that whitens the registration residuals [m]");
    v("plane_flatness", c.plane_flatness,
      "GICP-style eigenvalue of a map neighbourhood's normal axis");
    v("doppler_sigma_mps", c.doppler_sigma_mps, "Doppler residual noise [m/s]");
    v("use_doppler", c.use_doppler, "Doppler residuals (priors not built from them only)");
    v("max_registration_residuals", c.max_registration_residuals,
      "evenly thinned matches given to Ceres");
    v("max_doppler_residuals", c.max_doppler_residuals, "Doppler residuals given to Ceres");
    v("refine_max_iterations", c.refine_max_iterations, "Ceres iterations of the refinement");
    v("registration_covariance", c.registration_covariance, RegistrationCovarianceChoices(),
      "how the registration's residuals count against the prior");
    v("registration_cluster_m", c.registration_cluster_m,
      "cell of the clustered model's groups [m]");
    v("registration_floor_sigma_translation_m", c.registration_floor_sigma_translation_m,
      "registration noise no residual shows, added per axis [m]");
    v("registration_floor_sigma_rotation_rad", c.registration_floor_sigma_rotation_rad,
      "registration noise no residual shows, added per axis [rad]");
    v("registration_weak_ratio", c.registration_weak_ratio,
      "degeneracy-aware registration: weak eigenvalue fraction (0: off)");
    VisitFields(c.smoother, Prefixed{"smoother.", v});
    v("min_correspondences", c.min_correspondences, "fewer matches: nothing to register");
    v("max_rms_m", c.max_rms_m, "a larger correspondence RMS: nothing to register [m]");
    v("min_observability", c.min_observability,
      "lambda_min / lambda_max of the point-to-plane information");
}

template <typename Visitor>
void VisitFields(PriorNoiseConfig &c, Visitor &&v) {
    v("none_sigma_translation_m", c.none_sigma_translation_m,
      "`none`: motion since the previous scan, 1 sigma [m]");
    v("none_sigma_rotation_rad", c.none_sigma_rotation_rad,
      "`none`: rotation since the previous scan [rad]");
    v("constvel_sigma_accel_mps2", c.constvel_sigma_accel_mps2,
      "`constvel`: unmodelled acceleration [m/s^2]");
    v("constvel_sigma_angular_accel_radps2", c.constvel_sigma_angular_accel_radps2,
      "`constvel`: unmodelled angular acceleration [rad/s^2]");
    v("imu_gyro_sigma_radps", c.imu_gyro_sigma_radps, "`imu`: gyro noise [rad/s]");
    v("imu_accel_sigma_mps2", c.imu_accel_sigma_mps2, "`imu`: accelerometer noise [m/s^2]");
    v("imu_velocity_sigma_mps", c.imu_velocity_sigma_mps,
      "`imu`: start velocity of the integration [m/s]");
    v("gravity_world_mps2", c.gravity_world_mps2, "gravity in the world frame [m/s^2]");
    v("doppler_min_sigma_v_mps", c.doppler_min_sigma_v_mps,
      "`doppler`: floor on the velocity sigma [m/s]");
    v("doppler_min_sigma_omega_radps", c.doppler_min_sigma_omega_radps,
      "`doppler`: floor on the angular-rate sigma, per axis [rad/s]");
    v("doppler_integration", c.doppler_integration, TwistIntegrationChoices(),
      "`doppler`, `imu+doppler`: the interval's twist from the two scans' (trapezoid) or "
      "this scan's (endpoint)");
    v("doppler_with_constvel", c.doppler_with_constvel,
      "`doppler`, `imu+doppler`: fused with the constvel prediction from the last two poses");
}

}  // namespace dorado::mapping
