// `dorado eval --gt GT.tum --est EST.tum`: RPE and ATE of one trajectory against its ground truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "commands.hpp"
#include "dorado/eval/absolute_trajectory_error.hpp"
#include "dorado/eval/association.hpp"
#include "dorado/eval/end_point_error.hpp"
#include "dorado/eval/kitti_drift.hpp"
#include "dorado/eval/relative_pose_error.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "one_of.hpp"

namespace dorado::apps {

namespace {

struct EvalOptions {
    std::string gt_path;
    std::string est_path;
    double delta = 1.0;
    std::string unit = "frames";
    std::string association = "interpolate";
    double max_gap_s = 0.5;
    double max_diff_s = 0.01;
    double t_offset_s = 0.0;
    bool sim3 = false;
    std::string json_path;
};

int64_t SecondsToNanosChecked(double seconds, const char *option) {
    if (!(seconds > 0.0) || !std::isfinite(seconds)) {
        throw std::invalid_argument(std::string(option) + ": must be a positive number of seconds");
    }
    return static_cast<int64_t>(std::llround(seconds * 1e9));
}

nlohmann::json ToJson(const eval::Statistics &s) {
    const auto num = [](double v) {
        return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
    };
    return {{"rmse", num(s.rmse)}, {"mean", num(s.mean)}, {"median", num(s.median)},
            {"std", num(s.std)},   {"min", num(s.min)},   {"max", num(s.max)},
            {"count", s.count}};
}

void PrintRow(const char *name, const eval::Statistics &s) {
    std::printf("%-24s %10.6f %10.6f %10.6f %10.6f %10.6f %10.6f %7zu\n", name, s.rmse, s.mean,
                s.median, s.std, s.min, s.max, s.count);
}

void RunEval(const EvalOptions &o) {
    const Trajectory reference = io::ReadTum(o.gt_path);
    const Trajectory estimate = io::ReadTum(o.est_path);
    eval::AssociationConfig association;
    association.method = eval::ParseAssociationMethod(o.association);
    association.t_offset_ns = static_cast<int64_t>(std::llround(o.t_offset_s * 1e9));
    association.max_gap_ns = SecondsToNanosChecked(o.max_gap_s, "--max-gap");
    association.max_time_diff_ns = SecondsToNanosChecked(o.max_diff_s, "--max-diff");
    const eval::AssociatedPoses poses = eval::Associate(reference, estimate, association);
    if (poses.size() < 2) {
        throw std::runtime_error(o.est_path + ": only " + std::to_string(poses.size()) + " of " +
                                 std::to_string(estimate.size()) + " poses have ground truth in " +
                                 o.gt_path + " (check the time stamps and --max-gap/--max-diff)");
    }
    const eval::PairSelection selection{o.delta, eval::ParseDeltaUnit(o.unit), 0.1};
    const eval::RelativeErrors rpe = eval::ComputeRpe(poses, selection);
    if (rpe.pairs.empty()) {
        throw std::runtime_error(o.est_path + ": no pose pair " + std::to_string(o.delta) + " " +
                                 o.unit + " apart");
    }
    const auto rpe_t = eval::ComputeStatistics(rpe.translation_m);
    const auto rpe_r = eval::ComputeStatistics(rpe.rotation_deg);
    std::unique_ptr<eval::AteResult> ate;
    if (poses.size() >= 3)
        ate = std::make_unique<eval::AteResult>(eval::ComputeAte(poses, {o.sim3}));

    std::printf(
        "associated %zu of %zu estimated poses (%zu without ground truth); %zu pairs, "
        "delta %g %s\n",
        poses.size(), estimate.size(), poses.unmatched_est_stamps_ns.size(), rpe.pairs.size(),
        o.delta, eval::ToString(selection.unit).c_str());
    std::printf("%-24s %10s %10s %10s %10s %10s %10s %7s\n", "metric", "rmse", "mean", "median",
                "std", "min", "max", "count");
    PrintRow("rpe_translation [m]", rpe_t);
    PrintRow("rpe_rotation [deg]", rpe_r);
    eval::Statistics ate_stats;
    if (ate) {
        ate_stats = eval::ComputeStatistics(ate->translation_m);
        PrintRow(o.sim3 ? "ate_sim3 [m]" : "ate_se3 [m]", ate_stats);
    }
    const eval::EndPointError end = eval::ComputeEndPointError(poses);
    std::printf(
        "end_point_error          %.3f m, %.3f %% of the reference's %.1f m path (start "
        "poses aligned)\n",
        end.error_m, end.percent, end.path_length_m);
    const eval::DriftConfig drift_config;
    const eval::DriftResult drift = eval::ComputeKittiDrift(poses, drift_config);
    const double shortest_m =
        *std::min_element(drift_config.lengths_m.begin(), drift_config.lengths_m.end());
    if (drift.segments > 0)
        std::printf(
            "kitti_drift (100-800 m)  %.3f %% translation, %.3f deg/100 m rotation, %d "
            "segments\n",
            drift.translation_percent, drift.rotation_deg_per_100m, drift.segments);
    else
        std::printf(
            "kitti_drift (100-800 m)  none: the reference's path is %.1f m, not longer "
            "than the shortest segment (%.0f m)\n",
            end.path_length_m, shortest_m);
    if (o.json_path.empty()) return;
    nlohmann::json j = {
        {"gt", o.gt_path},
        {"est", o.est_path},
        {"associated", poses.size()},
        {"unmatched", poses.unmatched_est_stamps_ns.size()},
        {"delta", o.delta},
        {"delta_unit", eval::ToString(selection.unit)},
        {"rpe_translation_m", ToJson(rpe_t)},
        {"rpe_rotation_deg", ToJson(rpe_r)},
        {"rpe_translation_m_per_pair", rpe.translation_m},
        {"rpe_rotation_deg_per_pair", rpe.rotation_deg},
    };
    j["end_point_error"] = {
        {"error_m", end.error_m},
        {"path_length_m", end.path_length_m},
        {"percent", std::isfinite(end.percent) ? nlohmann::json(end.percent) : nlohmann::json()}};
    if (drift.segments > 0) {
        j["kitti_drift"] = {{"translation_percent", drift.translation_percent},
                            {"rotation_deg_per_100m", drift.rotation_deg_per_100m},
                            {"segments", drift.segments}};
    } else {
        j["kitti_drift_none"] = "the reference's path is shorter than " +
                                std::to_string(static_cast<int>(shortest_m)) + " m";
    }
    if (ate) {
        j["ate_m"] = ToJson(ate_stats);
        j["ate_alignment"] = o.sim3 ? "sim3" : "se3";
        j["ate_scale"] = ate->scale;
    }
    io::WriteFileAtomically(o.json_path, [&](std::ostream &os) { os << j.dump(2) << "\n"; });
}

}  // namespace

void RegisterEvalCommand(CLI::App &app) {
    auto options = std::make_shared<EvalOptions>();
    CLI::App *cmd = app.add_subcommand(
        "eval",
        "Relative pose error (evo's definition: E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j)), ATE, the "
        "end-point error (start poses aligned; m and % of the reference's path) and the KITTI "
        "drift (translation % and rotation deg/100 m over 100..800 m segments, the KITTI devkit's "
        "definition) of an estimated TUM trajectory against a ground-truth TUM trajectory.");
    cmd->add_option("--gt", options->gt_path, "ground truth, TUM format")->required();
    cmd->add_option("--est", options->est_path, "estimate, TUM format")->required();
    cmd->add_option("--delta", options->delta, "RPE pair distance")->capture_default_str();
    cmd->add_option("--unit", options->unit, "unit of --delta")
        ->check(OneOf({"frames", "seconds", "meters", "f", "s", "m"}))
        ->capture_default_str();
    cmd->add_option("--association", options->association,
                    "interpolate: ground truth interpolated at each estimated stamp; nearest: "
                    "evo's nearest stamp within --max-diff")
        ->check(OneOf({"interpolate", "nearest"}))
        ->capture_default_str();
    cmd->add_option("--max-gap", options->max_gap_s,
                    "interpolate: largest ground-truth gap bridged [s]")
        ->capture_default_str();
    cmd->add_option("--t_max_diff,--max-diff", options->max_diff_s,
                    "nearest: largest stamp difference [s] (evo's --t_max_diff)")
        ->capture_default_str();
    cmd->add_option("--t_offset", options->t_offset_s,
                    "nearest: added to the estimated stamps before matching [s] (evo's --t_offset)")
        ->capture_default_str();
    cmd->add_flag("--sim3", options->sim3, "ATE with Sim(3) (scale) alignment instead of SE(3)");
    cmd->add_option("--json", options->json_path, "also write the statistics as JSON");
    cmd->callback([options] { RunEval(*options); });
}

}  // namespace dorado::apps
