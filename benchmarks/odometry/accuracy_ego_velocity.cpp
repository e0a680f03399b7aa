// Accuracy of the ego-velocity estimator against the Cramer-Rao bound.
// For each scenario, over seeded trials: the velocity RMSE per axis next to the CRB
// sqrt(diag((A^T W A)^-1)) of the same geometry with W = diag(1 / sigma_i^2) over the static
// points (what an oracle that knew the outliers and the noise could reach), and the ratio of the
// mean squared errors. Run: build/benchmarks/odometry/accuracy_ego_velocity [trials]
#include <Eigen/Cholesky>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/testing/doppler_scan.hpp"

using namespace dorado::odometry;
namespace testing = dorado::testing;

namespace {

struct Scenario {
    std::string name;
    double dynamic_fraction;
    bool coherent;
};

void Evaluate(const std::string &label, const EgoVelocityConfig &config, const Scenario &sc,
              int trials) {
    EgoVelocityEstimator estimator(config);
    Eigen::Vector3d se = Eigen::Vector3d::Zero(), crb = Eigen::Vector3d::Zero();
    int invalid = 0;
    for (int t = 0; t < trials; ++t) {
        testing::SceneOptions o;
        o.points = 5000;
        o.dynamic_fraction = sc.dynamic_fraction;
        o.coherent_crowd = sc.coherent;
        o.seed = 7000 + t;
        const auto s = testing::MakeScan(o);
        Eigen::Matrix3Xd dirs(3, o.points);
        Eigen::VectorXd sigma(o.points);
        int n = 0;
        for (int i = 0; i < o.points; ++i) {
            if (s.dynamic[i]) continue;
            dirs.col(n) = s.directions.col(i);
            sigma[n++] = s.sigma_mps[i];
        }
        crb += VelocityCramerRaoBound(dirs.leftCols(n), sigma.head(n)).diagonal();
        const auto r = estimator.Estimate(s.scan);
        invalid += !r.valid();
        se += (r.v_radar_mps - o.v_radar).cwiseAbs2();
    }
    const Eigen::Vector3d rmse = (se / trials).cwiseSqrt(), bound = (crb / trials).cwiseSqrt();
    std::printf(
        "%-34s %-16s  RMSE [mm/s] %6.2f %6.2f %6.2f   CRB %6.2f %6.2f %6.2f   "
        "RMSE/CRB %.3f  invalid %d\n",
        sc.name.c_str(), label.c_str(), 1e3 * rmse.x(), 1e3 * rmse.y(), 1e3 * rmse.z(),
        1e3 * bound.x(), 1e3 * bound.y(), 1e3 * bound.z(), std::sqrt(se.sum() / crb.sum()),
        invalid);
}

}  // namespace

int main(int argc, char **argv) {
    const int trials = argc > 1 ? std::atoi(argv[1]) : 200;
    std::printf(
        "5000-point Hugin-like scans (120 x 30 deg FOV), Doppler sigma 0.05 m/s growing "
        "for weak returns, %d trials each\n",
        trials);
    EgoVelocityConfig ransac, unit, irls, none;
    unit.use_power = false;
    irls.method = RobustMethod::kTrimmedIrls;
    none.method = RobustMethod::kNone;
    const Scenario scenarios[] = {{"static scene", 0.0, false},
                                  {"30 % random moving objects", 0.3, false},
                                  {"50 % random moving objects", 0.5, false},
                                  {"30 % bus (one coherent crowd)", 0.3, true},
                                  {"50 % bus (one coherent crowd)", 0.5, true}};
    for (const auto &sc : scenarios) {
        Evaluate("RANSAC+SNR", ransac, sc, trials);
        Evaluate("RANSAC unit w", unit, sc, trials);
        Evaluate("trimmed IRLS", irls, sc, trials);
        if (sc.dynamic_fraction == 0.0) Evaluate("plain WLS", none, sc, trials);
    }
    return 0;
}
