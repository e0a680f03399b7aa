// Evaluation of the benchmark's runs against their ground truth (the first half of the report):
// association, the common stamps of each sequence, RPE and ATE. bench_report.cpp writes the files.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "bench_report.hpp"
#include "dorado/eval/absolute_trajectory_error.hpp"
#include "dorado/eval/association.hpp"
#include "dorado/io/trajectory_io.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

std::vector<int64_t> Intersect(const std::vector<int64_t> &a, const std::vector<int64_t> &b) {
    std::vector<int64_t> out;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
    return out;
}

// Mean time per scan from the run's own per-scan CSV.
std::vector<double> TimePerScan(const BenchRun &run) {
    if (run.kind == RunKind::kMap) {
        return ReadCsvColumn((fs::path(run.job.out_dir) / "scans.csv").string(), "time_total_ms");
    }
    return ReadCsvColumn((fs::path(run.job.out_dir) / "velocities.csv").string(), "time_ms");
}

// A run's trajectory associated with its ground truth (`ground_truths` caches the files read);
// e.ok when at least 3 poses have ground truth, else e.note says why.
eval::AssociatedPoses AssociateRun(const BenchRun &run, const JobOutcome &outcome,
                                   const BenchConfig &config,
                                   const eval::AssociationConfig &association,
                                   std::map<std::string, Trajectory> &ground_truths,
                                   RunEvaluation &e) {
    e.sequence = run.sequence;
    e.method = run.method;
    e.kind = run.kind;
    e.run_dir = run.job.out_dir;
    e.ground_truth = run.ground_truth;
    e.has_translation = run.has_translation;
    eval::AssociatedPoses associated;
    const bool finished =
        outcome.status == JobStatus::kSucceeded || outcome.status == JobStatus::kAlreadyDone;
    if (!finished) {
        e.note = "run failed: " + outcome.message;
        return associated;
    }
    if (config.reference == BenchReference::kExact && !fs::exists(run.ground_truth)) {
        // Data simulated before the simulator wrote its exact trajectory: the sequence's runs
        // were made on that data, so they go too.
        e.note = run.ground_truth + ": missing; delete " +
                 fs::path(run.ground_truth).parent_path().string() + " and " +
                 fs::path(run.job.out_dir).parent_path().string() + " to simulate and run it again";
        return associated;
    }
    try {
        if (!ground_truths.count(run.ground_truth)) {
            ground_truths[run.ground_truth] = io::ReadTum(run.ground_truth);
        }
        const Trajectory estimate =
            io::ReadTum((fs::path(run.job.out_dir) / "trajectory.tum").string());
        e.poses = estimate.size();
        associated = eval::Associate(ground_truths[run.ground_truth], estimate, association);
        e.matched = associated.size();
        e.ok = e.matched >= 3;
        if (!e.ok) e.note = "fewer than 3 poses have ground truth";
    } catch (const std::exception &ex) {
        e.note = ex.what();
    }
    e.time_per_scan_ms = TimePerScan(run);
    return associated;
}

// Common stamps per sequence, from the runs that cover at least half of the best one (`best`:
// the most matched poses of a run of each sequence).
std::map<std::string, std::vector<int64_t>> CommonStamps(
    const std::vector<RunEvaluation> &evaluations,
    const std::vector<eval::AssociatedPoses> &associated,
    const std::map<std::string, std::size_t> &best) {
    std::map<std::string, std::vector<int64_t>> common;
    for (std::size_t k = 0; k < evaluations.size(); ++k) {
        const RunEvaluation &e = evaluations[k];
        if (!e.ok || 2 * e.matched < best.at(e.sequence)) continue;
        auto [it, first] = common.try_emplace(e.sequence, associated[k].stamps_ns);
        if (!first) it->second = Intersect(it->second, associated[k].stamps_ns);
    }
    return common;
}

// RPE per frame and per second, and ATE, of one run on the stamps it is scored on.
void Score(const BenchConfig &config, eval::AssociatedPoses poses, std::size_t best,
           const std::vector<int64_t> &common, RunEvaluation &e) {
    const eval::PairSelection per_frame{static_cast<double>(config.rpe_frame_delta),
                                        eval::DeltaUnit::kFrames, 0.1};
    const eval::PairSelection per_second{config.rpe_second_delta_s, eval::DeltaUnit::kSeconds, 0.1};
    if (2 * e.matched >= best) {
        poses = eval::KeepStamps(poses, common);
    } else {
        e.note = "scored on its own " + std::to_string(e.matched) + " stamps (the best run has " +
                 std::to_string(best) + ")";
    }
    e.scored = poses.size();
    if (e.scored < 3) {
        e.ok = false;
        e.note = "fewer than 3 poses in common with the other runs";
        return;
    }
    e.rpe_frame = eval::ComputeRpe(poses, per_frame);
    e.rpe_second = eval::ComputeRpe(poses, per_second);
    if (e.has_translation) e.ate_m = eval::ComputeAte(poses).translation_m;
}

}  // namespace

std::vector<double> ReadCsvColumn(const std::string &path, const std::string &column) {
    std::ifstream in(path);
    std::string line;
    if (!in || !std::getline(in, line)) return {};
    const auto split = [](const std::string &text) {
        std::vector<std::string> cells;
        std::stringstream ss(text);
        for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
        return cells;
    };
    const auto header = split(line);
    const auto it = std::find(header.begin(), header.end(), column);
    if (it == header.end()) return {};
    const auto index = static_cast<std::size_t>(it - header.begin());
    std::vector<double> values;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        const auto cells = split(line);
        double v = std::nan("");
        if (index < cells.size()) {
            try {
                v = std::stod(cells[index]);
            } catch (const std::exception &) {
            }
        }
        values.push_back(v);
    }
    return values;
}

std::vector<RunEvaluation> EvaluateRuns(const std::vector<BenchRun> &runs,
                                        const std::vector<JobOutcome> &outcomes,
                                        const BenchConfig &config) {
    eval::AssociationConfig association;
    association.method = config.association;
    association.max_gap_ns = static_cast<int64_t>(std::llround(config.association_max_gap_s * 1e9));
    association.max_time_diff_ns = static_cast<int64_t>(std::llround(config.t_max_diff_s * 1e9));

    std::vector<RunEvaluation> evaluations;
    std::vector<eval::AssociatedPoses> associated;
    std::map<std::string, Trajectory> ground_truths;
    for (std::size_t r = 0; r < runs.size(); ++r) {
        if (runs[r].kind == RunKind::kSimulate) continue;
        evaluations.emplace_back();
        associated.push_back(AssociateRun(runs[r], outcomes[r], config, association, ground_truths,
                                          evaluations.back()));
    }
    std::map<std::string, std::size_t> best;
    for (const RunEvaluation &e : evaluations)
        best[e.sequence] = std::max(best[e.sequence], e.matched);
    auto common = CommonStamps(evaluations, associated, best);
    for (std::size_t k = 0; k < evaluations.size(); ++k) {
        RunEvaluation &e = evaluations[k];
        if (e.ok) Score(config, associated[k], best[e.sequence], common[e.sequence], e);
    }
    return evaluations;
}

}  // namespace dorado::apps
