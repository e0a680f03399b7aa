#include "dorado/config/map_config.hpp"

#include <stdexcept>

#include "dorado/io/yaml_section.hpp"

namespace dorado::config {
namespace {

using io::YamlSection;

void ReadMapper(YamlSection s, mapping::MapperConfig &c) {
    s.Read("min_range_m", c.min_range_m);
    s.Read("max_range_m", c.max_range_m);
    s.Read("scan_voxel_m", c.scan_voxel_m);
    s.Read("max_source_points", c.max_source_points);
    YamlSection map = s.Child("map");
    map.Read("voxel_size_m", c.map.voxel_size_m);
    map.Read("max_points_per_voxel", c.map.max_points_per_voxel);
    map.Read("max_distance_m", c.map.max_distance_m);
    map.RejectUnknownKeys();
    s.Read("keyframe_distance_m", c.keyframe_distance_m);
    s.Read("keyframe_angle_deg", c.keyframe_angle_deg);
    s.Read("update_map_on_fallback", c.update_map_on_fallback);
    s.ReadParsed("method", c.method, mapping::ParseRegistrationMethod);
    s.Read("max_iterations", c.max_iterations);
    s.Read("initial_threshold_m", c.initial_threshold_m);
    s.Read("min_threshold_m", c.min_threshold_m);
    s.Read("min_motion_m", c.min_motion_m);
    s.Read("covariance_neighbours", c.covariance_neighbours);
    s.ReadParsed("refinement", c.refinement, mapping::ParseRefinement);
    s.ReadParsed("kernel", c.kernel, mapping::ParseRobustKernel);
    s.Read("kernel_scale", c.kernel_scale);
    s.Read("point_sigma_m", c.point_sigma_m);
    s.Read("plane_flatness", c.plane_flatness);
    s.Read("doppler_sigma_mps", c.doppler_sigma_mps);
    s.Read("use_doppler", c.use_doppler);
    s.Read("max_registration_residuals", c.max_registration_residuals);
    s.Read("max_doppler_residuals", c.max_doppler_residuals);
    s.Read("refine_max_iterations", c.refine_max_iterations);
    s.Read("refine_outer_iterations", c.refine_outer_iterations);
    s.ReadParsed("registration_covariance", c.registration_covariance,
                 mapping::ParseRegistrationCovarianceModel);
    s.Read("registration_cluster_m", c.registration_cluster_m);
    YamlSection window = s.Child("window");
    window.Read("size", c.window.size);
    window.ReadVector3("qc_linear", c.window.qc_linear);
    window.ReadVector3("qc_angular", c.window.qc_angular);
    window.Read("use_kinematic_model", c.window.use_kinematic_model);
    window.Read("gyro_sigma_radps", c.window.gyro_sigma_radps);
    window.Read("gyro_bias_sigma_radps", c.window.gyro_bias_sigma_radps);
    window.Read("max_iterations", c.window.max_iterations);
    window.RejectUnknownKeys();
    s.Read("min_correspondences", c.min_correspondences);
    s.Read("max_rms_m", c.max_rms_m);
    s.Read("min_observability", c.min_observability);
    s.Read("max_prior_mahalanobis_squared", c.max_prior_mahalanobis_squared);
    s.Read("registration_sigma_translation_m", c.registration_sigma_translation_m);
    s.Read("registration_sigma_rotation_rad", c.registration_sigma_rotation_rad);
    s.Read("registration_floor_sigma_translation_m", c.registration_floor_sigma_translation_m);
    s.Read("registration_floor_sigma_rotation_rad", c.registration_floor_sigma_rotation_rad);
    s.Read("registration_weak_ratio", c.registration_weak_ratio);
    s.Read("doppler_in_registration", c.doppler_in_registration);
    s.Read("jump_gate_innovation", c.jump_gate_innovation);
    s.RejectUnknownKeys();
}

void ReadPrior(YamlSection s, mapping::PriorNoiseConfig &c) {
    s.Read("none_sigma_translation_m", c.none_sigma_translation_m);
    s.Read("none_sigma_rotation_rad", c.none_sigma_rotation_rad);
    s.Read("constvel_sigma_accel_mps2", c.constvel_sigma_accel_mps2);
    s.Read("constvel_sigma_angular_accel_radps2", c.constvel_sigma_angular_accel_radps2);
    s.Read("imu_gyro_sigma_radps", c.imu_gyro_sigma_radps);
    s.Read("imu_accel_sigma_mps2", c.imu_accel_sigma_mps2);
    s.Read("imu_velocity_sigma_mps", c.imu_velocity_sigma_mps);
    s.ReadVector3("gravity_world_mps2", c.gravity_world_mps2);
    s.Read("doppler_min_sigma_v_mps", c.doppler_min_sigma_v_mps);
    s.ReadVector3("doppler_min_sigma_omega_radps", c.doppler_min_sigma_omega_radps);
    s.RejectUnknownKeys();
}

}  // namespace

mapping::PriorKind ParsePriorKindKey(const std::string &text, const std::string &what) {
    try {
        return mapping::ParsePriorKind(text);
    } catch (const std::invalid_argument &e) {
        throw io::ConfigError(what + ": " + e.what());
    }
}

mapping::Refinement ParseRefinementKey(const std::string &text, const std::string &what) {
    try {
        return mapping::ParseRefinement(text);
    } catch (const std::invalid_argument &e) {
        throw io::ConfigError(what + ": " + e.what());
    }
}

MapCommandConfig LoadMapConfig(const std::string &yaml_path) {
    MapCommandConfig config;
    YamlSection top(io::LoadYamlFile(yaml_path), yaml_path);
    ReadMapper(top.Child("mapper"), config.mapper);
    ReadPrior(top.Child("prior"), config.prior);
    YamlSection output = top.Child("output");
    output.Read("map_voxel_m", config.output_voxel_m);
    output.RejectUnknownKeys();
    top.RejectUnknownKeys();
    try {
        config.mapper.Validate();
        config.prior.Validate();
    } catch (const std::invalid_argument &e) {
        throw io::ConfigError(yaml_path + ": " + e.what());
    }
    if (!(config.output_voxel_m > 0.0)) top.Fail("output.map_voxel_m", "must be > 0");
    return config;
}

}  // namespace dorado::config
