#pragma once
/// @file simulator.hpp
/// Runs a whole sequence: builds terrain, route, world and moving objects from the sequence
/// description, then streams radar scans, IMU samples and ground-truth poses in time order into
/// a ROS1 bag, and keeps the truth needed to judge estimators.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/trajectory.hpp"
#include "dorado/core/twist.hpp"
#include "dorado/sim/sequence_config.hpp"

namespace dorado::sim {

/// Topic names of the written bag (those of the paper's dataset for the radar).
struct BagTopics {
    std::string radar = "/hugin_raf_1/radar_data";
    std::string imu = "/imu/data";
    std::string ground_truth = "/ground_truth/odom";
    std::string world_frame = "map";
    std::string base_frame = "base_link";
};

/// The exact velocity of the vehicle at one radar scan.
struct TrueTwist {
    int64_t stamp_ns = 0;
    Twist twist_base;  ///< the base's twist in the base frame (exact: zero covariance)
    Eigen::Vector3d v_radar = Eigen::Vector3d::Zero();  ///< radar origin, radar frame [m/s]
};

struct SimulationStats {
    double duration_s = 0.0;
    std::size_t scans = 0;
    double points_per_scan_mean = 0.0;
    std::size_t points_per_scan_min = 0;
    std::size_t points_per_scan_max = 0;
    double dynamic_fraction = 0.0;      ///< points on moving objects / all points
    double max_dynamic_fraction = 0.0;  ///< the worst scan
    double ground_fraction = 0.0;
    double ghost_fraction = 0.0;  ///< multipath and ambiguity ghosts / all points
    double clutter_fraction = 0.0;
    std::size_t imu_samples = 0;
    std::size_t ground_truth_poses = 0;
    std::size_t static_reflectors = 0;
    std::size_t moving_objects = 0;
    double path_length_m = 0.0;
    double max_speed_mps = 0.0;
    double rms_roll_rate_radps = 0.0;
    double rms_pitch_rate_radps = 0.0;
    double max_abs_roll_deg = 0.0;
    double max_abs_pitch_deg = 0.0;
    double seconds_taken = 0.0;
};

struct SimulationResult {
    Trajectory ground_truth;        ///< base frame, at the lidar's rate, with the mapper's error
    Trajectory true_trajectory;     ///< the exact base pose at the same stamps
    std::vector<TrueTwist> twists;  ///< one per radar scan
    Extrinsics extrinsics;
    VehicleGeometry vehicle;
    SimulationStats stats;
};

/// Called with (scans done, scans total).
using ProgressCallback = std::function<void(std::size_t, std::size_t)>;

/// Simulates the sequence into `bag_path`. Throws std::runtime_error naming the file on I/O errors.
[[nodiscard]] SimulationResult Simulate(const SequenceConfig &config, const std::string &bag_path,
                                        const BagTopics &topics = {},
                                        const ProgressCallback &progress = {});

/// Writes DIR/data.bag, ground_truth.tum, true_trajectory.tum, true_twist.csv, dataset.yaml and
/// simulation.json
/// (the layout of `dorado simulate`). Returns the result.
SimulationResult SimulateToDirectory(const SequenceConfig &config, const std::string &out_dir,
                                     const ProgressCallback &progress = {});

}  // namespace dorado::sim
