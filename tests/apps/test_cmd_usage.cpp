// A first hour without surprises: every command-line error exits 1 with one line that names the
// closest valid option or command; an --out folder that holds an earlier run is emptied of the
// files dorado writes there (and only those) before a run writes its own.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dorado/testing/run_command.hpp"
#include "output_folder.hpp"

namespace {

namespace fs = std::filesystem;

class CmdUsage : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_cmd_usage_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    using Result = dorado::testing::CommandResult;
    static Result Dorado(const std::string &args) {
        return dorado::testing::RunCommand(std::string(DORADO_BINARY) + " " + args, dir_);
    }
    static bool Has(const std::string &text, const std::string &part) {
        return text.find(part) != std::string::npos;
    }
    static void Touch(const fs::path &path) {
        fs::create_directories(path.parent_path());
        std::ofstream(path) << "earlier\n";
    }

    static fs::path dir_;
};

fs::path CmdUsage::dir_;

TEST_F(CmdUsage, AnUnknownOptionExitsOneNamingTheClosestOption) {
    const Result r = Dorado("map x.yaml --fixed-mount");
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_TRUE(Has(r.err, "unknown option '--fixed-mount' (did you mean '--fixed-mounts'?)"))
        << r.err;
    EXPECT_TRUE(Has(r.err, "`dorado map --help`")) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line:\n" << r.err;

    const Result value = Dorado("odometry x.yaml --out o --confg=c.yaml");
    EXPECT_EQ(value.code, 1);
    EXPECT_TRUE(Has(value.err, "(did you mean '--config'?)")) << value.err;
}

TEST_F(CmdUsage, AnUnknownCommandExitsOneNamingTheClosestCommand) {
    const Result r = Dorado("mapp x.yaml");
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_TRUE(Has(r.err, "unknown command 'mapp' (did you mean 'map'?)")) << r.err;

    const Result nested = Dorado("config prnt odometry");
    EXPECT_EQ(nested.code, 1) << nested.err;
    EXPECT_TRUE(Has(nested.err, "unknown command 'prnt' (did you mean 'print'?)")) << nested.err;
    EXPECT_TRUE(Has(nested.err, "`dorado config --help`")) << nested.err;
}

TEST_F(CmdUsage, EveryOtherParseErrorExitsOneAndHelpExitsZero) {
    EXPECT_EQ(Dorado("").code, 1);                                  // no command
    EXPECT_EQ(Dorado("odometry x.yaml").code, 1);                   // --out missing
    EXPECT_EQ(Dorado("map x.yaml --out o --prior bogus").code, 1);  // a value not allowed
    const Result far = Dorado("map x.yaml --out o --zzzzzzzz");     // nothing close: no guess
    EXPECT_EQ(far.code, 1);
    EXPECT_TRUE(Has(far.err, "unknown option '--zzzzzzzz';")) << far.err;
    const Result help = Dorado("map --help");
    EXPECT_EQ(help.code, 0);
    EXPECT_TRUE(Has(help.out, "--fixed-mounts")) << help.out;
    EXPECT_EQ(Dorado("--version").code, 0);
}

TEST_F(CmdUsage, AReusedOutFolderKeepsNoEarlierRunsFileAndEveryUserFile) {
    const fs::path sim = dir_ / "sim", out = dir_ / "out";
    ASSERT_EQ(Dorado("simulate --sequence seq04 --duration 3 --out " + sim.string()).code, 0);
    // An earlier multi-radar map and an odometry run with masks, and the user's own files.
    for (const char *name : {"mounts.yaml", "twist.csv", "velocities.csv", "masks/000001.txt"})
        Touch(out / name);
    for (const char *name : {"notes.txt", "masks/keep.md", "run.yaml"}) Touch(out / name);

    // A run refused for a bad flag value changes nothing.
    EXPECT_EQ(Dorado("map " + sim.string() + " --out " + out.string() + " --refine bogus").code, 1);
    EXPECT_TRUE(fs::exists(out / "mounts.yaml"));

    const Result r = Dorado("map " + sim.string() + " --prior doppler --out " + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(Has(r.err, out.string() + " held an earlier run's outputs, removed: "
                                          "velocities.csv, mounts.yaml, twist.csv, masks/\n"))
        << r.err;
    for (const char *name : {"mounts.yaml", "twist.csv", "velocities.csv", "masks/000001.txt"})
        EXPECT_FALSE(fs::exists(out / name)) << name;
    for (const char *name : {"notes.txt", "masks/keep.md", "run.yaml"})
        EXPECT_TRUE(fs::exists(out / name)) << name;
    EXPECT_TRUE(fs::exists(out / "trajectory.tum"));
    EXPECT_TRUE(fs::exists(out / "scans.csv"));

    // The same folder for odometry: the map's files go, the odometry's come.
    const Result odometry = Dorado("odometry " + sim.string() + " --out " + out.string());
    ASSERT_EQ(odometry.code, 0) << odometry.err;
    EXPECT_FALSE(fs::exists(out / "scans.csv"));
    EXPECT_FALSE(fs::exists(out / "map.pcd"));
    EXPECT_TRUE(fs::exists(out / "velocities.csv"));
    EXPECT_TRUE(fs::exists(out / "notes.txt"));
}

TEST_F(CmdUsage, BenchRemovesItsReportAndFiguresButNotItsRuns) {
    const fs::path bench = dir_ / "bench";
    for (const char *name :
         {"results.md", "rpe_pairs.csv", "plots/fig7_trajectories.png", "plots/mine.png",
          "runs/seq04/map_doppler/summary.json", "data/seq04/dataset.yaml"})
        Touch(bench / name);
    const auto removed =
        dorado::apps::RemoveEarlierOutputs(bench.string(), dorado::apps::OutputKind::kBench);
    EXPECT_EQ(removed, (std::vector<std::string>{"results.md", "rpe_pairs.csv",
                                                 "plots/fig7_trajectories.png"}));
    EXPECT_TRUE(fs::exists(bench / "plots/mine.png"));
    EXPECT_TRUE(fs::exists(bench / "runs/seq04/map_doppler/summary.json"));
    EXPECT_TRUE(fs::exists(bench / "data/seq04/dataset.yaml"));
}

}  // namespace
