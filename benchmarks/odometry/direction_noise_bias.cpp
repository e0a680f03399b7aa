// The v_z bias of the ego-velocity from direction noise (errors in variables) against speed, for
// ground-heavy scenes (70 % of the returns 2-15 deg below the horizon), plain eq. (2) least
// squares against the bias-compensated fit, beside the Cramer-Rao bound. The bound takes each
// point's direction noise into its Doppler variance, sigma_i^2 = sigma_d^2 + v^T C_i v (the
// linearised errors-in-variables model). Run:
//   build/benchmarks/odometry/direction_noise_bias [trials]
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "dorado/core/angles.hpp"
#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/testing/noisy_direction_scan.hpp"

using dorado::DegToRad;
using namespace dorado::odometry;
namespace testing = dorado::testing;

namespace {

struct Stats {
    double bias = 0.0, rmse = 0.0, sem = 0.0;
};

Stats Run(testing::NoisyDirectionOptions o, bool compensate, int trials, double &crb_sigma_vz) {
    EgoVelocityConfig c;
    c.doppler_sigma_mps = o.doppler_sigma_mps;
    c.sensor.azimuth_sigma_deg = o.azimuth_sigma_deg;
    c.sensor.elevation_sigma_deg = o.elevation_sigma_deg;
    c.compensate_direction_noise = compensate;
    EgoVelocityEstimator estimator(c);
    double sum = 0.0, sum2 = 0.0, crb = 0.0;
    int valid = 0;
    for (int t = 0; t < trials; ++t) {
        o.seed = 5000 + t;
        const auto scene = testing::MakeNoisyDirectionScan(o);
        const EgoVelocityResult r = estimator.Estimate(scene.scan);
        if (!r.valid()) continue;
        const double e = r.v_radar_mps.z() - o.v_radar.z();
        sum += e;
        sum2 += e * e;
        ++valid;
        // Effective Doppler sigma of each point at the true velocity and direction.
        const Eigen::Index n = scene.true_directions.cols();
        Eigen::VectorXd sigma(n);
        for (Eigen::Index i = 0; i < n; ++i) {
            const Eigen::Vector3d d = scene.true_directions.col(i);
            const double cos_el = std::hypot(d.x(), d.y());
            const Eigen::Vector3d e_el(-d.z() * d.x() / cos_el, -d.z() * d.y() / cos_el, cos_el);
            const Eigen::Vector3d e_az(-d.y() / cos_el, d.x() / cos_el, 0.0);
            const double se = DegToRad(o.elevation_sigma_deg), sa = DegToRad(o.azimuth_sigma_deg);
            sigma[i] = std::sqrt(o.doppler_sigma_mps * o.doppler_sigma_mps +
                                 std::pow(se * e_el.dot(o.v_radar), 2) +
                                 std::pow(sa * cos_el * e_az.dot(o.v_radar), 2));
        }
        crb += VelocityCramerRaoBound(scene.true_directions, sigma)(2, 2);
    }
    Stats s;
    s.bias = sum / valid;
    s.rmse = std::sqrt(sum2 / valid);
    s.sem = std::sqrt(std::max(sum2 / valid - s.bias * s.bias, 0.0) / valid);
    crb_sigma_vz = std::sqrt(crb / valid);
    return s;
}

}  // namespace

int main(int argc, char **argv) {
    const int trials = argc > 1 ? std::atoi(argv[1]) : 200;
    std::printf(
        "v_z bias of the ego-velocity, %d scans of 800 points per row, 70 %% ground, "
        "azimuth noise 0.5 deg, Doppler noise 0.05 m/s, v = (speed, 0, 0)\n",
        trials);
    std::printf("%6s %6s | %10s %10s | %10s %10s %8s | %9s\n", "el_deg", "v_mps", "plain_bias",
                "plain_rmse", "comp_bias", "comp_rmse", "bias_%v", "crb_sigma");
    for (double el_sigma : {1.0, 2.0}) {
        for (double speed : {2.0, 4.0, 6.0, 8.0, 10.0, 12.0, 15.0}) {
            testing::NoisyDirectionOptions o;
            o.elevation_sigma_deg = el_sigma;
            o.v_radar = Eigen::Vector3d(speed, 0.0, 0.0);
            double crb = 0.0;
            const Stats plain = Run(o, false, trials, crb);
            const Stats comp = Run(o, true, trials, crb);
            std::printf(
                "%6.1f %6.1f | %+10.4f %10.4f | %+10.4f %10.4f %+8.3f | %9.4f   "
                "(+-%.4f)\n",
                el_sigma, speed, plain.bias, plain.rmse, comp.bias, comp.rmse,
                100.0 * comp.bias / speed, crb, comp.sem);
        }
    }
    return 0;
}
