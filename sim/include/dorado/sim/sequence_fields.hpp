#pragma once
/// @file sequence_fields.hpp
/// A sequence YAML's field list (`VisitFields`, core/config_fields.hpp): every key of
/// configs/sequences/*.yaml once, with its doc. LoadSequenceConfig reads it, SequenceConfigYaml
/// writes it and `dorado config keys` lists it (docs/config_keys.md). Ranges: Validate().

#include "dorado/core/config_fields.hpp"
#include "dorado/sim/sequence_config.hpp"

namespace dorado::sim {

inline Choices<VehicleType> VehicleTypeChoices() {
    return {{"skid_steer", VehicleType::kSkidSteer}, {"ackermann", VehicleType::kAckermann}};
}

template <typename Visitor>
void VisitFields(MountConfig &c, Visitor &&v) {
    v("translation_m", c.translation_m, "on the base frame (origin: the rear axle's centre) [m]");
    v("rotation_rpy_deg", c.rotation_rpy_deg, "R = Rz(yaw) Ry(pitch) Rx(roll) [deg]");
}

template <typename Visitor>
void VisitFields(VehicleConfig &c, Visitor &&v) {
    v("type", c.type, VehicleTypeChoices(), "the drive");
    v("half_wheelbase_m", c.half_wheelbase_m, "the paper's m [m]");
    v("track_width_m", c.track_width_m, "between the left and right wheels [m]");
    v("wheel_radius_m", c.wheel_radius_m, "the base origin's height above the ground [m]");
    v("icr_offset_m", c.icr_offset_m, "mean true Z-ICR ahead of the rear axle [m]");
    v("icr_offset_sigma_m", c.icr_offset_sigma_m, "its slow random wander [m]");
    v("side_slip_gain_s", c.side_slip_gain_s, "downhill creep on side slopes [s]");
}

template <typename Visitor>
void VisitFields(MotionConfig &c, Visitor &&v) {
    v("speed_mps", c.speed_mps, "mean forward speed [m/s]");
    v("speed_sigma_mps", c.speed_sigma_mps, "spread of the segment speeds [m/s]");
    v("max_speed_mps", c.max_speed_mps, "speeds are clipped to [0, max] [m/s]");
    v("yaw_rate_sigma_radps", c.yaw_rate_sigma_radps, "spread of the segment yaw rates [rad/s]");
    v("max_yaw_rate_radps", c.max_yaw_rate_radps, "[rad/s]");
    v("max_lateral_accel_mps2", c.max_lateral_accel_mps2, "|v * omega| at most this [m/s^2]");
    v("segment_min_s", c.segment_min_s, "shortest segment [s]");
    v("segment_max_s", c.segment_max_s, "longest segment [s]");
    v("response_time_s", c.response_time_s, "lag of speed and yaw rate to the targets [s]");
    v("stop_probability", c.stop_probability, "chance that a segment is a stop");
    v("reverse_probability", c.reverse_probability, "chance that a segment drives backwards");
    v("max_distance_from_start_m", c.max_distance_from_start_m,
      "steer back towards the start beyond this [m] (0: free)");
}

template <typename Visitor>
void VisitFields(TerrainConfig &c, Visitor &&v) {
    v("hill_height_m", c.hill_height_m, "amplitude of the large hills [m]");
    v("hill_wavelength_m", c.hill_wavelength_m,
      "their wavelength [m] (RMS slope ~ 4.4 x height / wavelength)");
    v("side_slope_height_m", c.side_slope_height_m, "12 m ridges across the path: roll [m]");
    v("roughness_m", c.roughness_m, "bumps under the wheels: vibration [m]");
    v("roughness_wavelength_m", c.roughness_wavelength_m, "[m]");
}

template <typename Visitor>
void VisitFields(WorldConfig &c, Visitor &&v) {
    v("trees_per_1000m2", c.trees_per_1000m2, "near the route [per 1000 m^2]");
    v("poles_per_1000m2", c.poles_per_1000m2, "[per 1000 m^2]");
    v("rocks_per_1000m2", c.rocks_per_1000m2, "[per 1000 m^2]");
    v("bushes_per_1000m2", c.bushes_per_1000m2, "[per 1000 m^2]");
    v("buildings_per_1000m2", c.buildings_per_1000m2, "[per 1000 m^2]");
    v("walls_per_1000m2", c.walls_per_1000m2, "[per 1000 m^2]");
    v("parked_cars_per_1000m2", c.parked_cars_per_1000m2, "[per 1000 m^2]");
    v("vegetation_per_m2", c.vegetation_per_m2, "weak reflectors everywhere [per m^2]");
    v("corridor_half_width_m", c.corridor_half_width_m, "structure this far from the route [m]");
    v("clearance_m", c.clearance_m, "nothing static this close to the route [m]");
}

template <typename Visitor>
void VisitFields(DynamicConfig &c, Visitor &&v) {
    v("people", c.people, "moving objects over the sequence");
    v("cyclists", c.cyclists, "count");
    v("cars", c.cars, "count");
    v("crowds", c.crowds, "groups of 10-25 people walking together");
    v("large_vehicles", c.large_vehicles, "buses and trucks passing close by");
    v("spawn_distance_min_m", c.spawn_distance_min_m, "spawned this far from the vehicle [m]");
    v("spawn_distance_max_m", c.spawn_distance_max_m, "[m]");
}

template <typename Visitor>
void VisitFields(RadarConfig &c, Visitor &&v) {
    VisitFields(c.mount, Prefixed{"mount.", v});
    v("rate_hz", c.rate_hz, "scans per second [Hz]");
    v("azimuth_fov_deg", c.azimuth_fov_deg, "full field of view about the radar's X axis [deg]");
    v("elevation_fov_deg", c.elevation_fov_deg, "[deg]");
    v("min_range_m", c.min_range_m, "[m]");
    v("max_range_m", c.max_range_m, "[m]");
    v("range_sigma_m", c.range_sigma_m, "[m]");
    v("azimuth_sigma_deg", c.azimuth_sigma_deg, "[deg]");
    v("elevation_sigma_deg", c.elevation_sigma_deg, "[deg]");
    v("doppler_sigma_mps", c.doppler_sigma_mps, "Doppler noise at high SNR [m/s]");
    v("doppler_snr_ref_db", c.doppler_snr_ref_db, "the noise is x1.4 at this SNR [dB]");
    v("detection_threshold_db", c.detection_threshold_db, "SNR needed for a detection [dB]");
    v("snr_at_1m_0dbsm_db", c.snr_at_1m_0dbsm_db, "SNR of a 0 dBsm target at 1 m [dB]");
    v("noise_floor_db", c.noise_floor_db, "power = SNR + this [dB]");
    v("ground_returns_per_scan", c.ground_returns_per_scan, "ground patches tried per scan");
    v("ground_max_range_m", c.ground_max_range_m, "[m]");
    v("ground_sigma0_db", c.ground_sigma0_db, "ground backscatter per m^2, normal incidence [dB]");
    v("clutter_per_scan", c.clutter_per_scan, "false detections with random Doppler");
    v("ghost_probability", c.ghost_probability, "angular-ambiguity ghost per strong detection");
    v("double_bounce_probability", c.double_bounce_probability, "range x2 / Doppler x2 ghost");
    v("ground_multipath_probability", c.ground_multipath_probability, "mirror below the ground");
    v("doppler_unambiguous_mps", c.doppler_unambiguous_mps,
      "> 0: Doppler wraps into [-v, v) [m/s] (0: no aliasing)");
    v("occlusion_leak", c.occlusion_leak, "chance a point behind an opaque object shows");
    v("max_points", c.max_points, "the detection list's limit");
    v("frame_id", c.frame_id, "the PointCloud2 messages' frame");
}

template <typename Visitor>
void VisitFields(ImuConfig &c, Visitor &&v) {
    VisitFields(c.mount, Prefixed{"mount.", v});
    v("rate_hz", c.rate_hz, "[Hz]");
    v("gyro_noise_density", c.gyro_noise_density, "[rad/s/sqrt(Hz)]");
    v("gyro_bias_sigma_radps", c.gyro_bias_sigma_radps, "initial bias spread [rad/s]");
    v("gyro_bias_walk", c.gyro_bias_walk, "bias random walk [rad/s^2/sqrt(Hz)]");
    v("accel_noise_density", c.accel_noise_density, "[m/s^2/sqrt(Hz)]");
    v("accel_bias_sigma_mps2", c.accel_bias_sigma_mps2, "initial bias spread [m/s^2]");
    v("accel_bias_walk", c.accel_bias_walk, "[m/s^3/sqrt(Hz)]");
    v("frame_id", c.frame_id, "the Imu messages' frame");
}

template <typename Visitor>
void VisitFields(GroundTruthConfig &c, Visitor &&v) {
    v("rate_hz", c.rate_hz, "the reference trajectory's rate [Hz]");
    v("position_sigma_m", c.position_sigma_m, "its Gauss-Markov position error [m]");
    v("rotation_sigma_deg", c.rotation_sigma_deg, "its orientation error [deg]");
    v("correlation_time_s", c.correlation_time_s, "the error's correlation time [s]");
}

/// Every key of a sequence file (source_path is where it came from, not a key).
template <typename Visitor>
void VisitFields(SequenceConfig &c, Visitor &&v) {
    v("name", c.name, "the sequence's name; absent: the file's name");
    v("description", c.description, "what the sequence is for");
    v("duration_s", c.duration_s, "[s] (at most 3600)");
    v("seed", c.seed, "the random seed (--seed replaces it)");
    v("start_time_s", c.start_time_s, "stamp of the first sample [s]");
    VisitFields(c.vehicle, Prefixed{"vehicle.", v});
    VisitFields(c.motion, Prefixed{"motion.", v});
    VisitFields(c.terrain, Prefixed{"terrain.", v});
    VisitFields(c.world, Prefixed{"world.", v});
    VisitFields(c.dynamic, Prefixed{"dynamic.", v});
    VisitFields(c.radar, Prefixed{"radar.", v});
    VisitFields(c.imu, Prefixed{"imu.", v});
    VisitFields(c.ground_truth, Prefixed{"ground_truth.", v});
}

}  // namespace dorado::sim
