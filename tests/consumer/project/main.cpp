// One ego-velocity estimate through the installed dorado::odometry: a synthetic scan of static
// points seen from a radar moving at a known velocity (eq. 1: doppler_i = -d_i . v), exact data.
#include <cmath>
#include <cstdio>
#include <random>

#include "dorado/odometry/ego_velocity.hpp"

int main() {
    const Eigen::Vector3d v_true(4.0, -0.5, 0.2);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> azimuth(-1.0, 1.0), elevation(-0.2, 0.2),
        range(5.0, 50.0);
    dorado::RadarScan scan;
    scan.Resize(200);
    for (Eigen::Index i = 0; i < scan.size(); ++i) {
        const double a = azimuth(rng), e = elevation(rng), r = range(rng);
        const Eigen::Vector3d d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
        scan.xyz_radar.col(i) = r * d;
        scan.doppler_mps(i) = -d.dot(v_true);
        scan.power_db(i) = 20.0;
    }
    scan.has_power = true;
    scan.DeriveSphericalFromXyz();
    dorado::odometry::EgoVelocityEstimator estimator{dorado::odometry::EgoVelocityConfig{}};
    const auto result = estimator.Estimate(scan);
    const double error = (result.v_radar_mps - v_true).norm();
    std::printf("valid %d, v = [%.6f %.6f %.6f], error %.2e m/s\n", result.valid() ? 1 : 0,
                result.v_radar_mps.x(), result.v_radar_mps.y(), result.v_radar_mps.z(), error);
    return result.valid() && error < 1e-6 ? 0 : 1;
}
