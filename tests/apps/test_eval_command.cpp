// `dorado eval` end to end on TUM files: the per-frame RPE it reports equals the closed form of a
// straight-line reference against a circular-arc estimate (what evo_rpe --delta 1 --delta_unit f
// reports for these files), with the reference at another rate than the estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "dorado/core/angles.hpp"
#include "dorado/io/trajectory_io.hpp"

namespace {

namespace fs = std::filesystem;

TEST(EvalCommand, PerFrameRpeOfTumFilesMatchesClosedForm) {
    const fs::path dir =
        fs::temp_directory_path() / ("dorado_eval_cmd_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const double vq = 1.3, v = 1.5, w = 0.4;
    const int64_t t0 = 1'700'000'000'000'000'000;  // absolute epoch stamps, as in real files
    // Reference: straight line at 50 Hz (linear interpolation is exact on it); the estimate: arc
    // at irregular ~10 Hz stamps.
    dorado::Trajectory reference, estimate;
    for (int k = 0; k <= 300; ++k) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(vq * 0.02 * k, 0, 0);
        reference.Append(t0 + k * 20'000'000LL, T);
    }
    std::vector<double> stamps_s;
    for (int k = 0; k < 50; ++k) {
        const double t = 0.1 * k + 0.013 * std::sin(1.3 * k) + 0.02;
        stamps_s.push_back(t);
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = Eigen::AngleAxisd(w * t, Eigen::Vector3d::UnitZ()).matrix();
        T.translation() =
            Eigen::Vector3d(v / w * std::sin(w * t), v / w * (1 - std::cos(w * t)), 0);
        estimate.Append(t0 + static_cast<int64_t>(std::llround(t * 1e9)), T);
    }
    dorado::io::WriteTum((dir / "gt.tum").string(), reference);
    dorado::io::WriteTum((dir / "est.tum").string(), estimate);

    const std::string command = std::string(DORADO_BINARY) + " eval --gt " +
                                (dir / "gt.tum").string() + " --est " + (dir / "est.tum").string() +
                                " --json " + (dir / "rpe.json").string() + " > " +
                                (dir / "out.txt").string();
    ASSERT_EQ(std::system(command.c_str()), 0);
    std::ifstream in(dir / "rpe.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    const auto trans = j["rpe_translation_m_per_pair"].get<std::vector<double>>();
    const auto rot = j["rpe_rotation_deg_per_pair"].get<std::vector<double>>();
    ASSERT_EQ(trans.size(), 49u);
    // TUM files carry stamps and poses in text: 1e-6 is what the format's precision allows.
    for (std::size_t k = 0; k < trans.size(); ++k) {
        const double dt = stamps_s[k + 1] - stamps_s[k];
        const double ex = v / w * std::sin(w * dt) - vq * dt;
        const double ey = v / w * (1 - std::cos(w * dt));
        EXPECT_NEAR(trans[k], std::hypot(ex, ey), 1e-6) << k;
        EXPECT_NEAR(rot[k], dorado::RadToDeg(w * dt), 1e-5) << k;
    }
    // A wrong file is an error naming it.
    const std::string bad = std::string(DORADO_BINARY) + " eval --gt " +
                            (dir / "missing.tum").string() + " --est " +
                            (dir / "est.tum").string() + " 2> " + (dir / "err.txt").string();
    EXPECT_NE(std::system(bad.c_str()), 0);
    std::ifstream err(dir / "err.txt");
    const std::string message((std::istreambuf_iterator<char>(err)),
                              std::istreambuf_iterator<char>());
    EXPECT_NE(message.find("missing.tum"), std::string::npos) << message;
    fs::remove_all(dir);
}

}  // namespace

namespace {

// Writes a straight reference of `metres` in 1 m steps (10 Hz) and an estimate `scale` too long.
void WriteStraight(const fs::path &dir, int metres, double scale) {
    dorado::Trajectory reference, estimate;
    for (int k = 0; k <= metres; ++k) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(k, 0, 0);
        reference.Append(k * 100'000'000LL, T);
        T.translation() *= scale;
        estimate.Append(k * 100'000'000LL, T);
    }
    dorado::io::WriteTum((dir / "gt.tum").string(), reference);
    dorado::io::WriteTum((dir / "est.tum").string(), estimate);
}

std::string Slurp(const fs::path &path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(EvalCommand, PrintsEndPointErrorAndKittiDriftOrWhyNot) {
    const fs::path dir =
        fs::temp_directory_path() / ("dorado_eval_drift_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const std::string eval = std::string(DORADO_BINARY) + " eval --gt " +
                             (dir / "gt.tum").string() + " --est " + (dir / "est.tum").string() +
                             " --json " + (dir / "eval.json").string() + " > " +
                             (dir / "out.txt").string();
    // 300 m, the estimate 2 % long: it ends 6 m away (2 % of the path). KITTI segments (the
    // devkit's: the first pose more than L further, a start every 10 poses): 20 of 100 m (101 m
    // driven, 2.02 m off) and 10 of 200 m (201 m, 4.02 m off); 300 m has none (301 m > 300 m).
    WriteStraight(dir, 300, 1.02);
    ASSERT_EQ(std::system(eval.c_str()), 0);
    nlohmann::json j = nlohmann::json::parse(std::ifstream(dir / "eval.json"));
    EXPECT_NEAR(j["end_point_error"]["error_m"].get<double>(), 6.0, 1e-6);
    EXPECT_NEAR(j["end_point_error"]["path_length_m"].get<double>(), 300.0, 1e-6);
    EXPECT_NEAR(j["end_point_error"]["percent"].get<double>(), 2.0, 1e-6);
    const double drift = (20 * 2.02 / 100.0 + 10 * 4.02 / 200.0) / 30.0 * 100.0;
    EXPECT_EQ(j["kitti_drift"]["segments"].get<int>(), 30);
    EXPECT_NEAR(j["kitti_drift"]["translation_percent"].get<double>(), drift, 1e-6);
    EXPECT_NEAR(j["kitti_drift"]["rotation_deg_per_100m"].get<double>(), 0.0, 1e-9);
    const std::string out = Slurp(dir / "out.txt");
    EXPECT_NE(out.find("end_point_error          6.000 m, 2.000 % of the reference's 300.0 m path"),
              std::string::npos)
        << out;
    char line[96];
    std::snprintf(line, sizeof(line), "kitti_drift (100-800 m)  %.3f %% translation", drift);
    EXPECT_NE(out.find(line), std::string::npos) << out;

    // 60 m: no segment; it says why.
    WriteStraight(dir, 60, 1.02);
    ASSERT_EQ(std::system(eval.c_str()), 0);
    j = nlohmann::json::parse(std::ifstream(dir / "eval.json"));
    EXPECT_FALSE(j.contains("kitti_drift"));
    EXPECT_NEAR(j["end_point_error"]["error_m"].get<double>(), 1.2, 1e-6);
    EXPECT_NE(Slurp(dir / "out.txt")
                  .find("kitti_drift (100-800 m)  none: the reference's path is 60.0 m, not "
                        "longer than the shortest segment (100 m)"),
              std::string::npos);
    fs::remove_all(dir);
}
