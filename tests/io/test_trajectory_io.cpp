// Trajectory files: exact round trips, evo-compatible text, errors naming file and line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "dorado/core/lie.hpp"
#include "dorado/io/trajectory_io.hpp"

namespace dorado::io {
namespace {

namespace fs = std::filesystem;

std::string Slurp(const std::string &path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void Write(const std::string &path, const std::string &text) {
    std::ofstream(path) << text;
}

class TrajectoryIoTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_traj_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(-3.0, 3.0);
        int64_t t = 1690000000123456789LL;
        for (int i = 0; i < 50; ++i) {
            Vector6d xi;
            for (int k = 0; k < 6; ++k) xi[k] = u(rng);
            xi.tail<3>() *= 0.9;
            trajectory_.Append(t, ExpSE3(xi));
            t += 99999937;  // not a round number of ns
        }
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string Path(const std::string &name) const { return (dir_ / name).string(); }

    static void ExpectSame(const Trajectory &a, const Trajectory &b, double tol) {
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            EXPECT_EQ(a[i].stamp_ns, b[i].stamp_ns);
            EXPECT_LE(
                (a[i].T_world_body.matrix() - b[i].T_world_body.matrix()).cwiseAbs().maxCoeff(),
                tol);
        }
    }

    fs::path dir_;
    Trajectory trajectory_;
};

TEST_F(TrajectoryIoTest, TumRoundTripIsExactAndTextStable) {
    WriteTum(Path("a.tum"), trajectory_);
    const Trajectory back = ReadTum(Path("a.tum"));
    ExpectSame(trajectory_, back, 4e-9);  // 5e-10 per printed quaternion entry
    WriteTum(Path("b.tum"), back);
    EXPECT_EQ(Slurp(Path("a.tum")), Slurp(Path("b.tum"))) << "bit-exact to the printed precision";
    EXPECT_FALSE(fs::exists(Path("a.tum.tmp"))) << "the temporary file is renamed away";
}

TEST_F(TrajectoryIoTest, TumLineFormatIsEvoReadable) {
    Trajectory t;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << 1.5, -2, 0.25;
    t.Append(1690000000500000000LL, T);
    WriteTum(Path("one.tum"), t);
    std::ifstream in(Path("one.tum"));
    std::string header, line;
    std::getline(in, header);
    std::getline(in, line);
    EXPECT_EQ(header[0], '#');
    EXPECT_EQ(line,
              "1690000000.500000000 1.500000000 -2.000000000 0.250000000 0.000000000 0.000000000 "
              "0.000000000 1.000000000");
}

TEST_F(TrajectoryIoTest, KittiRoundTrip) {
    WriteKitti(Path("poses.txt"), Path("times.txt"), trajectory_);
    const Trajectory back = ReadKitti(Path("poses.txt"), Path("times.txt"));
    ExpectSame(trajectory_, back, 1e-8);
    WriteKitti(Path("poses2.txt"), Path("times2.txt"), back);
    EXPECT_EQ(Slurp(Path("times.txt")), Slurp(Path("times2.txt")));
}

TEST_F(TrajectoryIoTest, PaperCsvRoundTripWithHeader) {
    WritePaperCsv(Path("gt.csv"), trajectory_);
    EXPECT_EQ(Slurp(Path("gt.csv")).rfind("sec,nsec,x,y,z,qx,qy,qz,qw\n1690000000,123456789,", 0),
              0u);
    const Trajectory back = ReadPaperCsv(Path("gt.csv"));
    ExpectSame(trajectory_, back, 4e-9);  // 5e-10 per printed quaternion entry
    WritePaperCsv(Path("gt2.csv"), back);
    EXPECT_EQ(Slurp(Path("gt.csv")), Slurp(Path("gt2.csv")));
}

TEST_F(TrajectoryIoTest, ErrorsNameFileAndLine) {
    auto expect_error = [&](const std::string &text, const std::string &needle) {
        Write(Path("bad.tum"), text);
        try {
            (void)ReadTum(Path("bad.tum"));
            ADD_FAILURE() << "no error for: " << text;
        } catch (const TrajectoryFileError &e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expect_error("# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n", "bad.tum:3: expected 8 values");
    expect_error("1.0 0 0 nan 0 0 0 1\n", "bad.tum:1: bad number 'nan'");
    expect_error("1.0 0 0 0 0 0 0 0\n", "bad.tum:1: quaternion norm");
    expect_error("2.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n",
                 "bad.tum:2: time 1.000000000 s does not come after");
    expect_error("", "no poses");
    EXPECT_THROW((void)ReadTum(Path("missing.tum")), TrajectoryFileError);
    Write(Path("p.txt"), "1 0 0 0 0 1 0 0 0 0 1 0\n");
    Write(Path("t.txt"), "0.0\n1.0\n");
    EXPECT_THROW((void)ReadKitti(Path("p.txt"), Path("t.txt")), TrajectoryFileError);
}

}  // namespace
}  // namespace dorado::io
