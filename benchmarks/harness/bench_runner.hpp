#pragma once
/// @file bench_runner.hpp
/// Runs a graph of independent command-line jobs on a pool of worker processes, so that a long
/// benchmark can be interrupted and resumed:
/// - a job writes into `out_dir + ".tmp"` and is renamed to `out_dir` only after it exited 0 and
///   its marker file (e.g. summary.json, written last and atomically by every dorado command)
///   exists: an interrupted or failed job never leaves a directory that looks finished;
/// - a job whose `out_dir/marker` exists is finished and not run again, if it ran with the same
///   arguments (and the same contents of the .yaml files they name: `out_dir/bench_job.txt`)
///   and its dependencies were not run again; otherwise it runs again (an earlier run of
///   other settings in a re-used folder is not taken for this one);
/// - a job starts only after all its dependencies succeeded; it fails if one of them failed.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace dorado::apps {

struct BenchJob {
    std::string name;     ///< shown in the progress display and logs, e.g. "seq04/map_doppler"
    std::string out_dir;  ///< final directory of the job's results
    std::string marker;   ///< file in out_dir whose presence means the job finished
    /// Arguments after the program; the token "{out}" is replaced by the temporary directory.
    std::vector<std::string> args;
    std::vector<std::size_t> depends_on;  ///< indices of jobs that must succeed first
};

enum class JobStatus {
    kPending,
    kAlreadyDone,  ///< finished by an earlier invocation
    kSucceeded,
    kFailed,
};

struct JobOutcome {
    JobStatus status = JobStatus::kPending;
    double seconds = 0.0;
    std::string message;  ///< why it failed
};

struct RunnerOptions {
    std::string program;  ///< executable run for every job (the dorado binary itself)
    std::size_t workers = 1;
    std::string log_dir;  ///< each job's stdout+stderr go to log_dir/<name with '/' as '_'>.log
    /// Called after every change (start or end of a job) and about every 0.2 s.
    std::function<void(std::size_t finished, std::size_t total, const std::string &running)>
        on_progress;
    /// Called when a job ends (or is found already done), with its index and outcome.
    std::function<void(std::size_t job, const JobOutcome &outcome)> on_job_end;
    /// Called before the run, for each job whose finished output is of other settings (it runs
    /// again).
    std::function<void(std::size_t job)> on_stale;
    /// Asked between jobs: true (Ctrl-C) starts no further job; the running ones are waited for
    /// and the others end as failed, "not run (interrupted)".
    std::function<bool()> stop_requested;
};

/// Runs the jobs; returns one outcome per job, in job order. Throws std::invalid_argument for a
/// dependency that is out of range or not earlier in the list (which also rules out cycles).
[[nodiscard]] std::vector<JobOutcome> RunJobs(const std::vector<BenchJob> &jobs,
                                              const RunnerOptions &options);

/// Path of the running executable (/proc/self/exe).
[[nodiscard]] std::string SelfExecutablePath();

}  // namespace dorado::apps
