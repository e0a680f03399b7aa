#include "dorado/sim/sequence_config.hpp"

#include "dorado/core/lie.hpp"

#include <cmath>
#include <filesystem>
#include <vector>

#include "dorado/io/yaml_section.hpp"

namespace dorado::sim {

namespace fs = std::filesystem;

namespace {

using io::YamlSection;

void ReadMount(YamlSection s, MountConfig &mount) {
    s.ReadVector3("translation_m", mount.translation_m);
    s.ReadVector3("rotation_rpy_deg", mount.rotation_rpy_deg);
    s.RejectUnknownKeys();
}

void ReadVehicle(YamlSection s, VehicleConfig &v) {
    s.ReadEnum("type", v.type,
               {{"skid_steer", VehicleType::kSkidSteer}, {"ackermann", VehicleType::kAckermann}});
    s.Read("half_wheelbase_m", v.half_wheelbase_m);
    s.Read("track_width_m", v.track_width_m);
    s.Read("wheel_radius_m", v.wheel_radius_m);
    s.Read("icr_offset_m", v.icr_offset_m);
    s.Read("icr_offset_sigma_m", v.icr_offset_sigma_m);
    s.Read("side_slip_gain_s", v.side_slip_gain_s);
    s.RejectUnknownKeys();
}

void ReadMotion(YamlSection s, MotionConfig &m) {
    s.Read("speed_mps", m.speed_mps);
    s.Read("speed_sigma_mps", m.speed_sigma_mps);
    s.Read("max_speed_mps", m.max_speed_mps);
    s.Read("yaw_rate_sigma_radps", m.yaw_rate_sigma_radps);
    s.Read("max_yaw_rate_radps", m.max_yaw_rate_radps);
    s.Read("max_lateral_accel_mps2", m.max_lateral_accel_mps2);
    s.Read("segment_min_s", m.segment_min_s);
    s.Read("segment_max_s", m.segment_max_s);
    s.Read("response_time_s", m.response_time_s);
    s.Read("stop_probability", m.stop_probability);
    s.Read("reverse_probability", m.reverse_probability);
    s.Read("max_distance_from_start_m", m.max_distance_from_start_m);
    s.RejectUnknownKeys();
}

void ReadTerrain(YamlSection s, TerrainConfig &t) {
    s.Read("hill_height_m", t.hill_height_m);
    s.Read("hill_wavelength_m", t.hill_wavelength_m);
    s.Read("side_slope_height_m", t.side_slope_height_m);
    s.Read("roughness_m", t.roughness_m);
    s.Read("roughness_wavelength_m", t.roughness_wavelength_m);
    s.RejectUnknownKeys();
}

void ReadWorld(YamlSection s, WorldConfig &w) {
    s.Read("trees_per_1000m2", w.trees_per_1000m2);
    s.Read("poles_per_1000m2", w.poles_per_1000m2);
    s.Read("rocks_per_1000m2", w.rocks_per_1000m2);
    s.Read("bushes_per_1000m2", w.bushes_per_1000m2);
    s.Read("buildings_per_1000m2", w.buildings_per_1000m2);
    s.Read("walls_per_1000m2", w.walls_per_1000m2);
    s.Read("parked_cars_per_1000m2", w.parked_cars_per_1000m2);
    s.Read("vegetation_per_m2", w.vegetation_per_m2);
    s.Read("corridor_half_width_m", w.corridor_half_width_m);
    s.Read("clearance_m", w.clearance_m);
    s.RejectUnknownKeys();
}

void ReadDynamic(YamlSection s, DynamicConfig &d) {
    s.Read("people", d.people);
    s.Read("cyclists", d.cyclists);
    s.Read("cars", d.cars);
    s.Read("crowds", d.crowds);
    s.Read("large_vehicles", d.large_vehicles);
    s.Read("spawn_distance_min_m", d.spawn_distance_min_m);
    s.Read("spawn_distance_max_m", d.spawn_distance_max_m);
    s.RejectUnknownKeys();
}

void ReadRadar(YamlSection s, RadarConfig &r) {
    ReadMount(s.Child("mount"), r.mount);
    s.Read("rate_hz", r.rate_hz);
    s.Read("azimuth_fov_deg", r.azimuth_fov_deg);
    s.Read("elevation_fov_deg", r.elevation_fov_deg);
    s.Read("min_range_m", r.min_range_m);
    s.Read("max_range_m", r.max_range_m);
    s.Read("range_sigma_m", r.range_sigma_m);
    s.Read("azimuth_sigma_deg", r.azimuth_sigma_deg);
    s.Read("elevation_sigma_deg", r.elevation_sigma_deg);
    s.Read("doppler_sigma_mps", r.doppler_sigma_mps);
    s.Read("doppler_snr_ref_db", r.doppler_snr_ref_db);
    s.Read("detection_threshold_db", r.detection_threshold_db);
    s.Read("snr_at_1m_0dbsm_db", r.snr_at_1m_0dbsm_db);
    s.Read("noise_floor_db", r.noise_floor_db);
    s.Read("ground_returns_per_scan", r.ground_returns_per_scan);
    s.Read("ground_max_range_m", r.ground_max_range_m);
    s.Read("ground_sigma0_db", r.ground_sigma0_db);
    s.Read("clutter_per_scan", r.clutter_per_scan);
    s.Read("ghost_probability", r.ghost_probability);
    s.Read("double_bounce_probability", r.double_bounce_probability);
    s.Read("ground_multipath_probability", r.ground_multipath_probability);
    s.Read("doppler_unambiguous_mps", r.doppler_unambiguous_mps);
    s.Read("occlusion_leak", r.occlusion_leak);
    s.Read("max_points", r.max_points);
    s.Read("frame_id", r.frame_id);
    s.RejectUnknownKeys();
}

void ReadImu(YamlSection s, ImuConfig &i) {
    ReadMount(s.Child("mount"), i.mount);
    s.Read("rate_hz", i.rate_hz);
    s.Read("gyro_noise_density", i.gyro_noise_density);
    s.Read("gyro_bias_sigma_radps", i.gyro_bias_sigma_radps);
    s.Read("gyro_bias_walk", i.gyro_bias_walk);
    s.Read("accel_noise_density", i.accel_noise_density);
    s.Read("accel_bias_sigma_mps2", i.accel_bias_sigma_mps2);
    s.Read("accel_bias_walk", i.accel_bias_walk);
    s.Read("frame_id", i.frame_id);
    s.RejectUnknownKeys();
}

void ReadGroundTruth(YamlSection s, GroundTruthConfig &g) {
    s.Read("rate_hz", g.rate_hz);
    s.Read("position_sigma_m", g.position_sigma_m);
    s.Read("rotation_sigma_deg", g.rotation_sigma_deg);
    s.Read("correlation_time_s", g.correlation_time_s);
    s.RejectUnknownKeys();
}

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
    T.linear() = RotationFromRollPitchYaw(rotation_rpy_deg * M_PI / 180.0);
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
        YamlSection top(io::LoadYamlFile(yaml_path), yaml_path);
        top.Read("name", config.name);
        top.Read("description", config.description);
        top.Read("duration_s", config.duration_s);
        top.Read("seed", config.seed);
        top.Read("start_time_s", config.start_time_s);
        ReadVehicle(top.Child("vehicle"), config.vehicle);
        ReadMotion(top.Child("motion"), config.motion);
        ReadTerrain(top.Child("terrain"), config.terrain);
        ReadWorld(top.Child("world"), config.world);
        ReadDynamic(top.Child("dynamic"), config.dynamic);
        ReadRadar(top.Child("radar"), config.radar);
        ReadImu(top.Child("imu"), config.imu);
        ReadGroundTruth(top.Child("ground_truth"), config.ground_truth);
        top.RejectUnknownKeys();
    } catch (const io::ConfigError &e) {
        throw SequenceConfigError(e.what());  // dorado_sim's own error type, same message
    }
    config.Validate();
    return config;
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
    std::error_code ec;
    for (const auto &entry : fs::directory_iterator(DORADO_SEQUENCES_DIR, ec)) {
        if (entry.path().extension() == ".yaml") {
            known += (known.empty() ? "" : ", ") + entry.path().stem().string();
        }
    }
    throw SequenceConfigError("--sequence '" + name_or_path +
                              "': no such file or built-in sequence (built-in: " + known + ")");
}

}  // namespace dorado::sim
