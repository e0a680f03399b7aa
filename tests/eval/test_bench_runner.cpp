// The benchmark job pool with real child processes (/bin/sh), without the other dorado commands:
// dependencies, resume, atomic finish, failure propagation and real parallelism.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "bench_runner.hpp"

namespace dorado::apps {
namespace {

namespace fs = std::filesystem;

class BenchRunner : public ::testing::Test {
  protected:
    void SetUp() override {
        root_ = fs::temp_directory_path() /
                ("dorado_bench_runner_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(root_);
        fs::create_directories(root_);
    }
    void TearDown() override { fs::remove_all(root_); }

    // A job running a shell script with $1 = its temporary output directory.
    BenchJob ShellJob(const std::string &name, const std::string &script,
                      std::vector<std::size_t> depends_on = {}) const {
        return {name,
                (root_ / name).string(),
                "summary.json",
                {"-c", script, "sh", "{out}"},
                std::move(depends_on)};
    }
    RunnerOptions Options(std::size_t workers) const {
        RunnerOptions options;
        options.program = "/bin/sh";
        options.workers = workers;
        options.log_dir = (root_ / "logs").string();
        return options;
    }
    int CountLines(const fs::path &path) const {
        std::ifstream in(path);
        int n = 0;
        for (std::string line; std::getline(in, line);) ++n;
        return n;
    }

    fs::path root_;
};

TEST_F(BenchRunner, DependentJobsSeeTheirDependencyFinishedAndPublished) {
    const std::string data = (root_ / "data").string();
    std::vector<BenchJob> jobs;
    jobs.push_back(ShellJob("data", "sleep 0.2; echo 42 > $1/value; echo {} > $1/summary.json"));
    // Each run reads the finished data directory (not data.tmp): it must exist when they start.
    for (const char *name : {"run_a", "run_b", "run_c"}) {
        jobs.push_back(
            ShellJob(name, "cat " + data + "/value > $1/copy && echo {} > $1/summary.json", {0}));
    }
    const auto outcomes = RunJobs(jobs, Options(2));
    for (const auto &o : outcomes) EXPECT_EQ(o.status, JobStatus::kSucceeded) << o.message;
    std::ifstream in(root_ / "run_b" / "copy");
    std::string value;
    in >> value;
    EXPECT_EQ(value, "42");
    EXPECT_FALSE(fs::exists(root_ / "run_b.tmp"));
}

TEST_F(BenchRunner, FinishedJobsAreNotRunAgain) {
    const std::string counter = (root_ / "counter").string();
    std::vector<BenchJob> jobs{
        ShellJob("a", "echo run >> " + counter + "; echo {} > $1/summary.json"),
        ShellJob("b", "echo run >> " + counter + "; echo {} > $1/summary.json", {0})};
    auto outcomes = RunJobs(jobs, Options(2));
    EXPECT_EQ(outcomes[1].status, JobStatus::kSucceeded);
    EXPECT_EQ(CountLines(counter), 2);

    // Remove b's result only: a second invocation redoes b alone.
    fs::remove_all(root_ / "b");
    outcomes = RunJobs(jobs, Options(2));
    EXPECT_EQ(outcomes[0].status, JobStatus::kAlreadyDone);
    EXPECT_EQ(outcomes[1].status, JobStatus::kSucceeded);
    EXPECT_EQ(CountLines(counter), 3);

    outcomes = RunJobs(jobs, Options(2));
    EXPECT_EQ(outcomes[1].status, JobStatus::kAlreadyDone);
    EXPECT_EQ(CountLines(counter), 3);
}

TEST_F(BenchRunner, AFinishedJobOfOtherSettingsRunsAgainAndSoDoItsDependents) {
    const std::string counter = (root_ / "counter").string();
    const fs::path yaml = root_ / "settings.yaml";
    std::ofstream(yaml) << "voxel_size_m: 1.0\n";
    const auto jobs_with = [&](const std::string &a_says) {
        std::vector<BenchJob> jobs{
            ShellJob("a", "echo " + a_says + " >> " + counter + "; echo {} > $1/summary.json"),
            ShellJob("b", "echo b >> " + counter + "; echo {} > $1/summary.json", {0}),
            ShellJob("c", "echo c >> " + counter + "; echo {} > $1/summary.json")};
        jobs[2].args.push_back(yaml.string());  // c names a settings file
        return jobs;
    };
    std::vector<std::size_t> stale;
    RunnerOptions options = Options(1);
    options.on_stale = [&](std::size_t job) { stale.push_back(job); };
    auto outcomes = RunJobs(jobs_with("one"), options);
    EXPECT_EQ(CountLines(counter), 3);
    EXPECT_TRUE(stale.empty());

    // a's arguments change: a runs again, b (which reads a's output) too; c is kept.
    outcomes = RunJobs(jobs_with("two"), options);
    EXPECT_EQ(outcomes[0].status, JobStatus::kSucceeded);
    EXPECT_EQ(outcomes[1].status, JobStatus::kSucceeded);
    EXPECT_EQ(outcomes[2].status, JobStatus::kAlreadyDone);
    EXPECT_EQ(stale, (std::vector<std::size_t>{0, 1}));
    EXPECT_EQ(CountLines(counter), 5);

    // The settings file c names changes its value: c runs again.
    std::ofstream(yaml) << "voxel_size_m: 0.5\n";
    stale.clear();
    outcomes = RunJobs(jobs_with("two"), options);
    EXPECT_EQ(outcomes[0].status, JobStatus::kAlreadyDone);
    EXPECT_EQ(outcomes[2].status, JobStatus::kSucceeded);
    EXPECT_EQ(stale, (std::vector<std::size_t>{2}));
    EXPECT_EQ(CountLines(counter), 6);
}

TEST_F(BenchRunner, FailedJobLeavesNoResultAndFailsItsDependents) {
    std::vector<BenchJob> jobs{
        // Writes a partial trajectory, then dies: nothing may appear under "broken".
        ShellJob("broken", "echo '0 0 0' > $1/trajectory.tum; exit 3"),
        ShellJob("after", "echo {} > $1/summary.json", {0}),
        // Exits 0 but never writes its marker: not finished either.
        ShellJob("no_marker", "echo half > $1/trajectory.tum"),
        ShellJob("fine", "echo {} > $1/summary.json")};
    const auto outcomes = RunJobs(jobs, Options(2));
    EXPECT_EQ(outcomes[0].status, JobStatus::kFailed);
    EXPECT_NE(outcomes[0].message.find("exit code 3"), std::string::npos) << outcomes[0].message;
    EXPECT_EQ(outcomes[1].status, JobStatus::kFailed);
    EXPECT_NE(outcomes[1].message.find("broken"), std::string::npos);
    EXPECT_EQ(outcomes[2].status, JobStatus::kFailed);
    EXPECT_EQ(outcomes[3].status, JobStatus::kSucceeded);
    EXPECT_FALSE(fs::exists(root_ / "broken"));
    EXPECT_FALSE(fs::exists(root_ / "after"));
    EXPECT_FALSE(fs::exists(root_ / "no_marker"));
    EXPECT_TRUE(fs::exists(root_ / "fine" / "summary.json"));
}

TEST_F(BenchRunner, LeftoversOfAnInterruptedRunAreDiscarded) {
    // An earlier bench was killed mid-run: a temporary directory with a partial file remains, and
    // a final directory without its marker (as if copied by hand).
    fs::create_directories(root_ / "a.tmp");
    std::ofstream(root_ / "a.tmp" / "stale.tum") << "partial";
    fs::create_directories(root_ / "b");
    std::ofstream(root_ / "b" / "stale.tum") << "partial";
    std::vector<BenchJob> jobs{ShellJob("a", "echo {} > $1/summary.json"),
                               ShellJob("b", "echo {} > $1/summary.json")};
    const auto outcomes = RunJobs(jobs, Options(1));
    EXPECT_EQ(outcomes[0].status, JobStatus::kSucceeded);
    EXPECT_EQ(outcomes[1].status, JobStatus::kSucceeded);
    EXPECT_FALSE(fs::exists(root_ / "a" / "stale.tum"));
    EXPECT_FALSE(fs::exists(root_ / "b" / "stale.tum"));
    EXPECT_TRUE(fs::exists(root_ / "b" / "summary.json"));
}

TEST_F(BenchRunner, WorkersRunJobsConcurrently) {
    // Each job announces itself and waits (at most 2 s) for the other: both succeed only if the
    // pool runs them at the same time; with one worker they must time out.
    const auto job = [&](const std::string &me, const std::string &other) {
        const std::string mine = (root_ / (me + ".started")).string();
        const std::string theirs = (root_ / (other + ".started")).string();
        return ShellJob(me, "touch " + mine + "; i=0; while [ ! -e " + theirs +
                                " ] && [ $i -lt 20 ]; do sleep 0.1; i=$((i+1)); done; "
                                "[ -e " +
                                theirs + " ] && echo {} > $1/summary.json");
    };
    std::vector<BenchJob> jobs{job("x", "y"), job("y", "x")};
    auto outcomes = RunJobs(jobs, Options(2));
    EXPECT_EQ(outcomes[0].status, JobStatus::kSucceeded);
    EXPECT_EQ(outcomes[1].status, JobStatus::kSucceeded);

    for (const char *f : {"x", "y", "x.started", "y.started"}) fs::remove_all(root_ / f);
    outcomes = RunJobs(jobs, Options(1));
    EXPECT_EQ(outcomes[0].status, JobStatus::kFailed);
}

TEST_F(BenchRunner, ProgressReportsRunningJobsAndCounts) {
    std::vector<BenchJob> jobs{ShellJob("p", "sleep 0.5; echo {} > $1/summary.json")};
    RunnerOptions options = Options(1);
    bool saw_running = false;
    std::size_t last_finished = 0;
    options.on_progress = [&](std::size_t finished, std::size_t total, const std::string &running) {
        EXPECT_EQ(total, 1u);
        if (running.find("p ") != std::string::npos) saw_running = true;
        last_finished = finished;
    };
    (void)RunJobs(jobs, options);
    EXPECT_TRUE(saw_running);
    EXPECT_EQ(last_finished, 1u);
}

TEST_F(BenchRunner, DependencyOnALaterJobIsRejected) {
    std::vector<BenchJob> jobs{ShellJob("a", "true", {1}), ShellJob("b", "true")};
    EXPECT_THROW((void)RunJobs(jobs, Options(1)), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::apps
