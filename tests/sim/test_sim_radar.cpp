// The radar model against eq. (1) of the paper: static points' Doppler is -d . v_radar.
#include <gtest/gtest.h>

#include <cmath>

#include "dorado/sim/moving_objects.hpp"
#include "dorado/sim/radar_model.hpp"
#include "dorado/sim/terrain.hpp"
#include "dorado/sim/vehicle.hpp"
#include "dorado/sim/world.hpp"

namespace dorado::sim {
namespace {

/// A hilly sequence with people and a car, the radar on a rotated lever-arm mount.
SequenceConfig Scene() {
    SequenceConfig config;
    config.duration_s = 30.0;
    config.seed = 11;
    config.terrain.hill_height_m = 1.0;
    config.terrain.roughness_m = 0.01;
    config.dynamic.people = 30;
    config.dynamic.cars = 6;
    config.dynamic.spawn_distance_max_m = 15.0;
    config.radar.mount.translation_m = {0.7, 0.05, 0.4};
    config.radar.mount.rotation_rpy_deg = {3.0, 5.0, -10.0};
    return config;
}

void SwitchOffNoise(RadarConfig &radar) {
    radar.range_sigma_m = radar.azimuth_sigma_deg = radar.elevation_sigma_deg = 0.0;
    radar.doppler_sigma_mps = 0.0;
    radar.ghost_probability = radar.double_bounce_probability = 0.0;
    radar.ground_multipath_probability = radar.clutter_per_scan = 0.0;
}

class RadarModelTest : public ::testing::Test {
  protected:
    void Build(const SequenceConfig &config) {
        config_ = config;
        terrain_ = std::make_unique<Terrain>(config.terrain, config.seed);
        vehicle_ = std::make_unique<VehicleTrajectory>(config, *terrain_);
        world_ = std::make_unique<StaticWorld>(config.world, *terrain_, vehicle_->RouteSamples(),
                                               config.seed);
        moving_ =
            std::make_unique<MovingObjects>(config.dynamic, *terrain_, *vehicle_, config.seed);
        radar_ = std::make_unique<RadarModel>(config.radar, *terrain_, *world_, *moving_);
    }
    /// A scan at t and the radar's true velocity in the radar frame (independently composed).
    SimulatedScan Scan(double t, Eigen::Vector3d &v_radar, uint64_t seed = 1) const {
        const Eigen::Isometry3d T_base_radar = config_.radar.mount.Transform();
        const Eigen::Isometry3d T_world_base = vehicle_->Pose(t);
        const Twist twist = vehicle_->Twist(t);
        const Eigen::Vector3d v_base_radar =
            twist.v_base_mps + twist.omega_base_radps.cross(T_base_radar.translation());
        v_radar = T_base_radar.linear().transpose() * v_base_radar;
        std::mt19937_64 rng(seed);
        return radar_->Measure(t, T_world_base * T_base_radar, T_world_base.linear() * v_base_radar,
                               rng);
    }
    SequenceConfig config_;
    std::unique_ptr<Terrain> terrain_;
    std::unique_ptr<VehicleTrajectory> vehicle_;
    std::unique_ptr<StaticWorld> world_;
    std::unique_ptr<MovingObjects> moving_;
    std::unique_ptr<RadarModel> radar_;
};

TEST_F(RadarModelTest, StaticDopplerIsMinusDirectionDotVelocityWithoutNoise) {
    SequenceConfig config = Scene();
    SwitchOffNoise(config.radar);
    Build(config);
    std::size_t static_points = 0, moving_points = 0, moving_off_model = 0;
    for (double t = 3.0; t < 28.0; t += 2.5) {
        Eigen::Vector3d v_radar;
        const SimulatedScan sim = Scan(t, v_radar);
        ASSERT_GT(v_radar.norm(), 0.1) << "the vehicle should be moving at t = " << t;
        for (Eigen::Index i = 0; i < sim.scan.size(); ++i) {
            const Eigen::Vector3d d = sim.scan.xyz_radar.col(i).normalized();
            const double residual = sim.scan.doppler_mps[i] + d.dot(v_radar);
            const PointSource s = sim.source[static_cast<std::size_t>(i)];
            if (s == PointSource::kStatic || s == PointSource::kGround) {
                ++static_points;
                ASSERT_NEAR(residual, 0.0, 1e-9) << "scan t=" << t << " point " << i;
            } else if (s == PointSource::kMoving) {
                ++moving_points;
                moving_off_model += std::abs(residual) > 0.1;
            }
        }
    }
    EXPECT_GT(static_points, 5000u);
    // Moving objects have their own velocity: most of their points break eq. (1).
    EXPECT_GT(moving_points, 50u);
    EXPECT_GT(moving_off_model, moving_points / 2);
}

/// Robust standard deviation (1.4826 x median absolute value) of residuals around zero.
double RobustSigma(std::vector<double> r) {
    for (auto &x : r) x = std::abs(x);
    std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
    return 1.4826 * r[r.size() / 2];
}

TEST_F(RadarModelTest, NoiseIsLargerForWeakReturnsAndFieldsFollowTheHuginLayout) {
    SequenceConfig config = Scene();
    // Exact angles: the Doppler residual is then the Doppler noise alone.
    config.radar.azimuth_sigma_deg = config.radar.elevation_sigma_deg = 0.0;
    Build(config);
    std::vector<double> strong, weak;
    const double power_ref = config.radar.doppler_snr_ref_db + config.radar.noise_floor_db;
    for (double t = 4.0; t < 28.0; t += 3.0) {
        Eigen::Vector3d v_radar;
        const SimulatedScan sim = Scan(t, v_radar, 5);
        ASSERT_GT(sim.scan.size(), 200);
        for (Eigen::Index i = 0; i < sim.scan.size(); ++i) {
            const Eigen::Vector3d p = sim.scan.xyz_radar.col(i);
            // Range and elevation are those of the reported xyz; azimuth is measured from +Y.
            ASSERT_NEAR(sim.scan.range_m[i], p.norm(), 1e-9);
            ASSERT_NEAR(sim.scan.elevation_rad[i], std::asin(p.z() / p.norm()), 1e-9);
            ASSERT_NEAR(sim.scan.azimuth_rad[i], std::atan2(p.x(), p.y()), 1e-12);
            if (sim.source[static_cast<std::size_t>(i)] != PointSource::kStatic) continue;
            const double r = sim.scan.doppler_mps[i] + p.normalized().dot(v_radar);
            if (sim.scan.power_db[i] > power_ref + 15.0) strong.push_back(r);
            if (sim.scan.power_db[i] < power_ref) weak.push_back(r);  // SNR below the reference
        }
    }
    ASSERT_GT(strong.size(), 300u);
    ASSERT_GT(weak.size(), 300u);
    // Strong: sigma * sqrt(1 + 10^-1.5) = 1.016 sigma; weak (SNR 12-15 dB): 1.41-1.73 sigma.
    const double sigma = config.radar.doppler_sigma_mps;
    EXPECT_NEAR(RobustSigma(strong), 1.016 * sigma, 0.1 * sigma);
    EXPECT_GT(RobustSigma(weak), 1.35 * sigma);
    EXPECT_LT(RobustSigma(weak), 1.8 * sigma);
}

TEST_F(RadarModelTest, DopplerAliasesIntoTheUnambiguousInterval) {
    SequenceConfig config = Scene();
    SwitchOffNoise(config.radar);
    config.radar.doppler_unambiguous_mps = 0.4;  // slower than the vehicle: static points wrap
    Build(config);
    Eigen::Vector3d v_radar;
    const SimulatedScan sim = Scan(12.0, v_radar);
    ASSERT_GT(v_radar.norm(), 0.5);
    int wrapped = 0;
    for (Eigen::Index i = 0; i < sim.scan.size(); ++i) {
        const double measured = sim.scan.doppler_mps[i];
        EXPECT_GE(measured, -0.4);
        EXPECT_LT(measured, 0.4);
        if (sim.source[static_cast<std::size_t>(i)] != PointSource::kStatic) continue;
        const double truth = -sim.scan.xyz_radar.col(i).normalized().dot(v_radar);
        const double k = (truth - measured) / 0.8;  // a whole number of 2 v_max
        EXPECT_NEAR(k, std::round(k), 1e-6);
        wrapped += std::abs(std::round(k)) > 0.5;
    }
    EXPECT_GT(wrapped, 100);
}

TEST_F(RadarModelTest, DetectionsThinOutWithRange) {
    SequenceConfig config = Scene();
    config.terrain.hill_height_m = 0.0;
    config.world.vegetation_per_m2 = 1.0;
    Build(config);
    // Reflectors are spread evenly on the ground, so per unit area the detections must fall with
    // range (SNR ~ -40 log r): compare the density of points in [10, 20) m and [40, 50) m.
    double near = 0.0, far = 0.0;
    for (double t = 5.0; t < 25.0; t += 5.0) {
        Eigen::Vector3d v_radar;
        const SimulatedScan sim = Scan(t, v_radar);
        for (Eigen::Index i = 0; i < sim.scan.size(); ++i) {
            if (sim.source[static_cast<std::size_t>(i)] != PointSource::kStatic) continue;
            const double r = sim.scan.range_m[i];
            if (r >= 10 && r < 20) near += 1.0 / (20 * 20 - 10 * 10);
            if (r >= 40 && r < 50) far += 1.0 / (50 * 50 - 40 * 40);
        }
    }
    EXPECT_GT(near, 3.0 * far);
    EXPECT_GT(far, 0.0);
}

}  // namespace
}  // namespace dorado::sim
