// The benchmark matrix from its YAML: jobs, their commands and dependencies, and config errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "bench_plan.hpp"

namespace dorado::apps {
namespace {

const char *kConfig = R"(
jobs: 2
sequences:
  - name: s1
    simulate: {sequence: seq04, duration_s: 30, seed: 4}
  - name: real
    dataset: data/real.yaml
    ground_truth: data/real_gt.tum
odometry: [imu, doppler, imu+doppler]
map_priors: [none, doppler]
map_config: mapper.yaml
)";

TEST(BenchPlan, MatrixHasOneRunPerSequenceAndMethodAfterItsSimulation) {
    const BenchConfig config = ParseBenchConfig(kConfig, "/cfg", "test.yaml");
    EXPECT_EQ(config.jobs, 2u);
    EXPECT_EQ(config.map_priors, (std::vector<mapping::PriorKind>{mapping::PriorKind::kNone,
                                                                  mapping::PriorKind::kDoppler}));
    EXPECT_EQ(config.association, eval::AssociationMethod::kInterpolate);
    const auto runs = PlanBenchmark(config, "/out");
    // s1: simulate + 3 odometry + 2 map; real: 3 + 2.
    ASSERT_EQ(runs.size(), 11u);
    EXPECT_EQ(runs[0].kind, RunKind::kSimulate);
    EXPECT_EQ(runs[0].job.out_dir, "/out/data/s1");
    EXPECT_EQ(runs[0].job.marker, "simulation.json");
    const std::vector<std::string> sim_args{
        "simulate", "--sequence", "seq04", "--out", "{out}", "--seed", "4", "--duration", "30"};
    EXPECT_EQ(runs[0].job.args, sim_args);
    for (std::size_t r = 1; r <= 5; ++r) {
        EXPECT_EQ(runs[r].job.depends_on, std::vector<std::size_t>{0}) << runs[r].job.name;
        EXPECT_EQ(runs[r].dataset, "/out/data/s1/dataset.yaml");
        EXPECT_EQ(runs[r].ground_truth, "/out/data/s1/ground_truth.tum");
        EXPECT_EQ(runs[r].job.marker, "summary.json");
    }
    // The paper's "IMU" odometry is gyro-only rotation, "IMU + Doppler" is --method imu+doppler:
    // the same spelling as the command line's.
    EXPECT_EQ(runs[1].method, "odom_imu");
    EXPECT_EQ(runs[1].job.args.back(), "imu");
    EXPECT_EQ(runs[3].method, "odom_imu+doppler");
    EXPECT_EQ(runs[3].job.args.back(), "imu+doppler");
    const std::vector<std::string> map_args{
        "map",   "/out/data/s1/dataset.yaml", "--prior",  "doppler",         "--out",
        "{out}", "--accept-implausible",      "--config", "/cfg/mapper.yaml"};
    EXPECT_EQ(runs[5].job.args, map_args);
    EXPECT_EQ(runs[5].job.out_dir, "/out/runs/s1/map_doppler");
    // Existing data: paths relative to the config file, no dependency.
    EXPECT_EQ(runs[6].dataset, "/cfg/data/real.yaml");
    EXPECT_EQ(runs[6].ground_truth, "/cfg/data/real_gt.tum");
    EXPECT_TRUE(runs[6].job.depends_on.empty());
}

TEST(BenchPlan, ASequenceMayNameItsOwnMethods) {
    // A recording without an IMU: its own lists replace the benchmark's, the others keep them.
    const BenchConfig config = ParseBenchConfig(R"(
sequences:
  - {name: with_imu, dataset: a.yaml, ground_truth: a.tum}
  - {name: no_imu, dataset: b.yaml, ground_truth: b.tum, odometry: [doppler],
     map_priors: [constvel, doppler]}
odometry: [imu, doppler]
map_priors: [imu, doppler]
)",
                                                "/cfg", "test.yaml");
    std::vector<std::string> methods;
    for (const BenchRun &run : PlanBenchmark(config, "/out"))
        methods.push_back(run.sequence + "/" + run.method);
    EXPECT_EQ(methods, (std::vector<std::string>{"with_imu/odom_imu", "with_imu/odom_doppler",
                                                 "with_imu/map_imu", "with_imu/map_doppler",
                                                 "no_imu/odom_doppler", "no_imu/map_constvel",
                                                 "no_imu/map_doppler"}));
    try {
        (void)ParseBenchConfig(
            "sequences:\n  - {name: x, dataset: a.yaml, ground_truth: a.tum, map_priors: [gps]}\n",
            "/cfg", "test.yaml");
        ADD_FAILURE() << "an unknown prior was accepted";
    } catch (const std::runtime_error &e) {
        EXPECT_NE(std::string(e.what()).find("sequences[0]"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("gps"), std::string::npos) << e.what();
    }
}

TEST(BenchPlan, EachRunGetsItsSequencesDataFolder) {
    // data: relative to data_dir: (relative to the file), or to the --data argument; absolute as
    // written; each run of the sequence gets it as --data.
    const std::string yaml = R"(
data_dir: ../recordings
sequences:
  - {name: a, dataset: a.yaml, data: drive_a, ground_truth: a.tum}
  - {name: b, dataset: b.yaml, data: /abs/drive_b, ground_truth: b.tum}
  - {name: c, dataset: c.yaml, ground_truth: c.tum}
odometry: [doppler]
map_priors: [none]
)";
    BenchConfig config = ParseBenchConfig(yaml, "/cfg", "test.yaml");
    EXPECT_EQ(config.sequences[0].data, "/recordings/drive_a");
    EXPECT_EQ(config.sequences[1].data, "/abs/drive_b");
    EXPECT_EQ(config.sequences[2].data, "");
    const auto runs = PlanBenchmark(config, "/out");
    ASSERT_EQ(runs.size(), 6u);
    const std::vector<std::string> odometry{"odometry",
                                            "/cfg/a.yaml",
                                            "--out",
                                            "{out}",
                                            "--accept-implausible",
                                            "--method",
                                            "doppler",
                                            "--data",
                                            "/recordings/drive_a"};
    EXPECT_EQ(runs[0].job.args, odometry);
    EXPECT_EQ(runs[1].job.args.back(), "/recordings/drive_a");  // map_none
    EXPECT_EQ(runs[3].job.args.back(), "/abs/drive_b");
    EXPECT_EQ(std::count(runs[4].job.args.begin(), runs[4].job.args.end(), "--data"), 0);
    config = ParseBenchConfig(yaml, "/cfg", "test.yaml", "/mnt/disk");
    EXPECT_EQ(config.sequences[0].data, "/mnt/disk/drive_a");
    EXPECT_EQ(config.sequences[1].data, "/abs/drive_b");
}

TEST(BenchPlan, ErrorsNameTheKey) {
    const auto error_of = [](const std::string &yaml) {
        try {
            (void)ParseBenchConfig(yaml, "/cfg", "bad.yaml");
        } catch (const std::runtime_error &e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(error_of("jobs: 1").find("bad.yaml: key 'sequences'"), std::string::npos);
    EXPECT_NE(error_of("sequences: [{name: a, simulate: {}}]\nmap_priors: [lidar]")
                  .find("key 'map_priors': unknown method 'lidar'"),
              std::string::npos);
    EXPECT_NE(error_of("sequences: [{name: a}]").find("sequences[0].dataset"), std::string::npos);
    EXPECT_NE(error_of("sequences: [{name: a, simulate: {duration_s: -3}}]")
                  .find("sequences[0].simulate.duration_s"),
              std::string::npos);
    EXPECT_NE(error_of("sequences: [{name: a, simulate: {}}, {name: a, simulate: {}}]")
                  .find("sequences[1].name': repeats"),
              std::string::npos);
    EXPECT_NE(error_of("sequences: [{name: a, simulate: {}}]\njobs: many").find("jobs"),
              std::string::npos);
    // Misspelled keys are errors, not silent defaults.
    const std::string seed = error_of("sequences: [{name: a, simulate: {seedd: 3}}]");
    EXPECT_NE(seed.find("sequences[0].simulate.seedd"), std::string::npos) << seed;
    EXPECT_NE(seed.find("did you mean 'seed'"), std::string::npos) << seed;
    const std::string priors = error_of("sequences: [{name: a, simulate: {}}]\nmap_prior: [none]");
    EXPECT_NE(priors.find("did you mean 'map_priors'"), std::string::npos) << priors;
    EXPECT_NE(error_of("sequences: [{name: a, groundtruth: g.tum, dataset: d.yaml}]")
                  .find("sequences[0].groundtruth"),
              std::string::npos);
    EXPECT_NE(error_of("sequences: [{name: a, simulate: {}}]\nreference: lidar")
                  .find("key 'reference': must be ground_truth or exact, got 'lidar'"),
              std::string::npos);
}

TEST(BenchPlan, GridPointsAreNamedVariantsWithTheirOwnConfig) {
    const BenchConfig config = ParseBenchConfig(R"(
sequences: [{name: s1, simulate: {}}]
odometry: [imu]
map_priors: [doppler]
association: nearest
t_max_diff_s: 0.02
grid:
  map: {mapper.max_iterations: [5, 10], mapper.scan_voxel_m: [0.5, 1.0, 2]}
)",
                                                "/cfg", "test.yaml");
    EXPECT_EQ(config.association, eval::AssociationMethod::kNearest);
    EXPECT_DOUBLE_EQ(config.t_max_diff_s, 0.02);
    const auto runs = PlanBenchmark(config, "/out");
    ASSERT_EQ(runs.size(), 1u + 1u + 6u);  // simulate, odom_imu, 2 x 3 map variants
    EXPECT_EQ(runs[1].method, "odom_imu");
    EXPECT_FALSE(runs[1].has_translation);
    EXPECT_EQ(runs[2].method, "map_doppler@max_iterations=5,scan_voxel_m=0.5");
    EXPECT_EQ(runs[7].method, "map_doppler@max_iterations=10,scan_voxel_m=2");
    EXPECT_EQ(runs[7].job.out_dir, "/out/runs/s1/map_doppler@max_iterations=10,scan_voxel_m=2");
    EXPECT_EQ(runs[7].job.args.back(), "/out/configs/map@max_iterations=10,scan_voxel_m=2.yaml");
    const auto error_of = [](const std::string &yaml) {
        try {
            (void)ParseBenchConfig("sequences: [{name: a, simulate: {}}]\n" + yaml, "/", "g.yaml");
        } catch (const std::runtime_error &e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(
        error_of("grid: {map: {mapper.max_iterations: []}}").find("grid.map.mapper.max_iterations"),
        std::string::npos);
    EXPECT_NE(error_of("grid: {mapp: {}}").find("did you mean 'map'"), std::string::npos);
    EXPECT_NE(error_of("grid: {map: {a.b: [x/y]}}").find("names a directory"), std::string::npos);
    // A key the settings file would not read fails at plan time, not in every run.
    EXPECT_NE(error_of("grid: {map: {mapper.max_iteration: [5]}}").find("not a map settings key"),
              std::string::npos);
    EXPECT_NE(error_of("association: closest").find("must be interpolate or nearest"),
              std::string::npos);
}

TEST(BenchGrid, CartesianProductFirstAxisSlowest) {
    const auto variants = GridVariants({{"a.x", {"1", "2"}}, {"b", {"p", "q", "r"}}});
    ASSERT_EQ(variants.size(), 6u);
    EXPECT_EQ(variants[0].name, "x=1,b=p");
    EXPECT_EQ(variants[2].name, "x=1,b=r");
    EXPECT_EQ(variants[3].name, "x=2,b=p");
    ASSERT_EQ(variants[5].settings.size(), 2u);
    EXPECT_EQ(variants[5].settings[0], (std::pair<std::string, std::string>{"a.x", "2"}));
    EXPECT_EQ(GridVariants({}).size(), 1u);
    EXPECT_TRUE(GridVariants({}).front().name.empty());
}

TEST(BenchPlan, ExactReferenceScoresSimulatedSequencesAgainstTheTrueTrajectory) {
    BenchConfig config =
        ParseBenchConfig("reference: exact\nsequences: [{name: s1, simulate: {sequence: seq04}}]\n",
                         "/cfg", "test.yaml");
    ASSERT_EQ(config.reference, BenchReference::kExact);
    for (const BenchRun &run : PlanBenchmark(config, "/out"))
        EXPECT_EQ(run.ground_truth, "/out/data/s1/true_trajectory.tum") << run.method;
    // Recorded data has no exact trajectory: the plan says which sequence.
    config = ParseBenchConfig(kConfig, "/cfg", "test.yaml");
    config.reference = BenchReference::kExact;
    try {
        (void)PlanBenchmark(config, "/out");
        FAIL() << "no error";
    } catch (const std::runtime_error &e) {
        EXPECT_NE(std::string(e.what()).find("sequence 'real'"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace dorado::apps
