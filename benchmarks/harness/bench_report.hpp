#pragma once
/// @file bench_report.hpp
/// Scores the finished runs of a benchmark against their ground truth and writes the report:
/// results.csv (statistics per sequence, method and metric, and over all sequences),
/// bench_runs.csv (each run: directory, ground truth, status, poses),
/// rpe_pairs.csv (every RPE pair, for the box plots) and results.md (tables). The evaluation is in
/// bench_evaluate.cpp, the writing in bench_report.cpp.

#include <string>
#include <vector>

#include "bench_plan.hpp"
#include "bench_runner.hpp"
#include "dorado/eval/relative_pose_error.hpp"
#include "dorado/eval/statistics.hpp"

namespace dorado::apps {

struct RunEvaluation {
    std::string sequence;
    std::string method;
    RunKind kind = RunKind::kOdometry;
    std::string run_dir;
    std::string ground_truth;
    bool ok = false;
    std::string note;             ///< why it was not scored, or what limits its score
    bool has_translation = true;  ///< false for gyro-only odometry (rotation RPE only)
    std::size_t poses = 0;        ///< poses in its trajectory
    std::size_t matched = 0;      ///< poses with ground truth
    std::size_t scored = 0;       ///< poses on the sequence's common stamps
    eval::RelativeErrors rpe_frame;
    eval::RelativeErrors rpe_second;
    std::vector<double> ate_m;
    std::vector<double> time_per_scan_ms;
};

/// Evaluates every odometry and map run (simulations are skipped). Within a sequence, all runs
/// are scored on the stamps they have in common (so on the same RPE pairs); a run holding fewer
/// than half of the best run's stamps is scored on its own stamps and says so in its note.
[[nodiscard]] std::vector<RunEvaluation> EvaluateRuns(const std::vector<BenchRun> &runs,
                                                      const std::vector<JobOutcome> &outcomes,
                                                      const BenchConfig &config);

/// Writes results.csv, rpe_pairs.csv, bench_runs.csv and results.md into out_dir, each atomically.
void WriteReport(const std::vector<RunEvaluation> &evaluations, const BenchConfig &config,
                 const std::string &out_dir);

/// Values of one named column of a CSV file with a header row (NaN for unparsable cells);
/// empty when the file or the column is missing.
[[nodiscard]] std::vector<double> ReadCsvColumn(const std::string &path, const std::string &column);

}  // namespace dorado::apps
