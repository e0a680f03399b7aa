// Registration recovers a known transform between a synthetic radar scan and a transformed noisy
// copy, for every PCL method (each refined by Ceres and weighed by the smoother).
#include <gtest/gtest.h>

#include <random>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/testing/mapper_input.hpp"
#include "dorado/testing/street_scene.hpp"

namespace dorado::mapping {
namespace {
using testing::PriorInput;

using testing::MakeStreetWorld;
using testing::RadarSimOptions;
using testing::SimulateScan;

class KnownTransform : public ::testing::TestWithParam<RegistrationMethod> {};

// One scan's input: the prior and the interval, no masks.
TEST_P(KnownTransform, IsRecovered) {
    const RegistrationMethod method = GetParam();
    const Eigen::Matrix3Xd world = MakeStreetWorld(7);
    std::mt19937 rng(11);
    RadarSimOptions sim;
    sim.ghost_fraction = 0.0;
    const Eigen::Isometry3d T_base_radar = Eigen::Isometry3d(Eigen::Translation3d(1.5, 0.0, 1.0));
    Eigen::Array<bool, Eigen::Dynamic, 1> labels;
    const Eigen::Matrix3Xd no_movers(3, 0);
    const RadarScan first = SimulateScan(world, Eigen::Isometry3d::Identity(), T_base_radar,
                                         Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                         no_movers, Eigen::Vector3d::Zero(), sim, rng, &labels);

    // The copy: the same first scan's points seen from the known pose, plus 3 cm noise.
    Vector6d xi;
    xi << 0.45, -0.2, 0.05, 0.015, -0.01, 0.06;  // ~3.5 deg yaw, ~1 deg roll
    const Eigen::Isometry3d T_true = ExpSE3(xi);
    RadarScan copy = first;
    std::normal_distribution<double> noise(0.0, 0.03);
    const Eigen::Isometry3d T_radar2_radar1 = (T_true * T_base_radar).inverse() * T_base_radar;
    for (Eigen::Index i = 0; i < copy.size(); ++i)
        copy.xyz_radar.col(i) = T_radar2_radar1 * first.xyz_radar.col(i) +
                                Eigen::Vector3d(noise(rng), noise(rng), noise(rng));

    MapperConfig config;
    config.method = method;
    config.use_doppler = false;  // the copy's Doppler is not consistent with any motion
    config.map.voxel_size_m = 0.2;
    config.scan_voxel_m = 0.3;
    config.max_source_points = 3000;  // accuracy, not speed, is under test here
    config.max_iterations = 50;
    Extrinsics extrinsics;
    extrinsics.T_base_radar = T_base_radar;
    RadarMapper mapper(config, extrinsics);
    MotionPrior prior;  // identity, wide: registration has to find the whole transform
    prior.covariance = Matrix6d::Identity();
    ASSERT_TRUE(mapper.Register(first, PriorInput(prior, 0.1)).first_scan);
    const RegistrationResult result = mapper.Register(copy, PriorInput(prior, 0.1));

    ASSERT_FALSE(result.fallback()) << ToString(result.fallback_cause);
    std::printf("%s: observability %.4f\n", ToString(method), result.observability);
    const Eigen::Isometry3d error = T_true.inverse() * result.T_world_base;
    EXPECT_LT(error.translation().norm(), 0.05) << "method " << ToString(method);
    EXPECT_LT(RotationAngle(error.linear()), 0.003) << "method " << ToString(method);
    EXPECT_GT(result.correspondences, 500);
}

INSTANTIATE_TEST_SUITE_P(Methods, KnownTransform,
                         ::testing::Values(RegistrationMethod::kPointToPoint,
                                           RegistrationMethod::kPointToPlane,
                                           RegistrationMethod::kGicp));

TEST(MapperConfig, RejectsNonsenseNamingTheKey) {
    MapperConfig config;
    config.scan_voxel_m = -1.0;
    try {
        config.Validate();
        FAIL() << "accepted a negative voxel";
    } catch (const std::invalid_argument &e) {
        EXPECT_NE(std::string(e.what()).find("scan_voxel_m"), std::string::npos) << e.what();
    }
    config = MapperConfig{};
    config.map.max_points_per_voxel = 0;
    EXPECT_THROW(config.Validate(), std::invalid_argument);
    EXPECT_THROW((void)ParseRegistrationMethod("icp"), std::invalid_argument);
    EXPECT_EQ(ParseRobustKernel("tukey"), RobustKernel::kTukey);
}

}  // namespace
}  // namespace dorado::mapping
