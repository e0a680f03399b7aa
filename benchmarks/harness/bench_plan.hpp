#pragma once
/// @file bench_plan.hpp
/// The benchmark matrix (sequences x methods) read from a YAML file, and the jobs that run it.

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "bench_grid.hpp"
#include "bench_runner.hpp"
#include "dorado/eval/association.hpp"
#include "dorado/mapping/motion_prior.hpp"
#include "dorado/odometry/doppler_odometry.hpp"

namespace dorado::io {
struct FieldRow;  // io/field_yaml.hpp
}  // namespace dorado::io

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
    std::string data;  ///< --data of its runs (resolved); empty: the description's own paths
    std::string ground_truth;
    /// This sequence's own method lists (`odometry:`, `map_priors:` in its entry), e.g. without
    /// the IMU priors for a recording without an IMU; empty = the benchmark's lists.
    std::optional<std::vector<odometry::OdometryMethod>> odometry_methods;
    std::optional<std::vector<mapping::PriorKind>> map_priors;
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
    std::vector<odometry::OdometryMethod> odometry_methods{odometry::OdometryMethod::kImu,
                                                           odometry::OdometryMethod::kDoppler,
                                                           odometry::OdometryMethod::kImuDoppler};
    /// Mapper priors (paper Fig. 6, 7): none, constvel, imu, doppler, imu+doppler.
    std::vector<mapping::PriorKind> map_priors{std::begin(mapping::kAllPriorKinds),
                                               std::end(mapping::kAllPriorKinds)};
    std::string odometry_config;  ///< optional --config for `dorado odometry`
    std::string map_config;       ///< optional --config for `dorado map`
    /// The folder the sequences' relative `data:` are taken from (resolved; empty: the bench
    /// file's folder).
    std::string data_dir;
    /// Parameter grids (YAML `grid: {odometry: {...}, map: {...}}`): dotted keys of the
    /// odometry / map config file, each with a list of values; every point is a variant.
    std::vector<GridAxis> odometry_grid;
    std::vector<GridAxis> map_grid;
    std::size_t jobs = 0;  ///< parallel runs; 0 = the number of cores
    /// interpolate: ground truth interpolated at each estimated stamp (within
    /// association_max_gap_s); nearest: evo's nearest stamp within t_max_diff_s.
    eval::AssociationMethod association = eval::AssociationMethod::kInterpolate;
    double association_max_gap_s = 0.5;  ///< ground-truth interpolation gap limit
    double t_max_diff_s = 0.01;          ///< nearest: evo's --t_max_diff
    int rpe_frame_delta = 1;
    double rpe_second_delta_s = 1.0;
    BenchReference reference = BenchReference::kGroundTruth;
};

/// Reads and validates the YAML file; relative paths in it are taken from the file's directory,
/// the sequences' `data:` from @p data_dir when given (`dorado bench --data DIR`), else from the
/// file's `data_dir:`. Throws std::runtime_error naming the file and the key.
[[nodiscard]] BenchConfig LoadBenchConfig(const std::string &path,
                                          const std::string &data_dir = "");
/// Same, from YAML text; `base_dir` resolves relative paths, `origin` names the source in errors.
[[nodiscard]] BenchConfig ParseBenchConfig(const std::string &yaml_text,
                                           const std::string &base_dir, const std::string &origin,
                                           const std::string &data_dir = "");

/// Checks every input of every recorded sequence before the first run: its dataset (a
/// description's every path, as its runs will resolve them), its ground truth, the settings
/// files. Throws std::runtime_error naming the sequence, the key and the missing path.
void CheckBenchInputs(const BenchConfig &config);

/// Every key of the bench file with its built-in default and doc (`sequences[].` an entry's;
/// `grid:` not: config keys to lists of values).
[[nodiscard]] std::vector<io::FieldRow> BenchConfigFields();

enum class RunKind { kSimulate, kOdometry, kMap };

/// One cell of the matrix (or the simulation feeding a row).
struct BenchRun {
    RunKind kind = RunKind::kOdometry;
    std::string sequence;
    /// "odom_doppler", "map_imu+doppler", "map_doppler@max_iterations=5" (a grid variant), ...
    /// ("simulate" for simulations)
    std::string method;
    std::string dataset;          ///< the DATASET argument of the run
    std::string ground_truth;     ///< TUM ground truth of its sequence
    bool has_translation = true;  ///< false for gyro-only odometry (rotation RPE only)
    BenchJob job;
};

/// Runs in dependency order (each sequence's simulation before its runs). Layout under out_dir:
/// data/<sequence>/ (simulations), runs/<sequence>/<method>/, configs/ (the grid variants' config
/// files, see WriteVariantConfigs), logs/. Throws std::runtime_error
/// naming the sequence when the reference is exact and a sequence is not simulated.
[[nodiscard]] std::vector<BenchRun> PlanBenchmark(const BenchConfig &config,
                                                  const std::string &out_dir);

/// Writes the config file of every grid variant the plan's runs name (out_dir/configs/).
void WriteVariantConfigs(const BenchConfig &config, const std::string &out_dir);

}  // namespace dorado::apps
