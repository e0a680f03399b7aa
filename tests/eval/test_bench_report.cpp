// Scoring and reporting of benchmark runs on hand-made run directories (no other dorado command
// needed): same stamps for every method of a sequence, numbers against the closed form, failed
// runs reported, and the plot script producing every figure from the written CSVs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench_report.hpp"
#include "dorado/core/angles.hpp"
#include "dorado/io/trajectory_io.hpp"

namespace dorado::apps {
namespace {

namespace fs = std::filesystem;

constexpr double kVq = 1.3, kV = 1.5,
                 kW = 0.4;  // reference line speed; estimate arc speed, yaw rate

Eigen::Isometry3d Arc(double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(kW * t, Eigen::Vector3d::UnitZ()).matrix();
    T.translation() =
        Eigen::Vector3d(kV / kW * std::sin(kW * t), kV / kW * (1 - std::cos(kW * t)), 0);
    return T;
}

double ClosedFormTranslation(double dt) {
    return std::hypot(kV / kW * std::sin(kW * dt) - kVq * dt, kV / kW * (1 - std::cos(kW * dt)));
}

class BenchReport : public ::testing::Test {
  protected:
    void SetUp() override {
        out_ = fs::temp_directory_path() / ("dorado_bench_report_" + std::to_string(getpid()));
        fs::remove_all(out_);
        fs::create_directories(out_ / "data" / "s1");
        Trajectory gt;
        for (int k = 0; k <= 500; ++k) {
            Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
            T.translation() = Eigen::Vector3d(kVq * 0.02 * k, 0, 0);
            gt.Append(k * 20'000'000LL, T);
        }
        io::WriteTum((out_ / "data" / "s1" / "ground_truth.tum").string(), gt);
    }
    void TearDown() override { fs::remove_all(out_); }

    BenchRun Run(RunKind kind, const std::string &method) const {
        BenchRun run;
        run.kind = kind;
        run.sequence = "s1";
        run.method = method;
        run.ground_truth = (out_ / "data" / "s1" / "ground_truth.tum").string();
        run.job.out_dir = (out_ / "runs" / "s1" / method).string();
        return run;
    }
    // An arc trajectory at 10 Hz from 0.05 s to 9.95 s, without the stamp `skip` (-1: none).
    void WriteArcRun(const BenchRun &run, int skip, const std::string &csv_name,
                     const std::string &csv_text) const {
        fs::create_directories(run.job.out_dir);
        Trajectory est;
        for (int k = 0; k < 100; ++k) {
            if (k != skip) est.Append(50'000'000LL + k * 100'000'000LL, Arc(0.05 + 0.1 * k));
        }
        io::WriteTum((fs::path(run.job.out_dir) / "trajectory.tum").string(), est);
        std::ofstream(fs::path(run.job.out_dir) / csv_name) << csv_text;
    }

    fs::path out_;
};

TEST_F(BenchReport, MethodsAreScoredOnCommonStampsAgainstClosedForm) {
    std::vector<BenchRun> runs{Run(RunKind::kOdometry, "odom_doppler"),
                               Run(RunKind::kMap, "map_doppler"), Run(RunKind::kMap, "map_none")};
    std::ostringstream velocities;
    velocities
        << "t,omega_base_x,omega_base_y,omega_base_z,gyro_base_x,gyro_base_y,gyro_base_z,time_ms\n";
    for (int k = 0; k < 100; ++k) {
        velocities << 0.05 + 0.1 * k << ",0,0," << kW << ",0.001,0," << kW + 0.01 << ",2.0\n";
    }
    WriteArcRun(runs[0], -1, "velocities.csv", velocities.str());
    std::ostringstream scans;
    scans << "t,time_doppler_ms,time_register_ms,time_total_ms\n";
    for (int k = 0; k < 99; ++k) scans << 0.05 + 0.1 * k << ",1.0,5.0,6.0\n";
    WriteArcRun(runs[1], 5, "scans.csv", scans.str());  // the mapper lost one scan
    std::vector<JobOutcome> outcomes(3);
    outcomes[0].status = JobStatus::kSucceeded;
    outcomes[1].status = JobStatus::kAlreadyDone;
    outcomes[2].status = JobStatus::kFailed;
    outcomes[2].message = "exit code 1";

    BenchConfig config;
    const auto evaluations = EvaluateRuns(runs, outcomes, config);
    ASSERT_EQ(evaluations.size(), 3u);
    for (int r = 0; r < 2; ++r) {
        const RunEvaluation &e = evaluations[static_cast<std::size_t>(r)];
        ASSERT_TRUE(e.ok) << e.note;
        EXPECT_EQ(e.scored, 99u);  // both without the stamp the mapper lost
        ASSERT_EQ(e.rpe_frame.translation_m.size(), 98u);
        for (std::size_t p = 0; p < 98; ++p) {
            const double dt = (e.rpe_frame.stamp_j_ns[p] - e.rpe_frame.stamp_i_ns[p]) * 1e-9;
            EXPECT_NEAR(e.rpe_frame.translation_m[p], ClosedFormTranslation(dt), 1e-6);
            EXPECT_NEAR(e.rpe_frame.rotation_deg[p], RadToDeg(kW * dt), 1e-5);
            // A turn in the plane against a straight line: all of the error is yaw.
            EXPECT_NEAR(e.rpe_frame.yaw_deg[p], e.rpe_frame.rotation_deg[p], 1e-9);
            EXPECT_LT(e.rpe_frame.roll_deg[p] + e.rpe_frame.pitch_deg[p], 1e-9);
        }
        // Per second: pairs 1 s apart within the 10 % tolerance (the last one, at the end of the
        // data, is 0.9 s), each scored on its own duration.
        for (std::size_t p = 0; p < e.rpe_second.pairs.size(); ++p) {
            const double dt = (e.rpe_second.stamp_j_ns[p] - e.rpe_second.stamp_i_ns[p]) * 1e-9;
            EXPECT_NEAR(dt, 1.0, 0.1 + 1e-9);
            EXPECT_NEAR(e.rpe_second.translation_m[p], ClosedFormTranslation(dt), 1e-6);
        }
        EXPECT_GE(e.rpe_second.pairs.size(), 8u);
    }
    EXPECT_EQ(evaluations[0].rpe_second.stamp_i_ns, evaluations[1].rpe_second.stamp_i_ns);
    EXPECT_FALSE(evaluations[2].ok);

    WriteReport(evaluations, config, out_.string());
    std::ifstream csv(out_ / "results.csv");
    std::string line, frame_row;
    while (std::getline(csv, line)) {
        if (line.rfind("s1,odom_doppler,rpe_frame_translation,", 0) == 0) frame_row = line;
    }
    ASSERT_FALSE(frame_row.empty());
    double mean_expected = 0;
    for (std::size_t p = 0; p < 98; ++p)
        mean_expected += evaluations[0].rpe_frame.translation_m[p] / 98;
    std::stringstream ss(frame_row);
    std::vector<std::string> cells;
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    ASSERT_EQ(cells.size(), 11u);
    EXPECT_NEAR(std::stod(cells[5]), mean_expected, 1e-8);  // mean
    EXPECT_EQ(cells[10], "98");                             // count
    std::ifstream md(out_ / "results.md");
    const std::string report((std::istreambuf_iterator<char>(md)),
                             std::istreambuf_iterator<char>());
    EXPECT_NE(report.find("map_none: run failed: exit code 1"), std::string::npos) << report;
    EXPECT_NE(report.find("| method | RPE/frame roll | pitch | yaw [deg] |"), std::string::npos);

    // The figures, from the CSVs just written.
    const std::string plot = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                             "/scripts/plot_benchmark.py " + out_.string();
    ASSERT_EQ(std::system(plot.c_str()), 0);
    for (const char *name : {"fig4_angular_velocity", "fig5_rpe_per_frame", "fig6_rpe_per_second",
                             "fig7_trajectories", "runtime_per_stage"}) {
        EXPECT_TRUE(fs::exists(out_ / "plots" / (std::string(name) + ".png"))) << name;
        EXPECT_TRUE(fs::exists(out_ / "plots" / (std::string(name) + ".pdf"))) << name;
    }
}

TEST_F(BenchReport, CsvCellsWithCommasAndQuotesAreQuoted) {
    // A grid variant of two keys has a comma in its name; a failed run's note may hold both.
    const std::string method = "map_doppler[a=1,b=2]";
    std::vector<BenchRun> runs{Run(RunKind::kOdometry, method), Run(RunKind::kMap, "map_none")};
    WriteArcRun(runs[0], -1, "velocities.csv", "t,time_ms\n0.05,1\n");
    std::vector<JobOutcome> outcomes(2);
    outcomes[0].status = JobStatus::kSucceeded;
    outcomes[1].status = JobStatus::kFailed;
    outcomes[1].message = "key \"x\", then y";
    BenchConfig config;
    WriteReport(EvaluateRuns(runs, outcomes, config), config, out_.string());
    // Python's csv module (RFC 4180) is the independent reader: every row has the header's cells
    // and the names and the note come back whole.
    const std::string check =
        std::string(DORADO_SYSTEM_PYTHON) +
        " -c '\n"
        "import csv, sys\n"
        "d = sys.argv[1]\n"
        "for name, cells in ((\"results.csv\", 11), (\"bench_runs.csv\", 9), (\"rpe_pairs.csv\", "
        "10)):\n"
        "    rows = list(csv.reader(open(d + \"/\" + name, newline=\"\")))\n"
        "    assert len(rows) > 1 and all(len(r) == cells for r in rows), (name, rows[:3])\n"
        "    assert any(r[1] == \"map_doppler[a=1,b=2]\" for r in rows), name\n"
        "runs = list(csv.DictReader(open(d + \"/bench_runs.csv\", newline=\"\")))\n"
        "assert any(\"key \\\"x\\\", then y\" in r[\"note\"] for r in runs), runs\n"
        "' " +
        out_.string();
    EXPECT_EQ(std::system(check.c_str()), 0);
}

TEST_F(BenchReport, ExactReferenceMissingFromOlderSimulationIsNamed) {
    BenchRun run = Run(RunKind::kOdometry, "odom_doppler");
    run.ground_truth = (out_ / "data" / "s1" / "true_trajectory.tum").string();
    WriteArcRun(run, -1, "velocities.csv", "t,time_ms\n0.05,1\n");
    std::vector<JobOutcome> outcomes(1);
    outcomes[0].status = JobStatus::kAlreadyDone;
    BenchConfig config;
    config.reference = BenchReference::kExact;
    const auto evaluations = EvaluateRuns({run}, outcomes, config);
    ASSERT_EQ(evaluations.size(), 1u);
    EXPECT_FALSE(evaluations[0].ok);
    EXPECT_NE(evaluations[0].note.find("true_trajectory.tum: missing; delete " +
                                       (out_ / "data" / "s1").string()),
              std::string::npos)
        << evaluations[0].note;
}

}  // namespace
}  // namespace dorado::apps
