#pragma once
/// @file sequence_config.hpp
/// Everything that describes one simulated sequence: duration, seed, vehicle, motion profile,
/// terrain, world, moving objects, radar, IMU and ground truth. Plain structs with defaults (a
/// Husky-like robot on a grassy hillside, like the paper's dataset); a sequence YAML under
/// configs/sequences/ overrides any of them (every key: sequence_fields.hpp, docs/config_keys.md).

#include <Eigen/Geometry>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace dorado::io {
struct FieldRow;  // io/field_yaml.hpp
}  // namespace dorado::io

namespace dorado::sim {

/// A bad sequence description: the message names the file and the key.
class SequenceConfigError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// A sensor mount on the vehicle's base frame (origin at the centre of the rear axle).
struct MountConfig {
    Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
    Eigen::Vector3d rotation_rpy_deg = Eigen::Vector3d::Zero();  ///< R = Rz(yaw) Ry(pitch) Rx(roll)
    [[nodiscard]] Eigen::Isometry3d Transform() const;
};

enum class VehicleType { kSkidSteer, kAckermann };

struct VehicleConfig {
    VehicleType type = VehicleType::kSkidSteer;
    double half_wheelbase_m = 0.256;  ///< the paper's m (Clearpath Husky: wheelbase 0.512 m)
    double track_width_m = 0.555;     ///< distance between the left and right wheels
    double wheel_radius_m = 0.165;    ///< the base origin sits this high above the ground
    /// Mean position of the true Z-ICR ahead of the rear axle [m]. 0 = the paper's model holds
    /// exactly; a skid-steer vehicle skids, so its Z-ICR wanders ahead of the rear axle.
    double icr_offset_m = 0.0;
    double icr_offset_sigma_m = 0.0;  ///< slow random wander of that position [m]
    /// Lateral slip down side slopes: v_y = -gain * g * sin(roll) * speed-dependent factor [s].
    double side_slip_gain_s = 0.0;
};

/// Speed and yaw-rate profile: piecewise-constant targets of random length, smoothed by the
/// vehicle's response time; optional stops.
struct MotionConfig {
    double speed_mps = 1.0;             ///< mean forward speed
    double speed_sigma_mps = 0.3;       ///< spread of the segment speeds
    double max_speed_mps = 2.0;         ///< speeds are clipped to [0, max]
    double yaw_rate_sigma_radps = 0.3;  ///< spread of the segment yaw rates
    double max_yaw_rate_radps = 0.8;
    double max_lateral_accel_mps2 = 3.0;  ///< limits yaw rate at speed (|v * omega| <= this)
    double segment_min_s = 3.0;
    double segment_max_s = 8.0;
    double response_time_s = 0.6;   ///< first-order lag of speed and yaw rate towards the targets
    double stop_probability = 0.0;  ///< chance that a segment is a stop (speed 0)
    double reverse_probability = 0.0;  ///< chance that a segment drives backwards
    /// Stay within this distance of the start by steering back towards it [m] (0 = free).
    double max_distance_from_start_m = 0.0;
};

/// A smooth height field with hills, plus small-scale roughness that the wheels feel.
struct TerrainConfig {
    double hill_height_m = 1.0;        ///< amplitude of the large hills
    double hill_wavelength_m = 40.0;   ///< their typical wavelength
    double side_slope_height_m = 0.0;  ///< extra ridges across the path (make roll)
    double roughness_m = 0.01;         ///< amplitude of the bumps under the wheels
    double roughness_wavelength_m = 1.2;
};

/// Densities of static structure per 1000 m^2 of ground near the route.
struct WorldConfig {
    double trees_per_1000m2 = 3.0;
    double poles_per_1000m2 = 0.3;
    double rocks_per_1000m2 = 2.0;
    double bushes_per_1000m2 = 4.0;
    double buildings_per_1000m2 = 0.05;
    double walls_per_1000m2 = 0.1;
    double parked_cars_per_1000m2 = 0.0;
    /// Grass tufts, shrubs and debris: weak reflectors scattered everywhere [per m^2].
    double vegetation_per_m2 = 1.0;
    double corridor_half_width_m = 70.0;  ///< structure is placed this far from the route
    double clearance_m = 2.0;             ///< nothing static within this distance of the route
};

/// Moving objects: counts over the whole sequence, spawned near the vehicle's route.
struct DynamicConfig {
    int people = 6;
    int cyclists = 0;
    int cars = 1;
    int crowds = 0;          ///< groups of 10-25 people walking together
    int large_vehicles = 0;  ///< buses/trucks passing close by (a quarter of the scan or more)
    double spawn_distance_min_m = 4.0;
    double spawn_distance_max_m = 30.0;
};

struct RadarConfig {
    MountConfig mount;
    double rate_hz = 15.0;
    double azimuth_fov_deg = 100.0;  ///< full field of view, centred on the radar's X axis
    double elevation_fov_deg = 30.0;
    double min_range_m = 0.5;
    double max_range_m = 100.0;
    double range_sigma_m = 0.08;
    double azimuth_sigma_deg = 0.5;
    double elevation_sigma_deg = 1.0;
    double doppler_sigma_mps =
        0.04;  ///< at high SNR; weak returns get more (see doppler_snr_ref_db)
    /// Doppler noise grows as sigma * sqrt(1 + 10^((ref - snr)/10)): at snr = ref it is x1.4.
    double doppler_snr_ref_db = 15.0;
    double detection_threshold_db = 12.0;  ///< SNR needed for a detection (after Swerling fading)
    double snr_at_1m_0dbsm_db = 95.0;      ///< radar constant: SNR of a 0 dBsm target at 1 m
    double noise_floor_db = 25.0;          ///< power = SNR + noise floor (the power field's offset)
    double ground_returns_per_scan = 1500.0;  ///< ground patches tried per scan (near range)
    double ground_max_range_m = 30.0;
    double ground_sigma0_db = -18.0;          ///< ground backscatter per m^2 at normal incidence
    double clutter_per_scan = 60.0;           ///< random false detections with random Doppler
    double ghost_probability = 0.03;          ///< angular-ambiguity ghost per strong detection
    double double_bounce_probability = 0.02;  ///< range x2 / Doppler x2 ghost per strong detection
    double ground_multipath_probability = 0.03;  ///< mirror image below the ground
    double doppler_unambiguous_mps = 0.0;        ///< > 0: Doppler wraps into [-v, v) (aliasing)
    double occlusion_leak = 0.08;  ///< chance a point behind an opaque object still shows
    int max_points = 20000;        ///< the sensor's detection list limit
    std::string frame_id = "hugin_raf_1";
};

struct ImuConfig {
    MountConfig mount;
    double rate_hz = 200.0;
    double gyro_noise_density = 1.7e-4;   ///< [rad/s/sqrt(Hz)] (Xsens MTi-30: 0.01 deg/s/sqrt(Hz))
    double gyro_bias_sigma_radps = 2e-3;  ///< initial bias spread
    double gyro_bias_walk = 2e-5;         ///< bias random walk [rad/s^2/sqrt(Hz)]
    double accel_noise_density = 6e-4;    ///< [m/s^2/sqrt(Hz)]
    double accel_bias_sigma_mps2 = 0.02;
    double accel_bias_walk = 4e-4;  ///< [m/s^3/sqrt(Hz)]
    std::string frame_id = "imu_link";
};

/// The reference trajectory, like a lidar mapper's: at the lidar's rate, with a small slowly
/// varying error (Gauss-Markov) in position and orientation.
struct GroundTruthConfig {
    double rate_hz = 10.0;
    double position_sigma_m = 0.02;
    double rotation_sigma_deg = 0.2;
    double correlation_time_s = 3.0;
};

struct SequenceConfig {
    std::string name = "custom";
    std::string description;
    std::string source_path;  ///< the YAML it came from (empty when built in code)
    double duration_s = 60.0;
    uint64_t seed = 1;
    double start_time_s = 1694520000.0;  ///< stamp of the first sample (the dataset's epoch)
    VehicleConfig vehicle;
    MotionConfig motion;
    TerrainConfig terrain;
    WorldConfig world;
    DynamicConfig dynamic;
    RadarConfig radar;
    ImuConfig imu;
    GroundTruthConfig ground_truth;

    /// Throws SequenceConfigError naming the first nonsense value.
    void Validate() const;
};

/// Reads a sequence YAML through its field list (sequence_fields.hpp); every key is optional,
/// unknown keys and wrong types are errors.
[[nodiscard]] SequenceConfig LoadSequenceConfig(const std::string &yaml_path);

/// @p config as a sequence YAML (what LoadSequenceConfig reads back), each key with its doc.
[[nodiscard]] std::string SequenceConfigYaml(const SequenceConfig &config);

/// Every key of a sequence file with its built-in default and doc.
[[nodiscard]] std::vector<io::FieldRow> SequenceConfigFields();

/// The YAML file a `--sequence` argument names: an existing file, or NAME looked up as
/// configs/sequences/NAME.yaml in the working directory and in the source tree.
[[nodiscard]] std::string FindSequenceFile(const std::string &name_or_path);

/// The built-in sequences' names (configs/sequences/*.yaml in the source tree), sorted: what
/// `dorado simulate --help` lists and FindSequenceFile's error names.
[[nodiscard]] std::vector<std::string> BuiltInSequences();

}  // namespace dorado::sim
