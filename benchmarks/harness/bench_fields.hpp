#pragma once
/// @file bench_fields.hpp
/// The bench file's field lists (`VisitFields`, core/config_fields.hpp): every key of a
/// configs/benchmark_*.yaml once, with its doc. ParseBenchConfig reads them and `dorado config
/// keys` lists them (docs/config_keys.md). `sequences:` (a list: each entry BenchSequence's list)
/// and `grid:` (config keys to lists of values) have readers of their own.

#include "bench_plan.hpp"
#include "dorado/core/config_fields.hpp"
#include "dorado/mapping/mapper_fields.hpp"
#include "dorado/odometry/odometry_fields.hpp"

namespace dorado::apps {

inline Choices<eval::AssociationMethod> AssociationMethodChoices() {
    return {{"interpolate", eval::AssociationMethod::kInterpolate},
            {"nearest", eval::AssociationMethod::kNearest}};
}
inline Choices<BenchReference> BenchReferenceChoices() {
    return {{"ground_truth", BenchReference::kGroundTruth}, {"exact", BenchReference::kExact}};
}

/// One entry of `sequences:`: `simulate:` or `dataset:` + `ground_truth:`.
template <typename Visitor>
void VisitFields(BenchSequence &c, Visitor &&v) {
    v("name", c.name, "directory and table name (required; no '/', '@' or spaces)");
    v("simulate.sequence", c.simulate_sequence,
      "`dorado simulate --sequence`: a name or a .yaml (relative to this file); absent: name");
    v("simulate.seed", c.seed, "--seed");
    v("simulate.duration_s", c.duration_s, "--duration [s] (>= 0; 0: the sequence's own)");
    v("dataset", c.dataset, kPath, "recorded data: a dataset description or a bag");
    v("data", c.data,
      "recorded data: the folder given to its runs as --data (the description's relative paths "
      "are taken from it); relative: to data_dir; empty: the description's own paths");
    v("ground_truth", c.ground_truth, kPath,
      "recorded data: its TUM ground truth; absent: the description's ground_truth.path");
    v("odometry", c.odometry_methods, odometry::OdometryMethodChoices(),
      "this sequence's odometry methods; absent: the benchmark's");
    v("map_priors", c.map_priors, mapping::PriorKindChoices(),
      "this sequence's mapper priors; absent: the benchmark's");
}

/// Every key but `sequences:` and `grid:`.
template <typename Visitor>
void VisitFields(BenchConfig &c, Visitor &&v) {
    v("odometry", c.odometry_methods, odometry::OdometryMethodChoices(),
      "odometry methods (paper Fig. 5)");
    v("map_priors", c.map_priors, mapping::PriorKindChoices(), "mapper priors (paper Fig. 6, 7)");
    v("odometry_config", c.odometry_config, kPath, "--config of `dorado odometry`; empty: none");
    v("map_config", c.map_config, kPath, "--config of `dorado map`; empty: none");
    v("data_dir", c.data_dir, kPath,
      "the folder the sequences' relative data: are taken from, relative to this file; absent: "
      "this file's folder; `dorado bench --data DIR` replaces it");
    v("jobs", c.jobs, "parallel runs; 0: the number of cores");
    v("association", c.association, AssociationMethodChoices(),
      "ground truth at each estimated stamp: interpolated, or evo's nearest");
    v("association_max_gap_s", c.association_max_gap_s, "interpolate: gap limit [s] (> 0)");
    v("t_max_diff_s", c.t_max_diff_s, "nearest: evo's --t_max_diff [s] (> 0)");
    v("rpe_frame_delta", c.rpe_frame_delta, "RPE over this many frames (>= 1)");
    v("rpe_second_delta_s", c.rpe_second_delta_s, "RPE over this many seconds (> 0)");
    v("reference", c.reference, BenchReferenceChoices(),
      "scored against: the recorded ground truth, or (simulated) the exact trajectory");
}

}  // namespace dorado::apps
