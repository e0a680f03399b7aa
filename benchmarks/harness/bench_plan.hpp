#pragma once
/// @file bench_plan.hpp
/// The benchmark matrix (sequences x methods) read from a YAML file, and the jobs that run it.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bench_runner.hpp"

namespace dorado::apps {

/// One sequence: either simulated by `dorado simulate` into the output directory, or an existing
/// dataset description (or bag) with its ground truth.
struct BenchSequence {
    std::string name;  ///< used in directory names and tables
    // Simulated: `dorado simulate --sequence <simulate_sequence> --seed --duration`.
    std::string simulate_sequence;
    int64_t seed = 1;
    double duration_s = 0.0;  ///< 0: the simulator's default
    // Existing data (when simulate_sequence is empty).
    std::string dataset;
    std::string ground_truth;
};

/// What the runs are scored against.
enum class BenchReference {
    kGroundTruth,  ///< the recorded ground truth (simulated: ground_truth.tum, with a lidar
                   ///< mapper's error, as in the paper)
    kExact,        ///< simulated sequences only: the exact trajectory (true_trajectory.tum), so
                   ///< that an estimator's own error is not hidden under the reference's
};

/// Parses "ground_truth" | "exact"; throws std::invalid_argument otherwise.
[[nodiscard]] BenchReference ParseBenchReference(const std::string &text);

struct BenchConfig {
    std::vector<BenchSequence> sequences;
    /// Odometry methods (paper Fig. 5): imu (gyro rotation only), doppler, imu+doppler.
    std::vector<std::string> odometry_methods{"imu", "doppler", "imu+doppler"};
    /// Mapper priors (paper Fig. 6, 7): none, constvel, imu, doppler, imu+doppler.
    std::vector<std::string> map_priors{"none", "constvel", "imu", "doppler", "imu+doppler"};
    std::string odometry_config;         ///< optional --config for `dorado odometry`
    std::string map_config;              ///< optional --config for `dorado map`
    std::size_t jobs = 0;                ///< parallel runs; 0 = the number of cores
    double association_max_gap_s = 0.5;  ///< ground-truth interpolation gap limit
    int rpe_frame_delta = 1;
    double rpe_second_delta_s = 1.0;
    BenchReference reference = BenchReference::kGroundTruth;
};

/// Reads and validates the YAML file; relative paths in it are taken from the file's directory.
/// Throws std::runtime_error naming the file and the key.
[[nodiscard]] BenchConfig LoadBenchConfig(const std::string &path);
/// Same, from YAML text; `base_dir` resolves relative paths, `origin` names the source in errors.
[[nodiscard]] BenchConfig ParseBenchConfig(const std::string &yaml_text,
                                           const std::string &base_dir, const std::string &origin);

enum class RunKind { kSimulate, kOdometry, kMap };

/// One cell of the matrix (or the simulation feeding a row).
struct BenchRun {
    RunKind kind = RunKind::kOdometry;
    std::string sequence;
    std::string method;   ///< "odom_doppler", "map_imu+doppler", ... ("simulate" for simulations)
    std::string dataset;  ///< the DATASET argument of the run
    std::string ground_truth;  ///< TUM ground truth of its sequence
    BenchJob job;
};

/// Runs in dependency order (each sequence's simulation before its runs). Layout under out_dir:
/// data/<sequence>/ (simulations), runs/<sequence>/<method>/, logs/. Throws std::runtime_error
/// naming the sequence when the reference is exact and a sequence is not simulated.
[[nodiscard]] std::vector<BenchRun> PlanBenchmark(const BenchConfig &config,
                                                  const std::string &out_dir);

}  // namespace dorado::apps
