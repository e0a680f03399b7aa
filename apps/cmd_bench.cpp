// `dorado bench [CONFIG] --out DIR`: the paper's matrix of sequences x methods, run as child
// processes of this same program, scored against the ground truth, tabulated and plotted.
// For a workflow engine (workflow/Snakefile): --plan-only prints the runs as JSON, --run-one runs
// one of them, --score-only writes the report from the runs found on disk.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

#include "bench_plan.hpp"
#include "bench_report.hpp"
#include "bench_runner.hpp"
#include "commands.hpp"
#include "dorado/config/map_config.hpp"
#include "dorado/config/odometry_config.hpp"
#include "dorado/io/atomic_file.hpp"
#include "one_of.hpp"
#include "output_folder.hpp"
#include "progress.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

struct BenchOptions {
    std::string config_path = "configs/benchmark_paper.yaml";
    std::string out_dir;
    std::string data_dir;  ///< --data: the folder the sequences' data: are taken from
    std::size_t jobs = 0;
    bool no_plot = false;
    std::string reference;      ///< empty: the config's
    std::string association;    ///< empty: the config's
    double t_max_diff_s = 0.0;  ///< 0: the config's
    bool plan_only = false;
    bool score_only = false;
    std::string run_one;  ///< a run's name, "<sequence>/<method>"
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

BenchConfig LoadConfig(const BenchOptions &o) {
    BenchConfig config = LoadBenchConfig(FindConfig(o.config_path), o.data_dir);
    if (o.jobs > 0) config.jobs = o.jobs;
    if (!o.reference.empty()) config.reference = ParseBenchReference(o.reference);
    if (!o.association.empty()) config.association = eval::ParseAssociationMethod(o.association);
    if (o.t_max_diff_s > 0.0) config.t_max_diff_s = o.t_max_diff_s;
    if (config.jobs == 0) config.jobs = std::max(1u, std::thread::hardware_concurrency());
    return config;
}

// The runs as JSON for a workflow engine: name, output directory, marker, dependencies (names)
// and the command line ("{out}" is the temporary directory).
void PrintPlan(const std::vector<BenchRun> &runs, const std::string &out_dir) {
    nlohmann::json list = nlohmann::json::array();
    for (const BenchRun &run : runs) {
        std::vector<std::string> depends_on;
        for (const std::size_t d : run.job.depends_on) depends_on.push_back(runs[d].job.name);
        list.push_back({{"name", run.job.name},
                        {"sequence", run.sequence},
                        {"method", run.method},
                        {"kind", run.kind == RunKind::kSimulate   ? "simulate"
                                 : run.kind == RunKind::kOdometry ? "odometry"
                                                                  : "map"},
                        {"out_dir", run.job.out_dir},
                        {"marker", run.job.marker},
                        {"depends_on", depends_on},
                        {"args", run.job.args}});
    }
    std::cout << nlohmann::json{{"out", out_dir}, {"runs", list}}.dump(1) << "\n";
}

// One run, as `dorado bench` runs it (temporary directory, published by a rename when it
// succeeded); its dependencies must be done already.
void RunOne(const std::vector<BenchRun> &runs, const std::string &name, const std::string &out) {
    const auto it = std::find_if(runs.begin(), runs.end(),
                                 [&](const BenchRun &r) { return r.job.name == name; });
    if (it == runs.end()) throw std::runtime_error("--run-one: no run named '" + name + "'");
    BenchJob job = it->job;
    for (const std::size_t d : job.depends_on) {
        if (!fs::exists(fs::path(runs[d].job.out_dir) / runs[d].job.marker)) {
            throw std::runtime_error("--run-one " + name + ": needs " + runs[d].job.name +
                                     ", which is not done");
        }
    }
    job.depends_on.clear();
    RunnerOptions runner;
    runner.program = SelfExecutablePath();
    runner.log_dir = (fs::path(out) / "logs").string();
    const JobOutcome outcome = RunJobs({job}, runner).front();
    if (outcome.status == JobStatus::kFailed)
        throw std::runtime_error(name + ": " + outcome.message);
    std::fprintf(stderr, "bench: %s %s\n", name.c_str(),
                 outcome.status == JobStatus::kAlreadyDone ? "already done" : "done");
}

// Runs the matrix on this machine; returns one outcome per run.
std::vector<JobOutcome> RunAll(const std::vector<BenchRun> &runs, const BenchConfig &config,
                               const std::string &out_dir) {
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
    runner.on_stale = [&](std::size_t job) {
        std::fprintf(stderr,
                     "bench: %s: the finished run in %s had other settings or inputs: run again\n",
                     jobs[job].name.c_str(), jobs[job].out_dir.c_str());
    };
    const SignalCatcher signals;  // Ctrl-C: the running runs end, nothing new starts
    runner.stop_requested = [&] { return signals.caught() != 0; };
    std::fprintf(stderr, "bench: %zu runs (%zu sequences) on %zu parallel jobs, results in %s\n",
                 jobs.size(), config.sequences.size(), config.jobs, out_dir.c_str());
    std::vector<JobOutcome> outcomes = RunJobs(jobs, runner);
    progress.Finish();
    if (signals.caught() != 0) {
        std::size_t finished = 0;
        for (const JobOutcome &o : outcomes) finished += o.status != JobStatus::kFailed;
        throw StoppedEarly("bench " +
                               std::string(signals.caught() == SIGINT ? "interrupted (SIGINT)"
                                                                      : "terminated (SIGTERM)") +
                               ": " + std::to_string(finished) + " of " +
                               std::to_string(jobs.size()) + " runs finished, kept in " + out_dir +
                               "/runs (logs in " + out_dir +
                               "/logs); no report written: the same command again runs the "
                               "others and writes it",
                           130);
    }
    return outcomes;
}

// --score-only: the runs found finished on disk; the others count as failed (not run).
std::vector<JobOutcome> OutcomesOnDisk(const std::vector<BenchRun> &runs) {
    std::vector<JobOutcome> outcomes;
    for (const BenchRun &run : runs) {
        const bool done = fs::exists(fs::path(run.job.out_dir) / run.job.marker);
        outcomes.push_back(
            {done ? JobStatus::kAlreadyDone : JobStatus::kFailed, 0.0,
             done ? "" : "not run (no " + run.job.out_dir + "/" + run.job.marker + ")"});
    }
    return outcomes;
}

void Report(const std::vector<BenchRun> &runs, const std::vector<JobOutcome> &outcomes,
            const BenchConfig &config, const std::string &out_dir, bool no_plot) {
    const std::vector<RunEvaluation> evaluations = EvaluateRuns(runs, outcomes, config);
    WriteReport(evaluations, config, out_dir);
    std::fprintf(stderr, "bench: wrote %s/results.md, results.csv, rpe_pairs.csv\n",
                 out_dir.c_str());

    std::string plot_error;
    if (!no_plot) {
        plot_error = Plot(out_dir);
        if (plot_error.empty())
            std::fprintf(stderr, "bench: figures in %s/plots/\n", out_dir.c_str());
    }
    std::size_t failed = 0;
    std::string first_failure;
    for (std::size_t i = 0; i < outcomes.size(); ++i) {
        if (outcomes[i].status != JobStatus::kFailed) continue;
        if (failed++ == 0) first_failure = runs[i].job.name + ": " + outcomes[i].message;
    }
    if (failed > 0) {
        throw std::runtime_error(
            std::to_string(failed) + " of " + std::to_string(runs.size()) +
            " runs failed (logs in " + out_dir +
            "/logs); the report covers the others; the first: " + first_failure);
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

// Writes the grid variants' config files and reads each back as its command will, so that a
// misspelled grid key stops the sweep before any run, naming the key.
void WriteAndCheckVariantConfigs(const BenchConfig &config, const std::string &out_dir) {
    WriteVariantConfigs(config, out_dir);
    try {
        for (const GridVariant &v : GridVariants(config.odometry_grid)) {
            if (!v.name.empty())
                (void)config::LoadOdometryConfig(VariantConfigPath(out_dir, "odometry", v));
        }
        for (const GridVariant &v : GridVariants(config.map_grid)) {
            if (!v.name.empty()) (void)config::LoadMapConfig(VariantConfigPath(out_dir, "map", v));
        }
    } catch (const std::exception &e) {
        throw std::runtime_error(std::string("grid: ") + e.what());
    }
}

void RunBench(const BenchOptions &o) {
    if (o.plan_only + o.score_only + !o.run_one.empty() > 1) {
        throw std::invalid_argument("--plan-only, --score-only and --run-one exclude each other");
    }
    const BenchConfig config = LoadConfig(o);
    io::MakeDirectories(o.out_dir);
    const std::string out_dir = fs::canonical(o.out_dir).string();
    const std::vector<BenchRun> runs = PlanBenchmark(config, out_dir);
    // Not by --run-one or --score-only: a workflow's jobs run at the same time, after the plan.
    if (o.run_one.empty() && !o.score_only) WriteAndCheckVariantConfigs(config, out_dir);
    if (o.plan_only) return PrintPlan(runs, out_dir);
    if (!o.run_one.empty()) return RunOne(runs, o.run_one, out_dir);
    // Every input of every run before the first: a missing one stops here, named.
    if (!o.score_only) CheckBenchInputs(config);
    const std::vector<JobOutcome> outcomes =
        o.score_only ? OutcomesOnDisk(runs) : RunAll(runs, config, out_dir);
    PrepareOutputFolder(out_dir, OutputKind::kBench);  // the report's files; runs/ stays
    Report(runs, outcomes, config, out_dir, o.no_plot);
}

}  // namespace

void RegisterBenchCommand(CLI::App &app) {
    auto options = std::make_shared<BenchOptions>();
    CLI::App *cmd = app.add_subcommand(
        "bench",
        "Run a benchmark matrix (sequences x odometry methods and mapper priors) in parallel, "
        "score it against the ground truth and write results.md/.csv and the paper's figures. "
        "Finished runs are kept: running it again only redoes what is missing. A parameter grid "
        "(grid: in the YAML) makes every point a variant of each method.");
    cmd->add_option("config", options->config_path, "benchmark YAML")->capture_default_str();
    cmd->add_option("--out", options->out_dir, "output directory")->required();
    cmd->add_option("--data", options->data_dir,
                    "the folder that the sequences' relative data: folders are taken from "
                    "(default: the benchmark file's data_dir:, else its folder); each run gets its "
                    "sequence's data: as --data")
        ->type_name("DIR");
    cmd->add_option("--jobs", options->jobs,
                    "parallel runs (default: the config's, else all cores)");
    cmd->add_flag("--no-plot", options->no_plot, "skip the figures");
    cmd->add_option("--reference", options->reference,
                    "score against the recorded ground truth (ground_truth, the default) or, for "
                    "simulated sequences, the exact trajectory (exact)")
        ->check(OneOf({"ground_truth", "exact"}));
    cmd->add_option("--association", options->association,
                    "interpolate: ground truth interpolated at each estimated stamp (default); "
                    "nearest: evo's nearest stamp within --t_max_diff")
        ->check(OneOf({"interpolate", "nearest"}));
    cmd->add_option("--t_max_diff", options->t_max_diff_s,
                    "nearest: largest stamp difference [s] (default: the config's, else 0.01)")
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--plan-only", options->plan_only,
                  "print the runs as JSON (for workflow/Snakefile) and write the grid variants' "
                  "config files; run nothing");
    cmd->add_option("--run-one", options->run_one,
                    "run only the run named SEQUENCE/METHOD (its dependencies must be done)");
    cmd->add_flag("--score-only", options->score_only,
                  "run nothing: score the runs found finished in --out and write the report");
    cmd->callback([options] { RunBench(*options); });
}

}  // namespace dorado::apps
