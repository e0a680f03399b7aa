#include "bench_runner.hpp"

#include <fcntl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "dorado/core/time.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

std::string TempDir(const BenchJob &job) {
    return job.out_dir + ".tmp";
}

std::string LogPath(const RunnerOptions &options, const BenchJob &job) {
    std::string file = job.name;
    for (char &c : file) {
        if (c == '/') c = '_';
    }
    return (fs::path(options.log_dir) / (file + ".log")).string();
}

constexpr const char *kJobRecord = "bench_job.txt";

/// What a job ran with: its arguments, and the text of each .yaml file they name (the variant
/// configs and dataset descriptions, which a re-used folder may hold with other values).
std::string JobRecord(const BenchJob &job) {
    std::string record;
    for (const std::string &arg : job.args) {
        record += arg + "\n";
        std::error_code ec;
        if (arg.size() > 5 && arg.compare(arg.size() - 5, 5, ".yaml") == 0 &&
            fs::is_regular_file(arg, ec)) {
            std::ifstream in(arg);
            record += std::string(std::istreambuf_iterator<char>(in), {}) + "\n";
        }
    }
    return record;
}

bool HasMarker(const BenchJob &job) {
    return fs::exists(fs::path(job.out_dir) / job.marker);
}

/// Finished with these arguments (JobRecord).
bool IsDone(const BenchJob &job) {
    if (!HasMarker(job)) return false;
    std::ifstream in(fs::path(job.out_dir) / kJobRecord);
    return in && std::string(std::istreambuf_iterator<char>(in), {}) == JobRecord(job);
}

// Starts `program args` with "{out}" replaced, output to log_path; returns the child's pid.
pid_t Spawn(const std::string &program, const BenchJob &job, const std::string &log_path) {
    std::vector<std::string> args{program};
    for (const std::string &arg : job.args) args.push_back(arg == "{out}" ? TempDir(job) : arg);
    std::vector<char *> argv;
    for (std::string &arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);

    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("cannot start a process for " + job.name);
    if (pid == 0) {
        const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, STDOUT_FILENO);
            dup2(fd, STDERR_FILENO);
            close(fd);
        }
        // One core per job: the pool, not the job, spreads the work over the machine.
        setenv("OMP_NUM_THREADS", "1", 1);
        execv(program.c_str(), argv.data());
        _exit(127);
    }
    return pid;
}

// Prepares the temporary directory: anything left by an interrupted run is removed first.
void PrepareTempDir(const BenchJob &job) {
    fs::remove_all(TempDir(job));
    fs::create_directories(TempDir(job));
}

// After a zero exit: checks the marker and publishes the directory by one rename.
std::string Publish(const BenchJob &job) {
    if (!fs::exists(fs::path(TempDir(job)) / job.marker)) {
        return "exited 0 but wrote no " + job.marker;
    }
    std::ofstream(fs::path(TempDir(job)) / kJobRecord) << JobRecord(job);
    std::error_code ec;
    fs::remove_all(job.out_dir, ec);  // an unfinished leftover (no marker)
    fs::rename(TempDir(job), job.out_dir, ec);
    if (ec) return "cannot rename " + TempDir(job) + " to " + job.out_dir + ": " + ec.message();
    return "";
}

std::string ExitMessage(int status, const std::string &log_path) {
    if (WIFEXITED(status)) {
        const int code = WEXITSTATUS(status);
        if (code == 127) return "could not be executed (exit 127), see " + log_path;
        return "exit code " + std::to_string(code) + ", see " + log_path;
    }
    if (WIFSIGNALED(status)) {
        return "killed by signal " + std::to_string(WTERMSIG(status)) + ", see " + log_path;
    }
    return "ended abnormally, see " + log_path;
}

}  // namespace

std::vector<JobOutcome> RunJobs(const std::vector<BenchJob> &jobs, const RunnerOptions &options) {
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        for (const std::size_t d : jobs[i].depends_on) {
            if (d >= i) {
                throw std::invalid_argument("job " + jobs[i].name +
                                            " depends on a job that is not before it");
            }
        }
    }
    if (!options.log_dir.empty()) fs::create_directories(options.log_dir);
    const std::size_t workers = std::max<std::size_t>(1, options.workers);

    std::vector<JobOutcome> outcomes(jobs.size());
    std::size_t finished = 0;
    const auto end_job = [&](std::size_t i, JobStatus status, double seconds, std::string message) {
        outcomes[i] = {status, seconds, std::move(message)};
        ++finished;
        if (options.on_job_end) options.on_job_end(i, outcomes[i]);
    };
    // Done only with its dependencies done before (a dependency run again changes its input).
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        const bool inputs_kept = std::all_of(
            jobs[i].depends_on.begin(), jobs[i].depends_on.end(),
            [&](std::size_t d) { return outcomes[d].status == JobStatus::kAlreadyDone; });
        if (inputs_kept && IsDone(jobs[i]))
            end_job(i, JobStatus::kAlreadyDone, 0.0, "");
        else if (HasMarker(jobs[i]) && options.on_stale)
            options.on_stale(i);
    }

    struct Running {
        std::size_t job;
        Clock::time_point start;
        std::string log_path;
    };
    std::map<pid_t, Running> running;
    const auto report = [&] {
        if (!options.on_progress) return;
        std::string names;
        for (const auto &[pid, r] : running) {
            const double s = std::chrono::duration<double>(Clock::now() - r.start).count();
            names += (names.empty() ? "" : ", ") + jobs[r.job].name + " " +
                     std::to_string(static_cast<int>(s)) + "s";
        }
        options.on_progress(finished, jobs.size(), names);
    };
    const auto is_pending = [&](std::size_t i) {
        return outcomes[i].status == JobStatus::kPending &&
               std::none_of(running.begin(), running.end(),
                            [&](const auto &r) { return r.second.job == i; });
    };

    while (finished < jobs.size()) {
        // Fail jobs whose dependency failed; start ready jobs while workers are free.
        const bool stopping = options.stop_requested && options.stop_requested();
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            if (!is_pending(i)) continue;
            if (stopping) {
                end_job(i, JobStatus::kFailed, 0.0, "not run (interrupted)");
                continue;
            }
            bool ready = true;
            for (const std::size_t d : jobs[i].depends_on) {
                if (outcomes[d].status == JobStatus::kFailed) {
                    end_job(i, JobStatus::kFailed, 0.0, "needs " + jobs[d].name + ", which failed");
                    ready = false;
                    break;
                }
                if (outcomes[d].status == JobStatus::kPending) ready = false;
            }
            if (!ready || running.size() >= workers) continue;
            const std::string log_path = LogPath(options, jobs[i]);
            try {
                PrepareTempDir(jobs[i]);
                running[Spawn(options.program, jobs[i], log_path)] = {i, Clock::now(), log_path};
            } catch (const std::exception &e) {
                end_job(i, JobStatus::kFailed, 0.0, e.what());
            }
        }
        report();
        if (running.empty()) continue;  // only failures were settled this round

        int status = 0;
        const pid_t pid = waitpid(-1, &status, WNOHANG);
        if (pid <= 0) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            continue;
        }
        const auto it = running.find(pid);
        if (it == running.end()) continue;  // not one of ours
        const Running r = it->second;
        running.erase(it);
        const double seconds = std::chrono::duration<double>(Clock::now() - r.start).count();
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
            const std::string error = Publish(jobs[r.job]);
            end_job(r.job, error.empty() ? JobStatus::kSucceeded : JobStatus::kFailed, seconds,
                    error);
        } else {
            end_job(r.job, JobStatus::kFailed, seconds, ExitMessage(status, r.log_path));
        }
        report();
    }
    return outcomes;
}

std::string SelfExecutablePath() {
    std::error_code ec;
    const fs::path path = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw std::runtime_error("cannot find the dorado executable (/proc/self/exe)");
    return path.string();
}

}  // namespace dorado::apps
