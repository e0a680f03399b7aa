// `dorado simulate --sequence NAME|FILE.yaml --out DIR`: a synthetic dataset shaped like the
// paper's (Hugin radar bag, IMU, lidar-rate ground truth) plus its dataset description.
#include <cstdio>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "dorado/sim/sequence_config.hpp"
#include "dorado/sim/simulator.hpp"
#include "progress.hpp"

namespace dorado::apps {

namespace {

struct SimulateOptions {
    std::string sequence;
    std::string out_dir;
    std::optional<uint64_t> seed;
    std::optional<double> duration_s;
};

void RunSimulate(const SimulateOptions &options) {
    sim::SequenceConfig config = sim::LoadSequenceConfig(sim::FindSequenceFile(options.sequence));
    if (options.seed) config.seed = *options.seed;
    if (options.duration_s) config.duration_s = *options.duration_s;
    try {
        config.Validate();
    } catch (const sim::SequenceConfigError &e) {
        throw std::runtime_error(std::string(e.what()) + " (after --seed/--duration)");
    }
    std::unique_ptr<Progress> progress;
    const sim::SimulationResult result =
        sim::SimulateToDirectory(config, options.out_dir, [&](std::size_t done, std::size_t total) {
            if (!progress) progress = std::make_unique<Progress>("simulate " + config.name, total);
            progress->Update(done);
        });
    if (progress) progress->Finish();
    const sim::SimulationStats &s = result.stats;
    std::printf(
        "%s: %.1f s, %zu scans, %.0f points/scan (%zu-%zu), dynamic %.1f%% (worst scan %.0f%%), "
        "ghosts %.1f%%, clutter %.1f%%, ground %.1f%%, path %.0f m, max roll %.1f deg, "
        "max pitch %.1f deg, %.2f s to simulate\n",
        config.name.c_str(), s.duration_s, s.scans, s.points_per_scan_mean, s.points_per_scan_min,
        s.points_per_scan_max, 100.0 * s.dynamic_fraction, 100.0 * s.max_dynamic_fraction,
        100.0 * s.ghost_fraction, 100.0 * s.clutter_fraction, 100.0 * s.ground_fraction,
        s.path_length_m, s.max_abs_roll_deg, s.max_abs_pitch_deg, s.seconds_taken);
    std::printf(
        "wrote %s/{data.bag, ground_truth.tum, true_twist.csv, dataset.yaml, simulation.json}\n",
        options.out_dir.c_str());
}

}  // namespace

void RegisterSimulateCommand(CLI::App &app) {
    std::string built_in;
    for (const std::string &name : sim::BuiltInSequences()) built_in += " " + name;
    auto *cmd =
        app.add_subcommand("simulate",
                           "Simulate a radar dataset (Hugin-like 4D radar, IMU, lidar-rate "
                           "ground truth) from a sequence description: a built-in name (" +
                               built_in.substr(built_in.empty() ? 0 : 1) + ") or a YAML file");
    auto options = std::make_shared<SimulateOptions>();
    cmd->add_option("--sequence", options->sequence,
                    "built-in sequence name or a sequence YAML file")
        ->required();
    cmd->add_option("--out", options->out_dir, "output folder (created)")->required();
    cmd->add_option("--seed", options->seed, "random seed (overrides the sequence's)");
    cmd->add_option("--duration", options->duration_s, "duration [s] (overrides the sequence's)");
    cmd->callback([options]() { RunSimulate(*options); });
}

}  // namespace dorado::apps
