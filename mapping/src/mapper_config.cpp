// The mapper's settings: their validation and the one spelling of each choice (radar_mapper.hpp).
#include <cmath>
#include <stdexcept>
#include <string>

#include "dorado/core/require.hpp"
#include "dorado/mapping/mapper_fields.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::mapping {

void MapperConfig::Validate() const {
    Require(min_range_m >= 0.0 && std::isfinite(min_range_m), "mapper.min_range_m", "must be >= 0");
    Require(max_range_m > min_range_m, "mapper.max_range_m", "must be > min_range_m");
    Require(scan_voxel_m > 0.0 && std::isfinite(scan_voxel_m), "mapper.scan_voxel_m",
            "must be > 0");
    map.Validate();
    movers.Validate();
    smoother.Validate();
    Require(keyframe_distance_m >= 0.0, "mapper.keyframe_distance_m", "must be >= 0");
    Require(keyframe_angle_deg >= 0.0, "mapper.keyframe_angle_deg", "must be >= 0");
    Require(max_source_points >= 10, "mapper.max_source_points", "must be >= 10");
    Require(max_iterations >= 1, "mapper.max_iterations", "must be >= 1");
    Require(initial_threshold_m > 0.0, "mapper.initial_threshold_m", "must be > 0");
    Require(min_threshold_m > 0.0, "mapper.min_threshold_m", "must be > 0");
    Require(min_motion_m >= 0.0, "mapper.min_motion_m", "must be >= 0");
    Require(covariance_neighbours >= 3, "mapper.covariance_neighbours", "must be >= 3");
    Require(kernel_scale > 0.0, "mapper.kernel_scale", "must be > 0");
    Require(point_sigma_m > 0.0, "mapper.point_sigma_m", "must be > 0");
    Require(plane_flatness > 0.0 && plane_flatness <= 1.0, "mapper.plane_flatness",
            "must be in (0, 1]");
    Require(doppler_sigma_mps > 0.0, "mapper.doppler_sigma_mps", "must be > 0");
    Require(max_registration_residuals >= 1, "mapper.max_registration_residuals", "must be >= 1");
    Require(max_doppler_residuals >= 0, "mapper.max_doppler_residuals", "must be >= 0");
    Require(refine_max_iterations >= 1, "mapper.refine_max_iterations", "must be >= 1");
    Require(registration_floor_sigma_translation_m >= 0.0,
            "mapper.registration_floor_sigma_translation_m", "must be >= 0");
    Require(registration_floor_sigma_rotation_rad >= 0.0,
            "mapper.registration_floor_sigma_rotation_rad", "must be >= 0");
    Require(registration_weak_ratio >= 0.0 && registration_weak_ratio < 1.0,
            "mapper.registration_weak_ratio", "must be in [0, 1)");
    Require(registration_cluster_m > 0.0 && std::isfinite(registration_cluster_m),
            "mapper.registration_cluster_m", "must be > 0");
    Require(min_correspondences >= 6, "mapper.min_correspondences", "must be >= 6");
    Require(max_rms_m > 0.0, "mapper.max_rms_m", "must be > 0");
    Require(min_observability >= 0.0 && min_observability < 1.0, "mapper.min_observability",
            "must be in [0, 1)");
}

const char *ToString(RegistrationMethod method) {
    switch (method) {
        case RegistrationMethod::kPointToPoint:
            return "point_to_point";
        case RegistrationMethod::kPointToPlane:
            return "point_to_plane";
        case RegistrationMethod::kGicp:
            return "gicp";
    }
    return "?";
}

const char *ToString(RobustKernel kernel) {
    switch (kernel) {
        case RobustKernel::kNone:
            return "none";
        case RobustKernel::kHuber:
            return "huber";
        case RobustKernel::kCauchy:
            return "cauchy";
        case RobustKernel::kTukey:
            return "tukey";
    }
    return "?";
}

RegistrationMethod ParseRegistrationMethod(const std::string &name) {
    return ParseChoice(RegistrationMethodChoices(), name, "registration method");
}

RobustKernel ParseRobustKernel(const std::string &name) {
    return ParseChoice(RobustKernelChoices(), name, "robust kernel");
}

const char *ToString(RegistrationCovarianceModel model) {
    switch (model) {
        case RegistrationCovarianceModel::kIndependent:
            return "independent";
        case RegistrationCovarianceModel::kResidualScale:
            return "residual_scale";
        case RegistrationCovarianceModel::kClustered:
            return "clustered";
    }
    return "?";
}

RegistrationCovarianceModel ParseRegistrationCovarianceModel(const std::string &name) {
    return ParseChoice(RegistrationCovarianceChoices(), name, "registration covariance");
}

}  // namespace dorado::mapping
