#include "dorado/sim/sequence_config.hpp"

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include "dorado/io/field_yaml.hpp"
#include "dorado/sim/sequence_fields.hpp"

namespace dorado::sim {

namespace fs = std::filesystem;

namespace {

/// Collects the first violated range check as an error naming the key.
class Checker {
  public:
    explicit Checker(std::string file) : file_(std::move(file)) {}
    void Require(bool ok, const std::string &key, const std::string &what) const {
        if (!ok) throw SequenceConfigError(file_ + ": key '" + key + "': " + what);
    }
    void Positive(double v, const std::string &key) const {
        Require(std::isfinite(v) && v > 0.0, key, "must be a positive number, got " + Str(v));
    }
    void NonNegative(double v, const std::string &key) const {
        Require(std::isfinite(v) && v >= 0.0, key, "must be >= 0, got " + Str(v));
    }
    void Probability(double v, const std::string &key) const {
        Require(std::isfinite(v) && v >= 0.0 && v <= 1.0, key, "must be in [0, 1], got " + Str(v));
    }
    void Finite(const Eigen::Vector3d &v, const std::string &key) const {
        Require(v.allFinite(), key, "must be finite");
    }

  private:
    static std::string Str(double v) { return std::to_string(v); }
    std::string file_;
};

}  // namespace

Eigen::Isometry3d MountConfig::Transform() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = RotationFromRollPitchYaw(DegToRad(rotation_rpy_deg));
    T.translation() = translation_m;
    return T;
}

void SequenceConfig::Validate() const {
    const Checker c(source_path.empty() ? "sequence '" + name + "'" : source_path);
    c.Positive(duration_s, "duration_s");
    c.Require(duration_s <= 3600.0, "duration_s", "must be at most 3600 s");
    c.Positive(start_time_s, "start_time_s");
    c.Require(start_time_s < 4.0e9, "start_time_s", "must fit a ROS time (< 4e9 s)");
    c.Positive(vehicle.half_wheelbase_m, "vehicle.half_wheelbase_m");
    c.Positive(vehicle.track_width_m, "vehicle.track_width_m");
    c.NonNegative(vehicle.wheel_radius_m, "vehicle.wheel_radius_m");
    c.Require(std::isfinite(vehicle.icr_offset_m), "vehicle.icr_offset_m", "must be finite");
    c.NonNegative(vehicle.icr_offset_sigma_m, "vehicle.icr_offset_sigma_m");
    c.NonNegative(vehicle.side_slip_gain_s, "vehicle.side_slip_gain_s");
    c.NonNegative(motion.speed_mps, "motion.speed_mps");
    c.NonNegative(motion.speed_sigma_mps, "motion.speed_sigma_mps");
    c.Positive(motion.max_speed_mps, "motion.max_speed_mps");
    c.NonNegative(motion.yaw_rate_sigma_radps, "motion.yaw_rate_sigma_radps");
    c.Positive(motion.max_yaw_rate_radps, "motion.max_yaw_rate_radps");
    c.Positive(motion.max_lateral_accel_mps2, "motion.max_lateral_accel_mps2");
    c.Positive(motion.segment_min_s, "motion.segment_min_s");
    c.Require(motion.segment_max_s >= motion.segment_min_s, "motion.segment_max_s",
              "must be >= motion.segment_min_s");
    c.Positive(motion.response_time_s, "motion.response_time_s");
    c.Probability(motion.stop_probability, "motion.stop_probability");
    c.Probability(motion.reverse_probability, "motion.reverse_probability");
    c.NonNegative(motion.max_distance_from_start_m, "motion.max_distance_from_start_m");
    c.NonNegative(terrain.hill_height_m, "terrain.hill_height_m");
    c.Positive(terrain.hill_wavelength_m, "terrain.hill_wavelength_m");
    c.NonNegative(terrain.side_slope_height_m, "terrain.side_slope_height_m");
    c.NonNegative(terrain.roughness_m, "terrain.roughness_m");
    c.Positive(terrain.roughness_wavelength_m, "terrain.roughness_wavelength_m");
    for (const auto &[v, key] : {std::pair{world.trees_per_1000m2, "world.trees_per_1000m2"},
                                 {world.poles_per_1000m2, "world.poles_per_1000m2"},
                                 {world.rocks_per_1000m2, "world.rocks_per_1000m2"},
                                 {world.bushes_per_1000m2, "world.bushes_per_1000m2"},
                                 {world.buildings_per_1000m2, "world.buildings_per_1000m2"},
                                 {world.walls_per_1000m2, "world.walls_per_1000m2"},
                                 {world.parked_cars_per_1000m2, "world.parked_cars_per_1000m2"},
                                 {world.vegetation_per_m2, "world.vegetation_per_m2"},
                                 {world.clearance_m, "world.clearance_m"}}) {
        c.NonNegative(v, key);
    }
    c.Positive(world.corridor_half_width_m, "world.corridor_half_width_m");
    for (const auto &[v, key] : {std::pair{dynamic.people, "dynamic.people"},
                                 {dynamic.cyclists, "dynamic.cyclists"},
                                 {dynamic.cars, "dynamic.cars"},
                                 {dynamic.crowds, "dynamic.crowds"},
                                 {dynamic.large_vehicles, "dynamic.large_vehicles"}}) {
        c.Require(v >= 0 && v <= 10000, key, "must be in [0, 10000]");
    }
    c.Positive(dynamic.spawn_distance_min_m, "dynamic.spawn_distance_min_m");
    c.Require(dynamic.spawn_distance_max_m >= dynamic.spawn_distance_min_m,
              "dynamic.spawn_distance_max_m", "must be >= dynamic.spawn_distance_min_m");
    c.Finite(radar.mount.translation_m, "radar.mount.translation_m");
    c.Finite(radar.mount.rotation_rpy_deg, "radar.mount.rotation_rpy_deg");
    c.Positive(radar.rate_hz, "radar.rate_hz");
    c.Require(radar.rate_hz <= 100.0, "radar.rate_hz", "must be at most 100 Hz");
    c.Require(radar.azimuth_fov_deg > 0.0 && radar.azimuth_fov_deg <= 360.0,
              "radar.azimuth_fov_deg", "must be in (0, 360]");
    c.Require(radar.elevation_fov_deg > 0.0 && radar.elevation_fov_deg < 180.0,
              "radar.elevation_fov_deg", "must be in (0, 180)");
    c.Positive(radar.min_range_m, "radar.min_range_m");
    c.Require(radar.max_range_m > radar.min_range_m, "radar.max_range_m",
              "must be greater than radar.min_range_m");
    c.NonNegative(radar.range_sigma_m, "radar.range_sigma_m");
    c.NonNegative(radar.azimuth_sigma_deg, "radar.azimuth_sigma_deg");
    c.NonNegative(radar.elevation_sigma_deg, "radar.elevation_sigma_deg");
    c.NonNegative(radar.doppler_sigma_mps, "radar.doppler_sigma_mps");
    c.Require(std::isfinite(radar.doppler_snr_ref_db), "radar.doppler_snr_ref_db",
              "must be finite");
    c.Require(std::isfinite(radar.detection_threshold_db), "radar.detection_threshold_db",
              "must be finite");
    c.Require(std::isfinite(radar.snr_at_1m_0dbsm_db), "radar.snr_at_1m_0dbsm_db",
              "must be finite");
    c.Require(std::isfinite(radar.noise_floor_db), "radar.noise_floor_db", "must be finite");
    c.NonNegative(radar.ground_returns_per_scan, "radar.ground_returns_per_scan");
    c.Require(radar.ground_returns_per_scan <= 1e6, "radar.ground_returns_per_scan", "at most 1e6");
    c.Positive(radar.ground_max_range_m, "radar.ground_max_range_m");
    c.Require(std::isfinite(radar.ground_sigma0_db), "radar.ground_sigma0_db", "must be finite");
    c.NonNegative(radar.clutter_per_scan, "radar.clutter_per_scan");
    c.Require(radar.clutter_per_scan <= 1e5, "radar.clutter_per_scan", "at most 1e5");
    c.Probability(radar.ghost_probability, "radar.ghost_probability");
    c.Probability(radar.double_bounce_probability, "radar.double_bounce_probability");
    c.Probability(radar.ground_multipath_probability, "radar.ground_multipath_probability");
    c.NonNegative(radar.doppler_unambiguous_mps, "radar.doppler_unambiguous_mps");
    c.Probability(radar.occlusion_leak, "radar.occlusion_leak");
    c.Require(radar.max_points > 0 && radar.max_points <= 1000000, "radar.max_points",
              "must be in [1, 1e6]");
    c.Finite(imu.mount.translation_m, "imu.mount.translation_m");
    c.Finite(imu.mount.rotation_rpy_deg, "imu.mount.rotation_rpy_deg");
    c.Positive(imu.rate_hz, "imu.rate_hz");
    c.Require(imu.rate_hz <= 2000.0, "imu.rate_hz", "must be at most 2000 Hz");
    c.NonNegative(imu.gyro_noise_density, "imu.gyro_noise_density");
    c.NonNegative(imu.gyro_bias_sigma_radps, "imu.gyro_bias_sigma_radps");
    c.NonNegative(imu.gyro_bias_walk, "imu.gyro_bias_walk");
    c.NonNegative(imu.accel_noise_density, "imu.accel_noise_density");
    c.NonNegative(imu.accel_bias_sigma_mps2, "imu.accel_bias_sigma_mps2");
    c.NonNegative(imu.accel_bias_walk, "imu.accel_bias_walk");
    c.Positive(ground_truth.rate_hz, "ground_truth.rate_hz");
    c.Require(ground_truth.rate_hz <= 1000.0, "ground_truth.rate_hz", "must be at most 1000 Hz");
    c.NonNegative(ground_truth.position_sigma_m, "ground_truth.position_sigma_m");
    c.NonNegative(ground_truth.rotation_sigma_deg, "ground_truth.rotation_sigma_deg");
    c.Positive(ground_truth.correlation_time_s, "ground_truth.correlation_time_s");
}

SequenceConfig LoadSequenceConfig(const std::string &yaml_path) {
    SequenceConfig config;
    config.source_path = yaml_path;
    config.name = fs::path(yaml_path).stem().string();
    try {
        io::FieldReader reader(io::YamlSection(io::LoadYamlFile(yaml_path), yaml_path));
        VisitFields(config, reader);
        reader.RejectUnknownKeys();
    } catch (const io::ConfigError &e) {
        throw SequenceConfigError(e.what());  // dorado_sim's own error type, same message
    }
    config.Validate();
    return config;
}

std::string SequenceConfigYaml(const SequenceConfig &config) {
    SequenceConfig copy = config;
    io::FieldWriter writer;
    VisitFields(copy, writer);
    return writer.text();
}

std::vector<io::FieldRow> SequenceConfigFields() {
    return io::ListFields(SequenceConfig{});
}

std::string FindSequenceFile(const std::string &name_or_path) {
    if (fs::is_regular_file(name_or_path)) return name_or_path;
    const bool looks_like_path = name_or_path.find('/') != std::string::npos ||
                                 fs::path(name_or_path).extension() == ".yaml";
    if (!looks_like_path) {
        const std::string file = name_or_path + ".yaml";
        for (const fs::path &dir :
             {fs::path("configs/sequences"), fs::path(DORADO_SEQUENCES_DIR)}) {
            if (fs::is_regular_file(dir / file)) return (dir / file).string();
        }
    }
    std::string known;
    for (const std::string &name : BuiltInSequences()) known += (known.empty() ? "" : ", ") + name;
    throw SequenceConfigError("--sequence '" + name_or_path +
                              "': no such file or built-in sequence (built-in: " + known + ")");
}

std::vector<std::string> BuiltInSequences() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto &entry : fs::directory_iterator(DORADO_SEQUENCES_DIR, ec))
        if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace dorado::sim
