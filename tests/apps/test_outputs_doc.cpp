// docs/outputs.md against the files the commands write: `dorado odometry`, `map` (one radar) and
// `twist` (two radars) run on small data; every CSV's header is the page's `<!-- columns FILE -->`
// block, every file written is named on the page; docs/attitude.md lists every status of
// scans.csv's yaw_calibration and every ground reason of velocities.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "dorado/odometry/ground_plane.hpp"
#include "dorado/odometry/yaw_calibration.hpp"
#include "dorado/testing/run_command.hpp"
#include "dorado/testing/scan_folder.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path kDocs = fs::path(DORADO_SOURCE_DIR) / "docs";

std::string Slurp(const fs::path &path) {
    std::stringstream ss;
    ss << std::ifstream(path).rdbuf();
    return ss.str();
}

// FILE -> its columns as the page lists them ("a, b, c" in a code block), commas only.
std::map<std::string, std::string> DocumentedColumns(const std::string &page) {
    std::map<std::string, std::string> columns;
    const std::regex block("<!-- columns (\\S+) -->\n```\n([\\s\\S]*?)\n```\n<!-- end columns -->");
    for (std::sregex_iterator it(page.begin(), page.end(), block), end; it != end; ++it) {
        std::string text = (*it)[2];
        text = std::regex_replace(text, std::regex("\\s+"), "");
        columns[(*it)[1]] = text;
    }
    return columns;
}

std::string HeaderOf(const fs::path &csv) {
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);
    return line;
}

class OutputsDoc : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ =
            fs::path(::testing::TempDir()) / ("dorado_outputs_doc_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        const fs::path sim = dir_ / "sim";
        ASSERT_EQ(Dorado("simulate --sequence seq06 --duration 4 --out " + sim.string()).code, 0);
        ASSERT_EQ(Dorado("odometry " + sim.string() + " --accept-implausible --masks --out " +
                         (dir_ / "odometry").string())
                      .code,
                  0);
        ASSERT_EQ(Dorado("map " + sim.string() + " --accept-implausible --masks --out " +
                         (dir_ / "map").string())
                      .code,
                  0);
        const Result twist =
            Dorado("twist " + TwoRadars().string() + " --out " + (dir_ / "twist").string());
        ASSERT_EQ(twist.code, 0) << twist.err;
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    using Result = dorado::testing::CommandResult;
    static Result Dorado(const std::string &args) {
        return dorado::testing::RunCommand(std::string(DORADO_BINARY) + " " + args, dir_);
    }

    // Two 2D radars looking ahead and left at static points while the vehicle drives ahead.
    static fs::path TwoRadars() {
        for (const char *radar : {"front", "left"}) {
            dorado::testing::WriteScanFolder(dir_ / radar, 15, 30, [](int i, float *v) {
                v[0] = 5.0f + i, v[1] = -8.0f + 0.6f * i, v[2] = 0.0f, v[3] = 5.0f;
                v[4] = -1.5f * v[0] / std::hypot(v[0], v[1]);  // 1.5 m/s along the radar's x
            });
        }
        const fs::path description = dir_ / "two.yaml";
        std::ofstream(description)
            << "name: two\n"
            << dorado::testing::kFrontFolderKeys
            << "vehicle: {model: ackermann, half_wheelbase_m: 1.3}\n"
               "radar: {geometry: planar}\n"
               "radars:\n"
               "  - {name: front, scans_dir: front/scans, timestamps_file: front/times.txt,\n"
               "     T_base_radar: {translation_m: [3.6, 0, 0], rotation_rpy_deg: [0, 0, 0]}}\n"
               "  - {name: left, scans_dir: left/scans, timestamps_file: left/times.txt,\n"
               "     T_base_radar: {translation_m: [3.6, 0.8, 0], rotation_rpy_deg: [0, 0, 0]}}\n";
        return description;
    }

    static fs::path dir_;
};

fs::path OutputsDoc::dir_;

TEST_F(OutputsDoc, EveryCsvHeaderIsThePagesColumnList) {
    const auto documented = DocumentedColumns(Slurp(kDocs / "outputs.md"));
    std::size_t compared = 0;
    for (const char *run : {"odometry", "map", "twist"}) {
        for (const auto &entry : fs::directory_iterator(dir_ / run)) {
            if (entry.path().extension() != ".csv") continue;
            const std::string name = entry.path().filename().string();
            const auto found = documented.find(name);
            ASSERT_NE(found, documented.end())
                << "docs/outputs.md has no <!-- columns " << name << " --> block";
            EXPECT_EQ(HeaderOf(entry.path()), found->second)
                << run << "/" << name << ": the file's header differs from docs/outputs.md";
            ++compared;
        }
    }
    EXPECT_EQ(compared, 5u) << "velocities.csv, scans.csv, covariance.csv, loops.csv, twist.csv";
}

TEST_F(OutputsDoc, EveryFileWrittenIsNamedOnThePage) {
    const std::string page = Slurp(kDocs / "outputs.md");
    for (const char *run : {"odometry", "map", "twist"}) {
        for (const auto &entry : fs::recursive_directory_iterator(dir_ / run)) {
            if (!entry.is_regular_file()) continue;
            std::string name = fs::relative(entry.path(), dir_ / run).string();
            if (name.rfind("masks/", 0) == 0) name = "masks/NNNNNN.txt";
            EXPECT_NE(page.find("`" + name + "`"), std::string::npos)
                << run << " writes " << name << ", which docs/outputs.md does not name";
        }
    }
    for (const char *bench : {"`results.md`", "`results.csv`", "`bench_runs.csv`",
                              "`rpe_pairs.csv`", "`DIR/logs/`", "`DIR/plots/`"})
        EXPECT_NE(page.find(bench), std::string::npos) << bench;
}

// A page that lists what a column can hold lists every value.
TEST(StatusLists, AttitudePageListsEveryStatusAndReason) {
    const std::string page = Slurp(kDocs / "attitude.md");
    using dorado::odometry::YawCalibrationStatus;
    for (int k = 0; k <= static_cast<int>(YawCalibrationStatus::kUpdated); ++k) {
        const std::string status = ToString(static_cast<YawCalibrationStatus>(k));
        EXPECT_NE(page.find("`" + status + "`"), std::string::npos)
            << "docs/attitude.md does not list yaw_calibration status " << status;
    }
    using dorado::odometry::GroundFallback;
    for (int k = 1; k <= static_cast<int>(GroundFallback::kNoBaseHeight); ++k) {
        const std::string reason = ToString(static_cast<GroundFallback>(k));
        EXPECT_NE(page.find("`" + reason + "`"), std::string::npos)
            << "docs/attitude.md does not list ground reason " << reason;
    }
}

}  // namespace
