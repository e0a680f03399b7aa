#include "map_config.hpp"

#include <yaml-cpp/yaml.h>

#include <set>
#include <stdexcept>

#include "dorado/io/dataset_config.hpp"

namespace dorado::apps {
namespace {

// One YAML mapping: typed reads that name the key on error, and a check for unknown keys.
class Section {
  public:
    Section(const YAML::Node &node, std::string file, std::string prefix)
        : node_(node), file_(std::move(file)), prefix_(std::move(prefix)) {
        if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) Fail("", "must be a mapping");
    }
    [[noreturn]] void Fail(const std::string &key, const std::string &what) const {
        throw io::ConfigError(file_ + ": key '" + (key.empty() ? prefix_ : prefix_ + "." + key) +
                              "': " + what);
    }
    template <typename T>
    void Read(const std::string &key, T &value) {
        known_.insert(key);
        if (!node_.IsMap() || !node_[key].IsDefined() || node_[key].IsNull()) return;
        try {
            value = node_[key].as<T>();
        } catch (const YAML::Exception &) {
            Fail(key,
                 "has the wrong type (line " + std::to_string(node_[key].Mark().line + 1) + ")");
        }
    }
    void ReadVector3(const std::string &key, Eigen::Vector3d &value) {
        std::vector<double> v{value.x(), value.y(), value.z()};
        Read(key, v);
        if (v.size() != 3) Fail(key, "must be a list of 3 numbers");
        value = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    template <typename Parse, typename E>
    void ReadEnum(const std::string &key, E &value, Parse parse) {
        std::string text;
        Read(key, text);
        if (text.empty()) return;
        try {
            value = parse(text);
        } catch (const std::invalid_argument &e) {
            Fail(key, e.what());
        }
    }
    Section Child(const std::string &key) {
        known_.insert(key);
        return Section(node_.IsMap() ? node_[key] : YAML::Node(), file_,
                       prefix_.empty() ? key : prefix_ + "." + key);
    }
    void RejectUnknownKeys() const {
        if (!node_.IsMap()) return;
        for (const auto &entry : node_) {
            const auto key = entry.first.as<std::string>();
            if (!known_.count(key)) Fail(key, "unknown key");
        }
    }

  private:
    YAML::Node node_;
    std::string file_, prefix_;
    std::set<std::string> known_;
};

void ReadMapper(Section s, mapping::MapperConfig &c) {
    s.Read("min_range_m", c.min_range_m);
    s.Read("max_range_m", c.max_range_m);
    s.Read("scan_voxel_m", c.scan_voxel_m);
    s.Read("max_source_points", c.max_source_points);
    Section map = s.Child("map");
    map.Read("voxel_size_m", c.map.voxel_size_m);
    map.Read("max_points_per_voxel", c.map.max_points_per_voxel);
    map.Read("max_distance_m", c.map.max_distance_m);
    map.RejectUnknownKeys();
    s.Read("keyframe_distance_m", c.keyframe_distance_m);
    s.Read("keyframe_angle_deg", c.keyframe_angle_deg);
    s.Read("update_map_on_fallback", c.update_map_on_fallback);
    s.ReadEnum("method", c.method, mapping::ParseRegistrationMethod);
    s.Read("max_iterations", c.max_iterations);
    s.Read("initial_threshold_m", c.initial_threshold_m);
    s.Read("min_threshold_m", c.min_threshold_m);
    s.Read("min_motion_m", c.min_motion_m);
    s.Read("covariance_neighbours", c.covariance_neighbours);
    std::string refinement;
    s.Read("refinement", refinement);
    if (refinement == "ceres")
        c.refinement = mapping::Refinement::kCeres;
    else if (refinement == "none")
        c.refinement = mapping::Refinement::kNone;
    else if (!refinement.empty())
        s.Fail("refinement", "'" + refinement + "' is not one of: ceres, none");
    s.ReadEnum("kernel", c.kernel, mapping::ParseRobustKernel);
    s.Read("kernel_scale", c.kernel_scale);
    s.Read("point_sigma_m", c.point_sigma_m);
    s.Read("plane_flatness", c.plane_flatness);
    s.Read("doppler_sigma_mps", c.doppler_sigma_mps);
    s.Read("use_doppler", c.use_doppler);
    s.Read("max_registration_residuals", c.max_registration_residuals);
    s.Read("max_doppler_residuals", c.max_doppler_residuals);
    s.Read("refine_max_iterations", c.refine_max_iterations);
    s.Read("refine_outer_iterations", c.refine_outer_iterations);
    s.Read("min_correspondences", c.min_correspondences);
    s.Read("max_rms_m", c.max_rms_m);
    s.Read("min_observability", c.min_observability);
    s.Read("max_prior_mahalanobis_squared", c.max_prior_mahalanobis_squared);
    s.Read("registration_sigma_translation_m", c.registration_sigma_translation_m);
    s.Read("registration_sigma_rotation_rad", c.registration_sigma_rotation_rad);
    s.RejectUnknownKeys();
}

void ReadPrior(Section s, mapping::PriorNoiseConfig &c) {
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

MapCommandConfig LoadMapConfig(const std::string &yaml_path) {
    YAML::Node root;
    try {
        root = YAML::LoadFile(yaml_path);
    } catch (const YAML::Exception &e) {
        throw io::ConfigError(yaml_path + ": cannot read: " + e.what());
    }
    MapCommandConfig config;
    Section top(root, yaml_path, "");
    ReadMapper(top.Child("mapper"), config.mapper);
    ReadPrior(top.Child("prior"), config.prior);
    Section output = top.Child("output");
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

}  // namespace dorado::apps
