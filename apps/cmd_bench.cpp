// `dorado bench [CONFIG] --out DIR`: the paper's matrix of sequences x methods, run as child
// processes of this same program, scored against the ground truth, tabulated and plotted.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <thread>

#include "bench_plan.hpp"
#include "bench_report.hpp"
#include "bench_runner.hpp"
#include "commands.hpp"
#include "dorado/io/atomic_file.hpp"
#include "progress.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

struct BenchOptions {
    std::string config_path = "configs/benchmark_paper.yaml";
    std::string out_dir;
    std::size_t jobs = 0;
    bool no_plot = false;
    std::string reference;  ///< empty: the config's
};

// The default config from the current directory, else from the source tree dorado was built in.
std::string FindConfig(const std::string &path) {
    if (fs::exists(path)) return path;
    const fs::path in_source = fs::path(DORADO_SOURCE_DIR) / path;
    if (fs::path(path).is_relative() && fs::exists(in_source)) return in_source.string();
    throw std::runtime_error(path + ": benchmark configuration not found");
}

// Runs scripts/plot_benchmark.py with Debian's python (matplotlib); returns an error or "".
std::string Plot(const std::string &out_dir) {
    const fs::path script = fs::path(DORADO_SOURCE_DIR) / "scripts" / "plot_benchmark.py";
    if (!fs::exists(script)) return script.string() + " not found";
    const pid_t pid = fork();
    if (pid < 0) return "cannot start the plot script";
    if (pid == 0) {
        execl("/usr/bin/python3", "python3", script.c_str(), out_dir.c_str(),
              static_cast<char *>(nullptr));
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
    return "the plot script failed (" + script.string() + ")";
}

void RunBench(const BenchOptions &o) {
    const std::string config_path = FindConfig(o.config_path);
    BenchConfig config = LoadBenchConfig(config_path);
    if (o.jobs > 0) config.jobs = o.jobs;
    if (!o.reference.empty()) config.reference = ParseBenchReference(o.reference);
    if (config.jobs == 0) config.jobs = std::max(1u, std::thread::hardware_concurrency());
    io::MakeDirectories(o.out_dir);
    const std::string out_dir = fs::canonical(o.out_dir).string();

    const std::vector<BenchRun> runs = PlanBenchmark(config, out_dir);
    std::vector<BenchJob> jobs;
    for (const BenchRun &run : runs) jobs.push_back(run.job);

    RunnerOptions runner;
    runner.program = SelfExecutablePath();
    runner.workers = config.jobs;
    runner.log_dir = (fs::path(out_dir) / "logs").string();
    Progress progress("bench", jobs.size());
    runner.on_progress = [&](std::size_t finished, std::size_t total, const std::string &running) {
        progress.Update(finished, running.empty() ? "" : "running: " + running);
        (void)total;
    };
    std::size_t ended = 0;
    runner.on_job_end = [&](std::size_t job, const JobOutcome &outcome) {
        ++ended;
        // One line per ended run above the progress bar (which redraws on its next update).
        if (isatty(fileno(stderr))) std::fprintf(stderr, "\r\033[K");
        const char *what = outcome.status == JobStatus::kAlreadyDone ? "already done"
                           : outcome.status == JobStatus::kSucceeded ? "done"
                                                                     : "FAILED";
        std::fprintf(stderr, "bench: [%zu/%zu] %s %s", ended, jobs.size(), jobs[job].name.c_str(),
                     what);
        if (outcome.status == JobStatus::kSucceeded)
            std::fprintf(stderr, " in %.1f s", outcome.seconds);
        if (outcome.status == JobStatus::kFailed)
            std::fprintf(stderr, ": %s", outcome.message.c_str());
        std::fprintf(stderr, "\n");
    };
    std::fprintf(stderr, "bench: %zu runs (%zu sequences) on %zu parallel jobs, results in %s\n",
                 jobs.size(), config.sequences.size(), config.jobs, out_dir.c_str());
    const std::vector<JobOutcome> outcomes = RunJobs(jobs, runner);
    progress.Finish();

    const std::vector<RunEvaluation> evaluations = EvaluateRuns(runs, outcomes, config);
    WriteReport(evaluations, config, out_dir);
    std::fprintf(stderr, "bench: wrote %s/results.md, results.csv, rpe_pairs.csv\n",
                 out_dir.c_str());

    std::string plot_error;
    if (!o.no_plot) {
        plot_error = Plot(out_dir);
        if (plot_error.empty())
            std::fprintf(stderr, "bench: figures in %s/plots/\n", out_dir.c_str());
    }
    std::size_t failed = 0;
    for (const JobOutcome &outcome : outcomes) failed += outcome.status == JobStatus::kFailed;
    if (failed > 0) {
        throw std::runtime_error(std::to_string(failed) + " of " + std::to_string(jobs.size()) +
                                 " runs failed (logs in " + runner.log_dir +
                                 "); the report covers the others");
    }
    // Runs that finished but could not be scored (no ground truth at their stamps, a missing
    // reference file): the report lists them; the exit status says the matrix is incomplete.
    std::size_t unscored = 0;
    std::string first_note;
    for (const RunEvaluation &e : evaluations) {
        if (e.ok) continue;
        if (unscored++ == 0) first_note = e.sequence + "/" + e.method + ": " + e.note;
    }
    if (unscored > 0) {
        throw std::runtime_error(std::to_string(unscored) +
                                 " runs could not be scored (listed in " + out_dir +
                                 "/results.md), the first: " + first_note);
    }
    if (!plot_error.empty()) throw std::runtime_error(plot_error);
}

}  // namespace

void RegisterBenchCommand(CLI::App &app) {
    auto options = std::make_shared<BenchOptions>();
    CLI::App *cmd = app.add_subcommand(
        "bench",
        "Run a benchmark matrix (sequences x odometry methods and mapper priors) in parallel, "
        "score it against the ground truth and write results.md/.csv and the paper's figures. "
        "Finished runs are kept: running it again only redoes what is missing.");
    cmd->add_option("config", options->config_path, "benchmark YAML")->capture_default_str();
    cmd->add_option("--out", options->out_dir, "output directory")->required();
    cmd->add_option("--jobs", options->jobs,
                    "parallel runs (default: the config's, else all cores)");
    cmd->add_flag("--no-plot", options->no_plot, "skip the figures");
    cmd->add_option("--reference", options->reference,
                    "score against the recorded ground truth (ground_truth, the default) or, for "
                    "simulated sequences, the exact trajectory (exact)")
        ->check(CLI::IsMember({"ground_truth", "exact"}));
    cmd->callback([options] { RunBench(*options); });
}

}  // namespace dorado::apps
