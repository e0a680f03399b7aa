// The ground's residual in the mapper's refinement (ground_factor.hpp, RefinePose) against
// independent truths: the up-vector of a pose of known roll and pitch written out by hand, and a
// refinement whose prior and registration share a tilted attitude (a drifted map) brought back to
// the true roll and pitch by the road's plane.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "ground_factor.hpp"
#include "registration.hpp"

namespace dorado::mapping {
namespace {

constexpr double kDeg = DegToRad(1.0);

// The road's up-vector in the base frame for roll r, pitch p (ZYX), written out, not from a
// rotation: (-sin p, sin r cos p, cos r cos p).
Eigen::Vector3d UpOf(double roll, double pitch) {
    return {-std::sin(pitch), std::sin(roll) * std::cos(pitch), std::cos(roll) * std::cos(pitch)};
}

Eigen::Isometry3d Pose(double roll, double pitch, double yaw, const Eigen::Vector3d &t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = RotationFromRollPitchYaw(Eigen::Vector3d(roll, pitch, yaw));
    T.translation() = t;
    return T;
}

double Residual(const GroundUp &ground, const Eigen::Isometry3d &T, Eigen::Vector2d *r) {
    std::unique_ptr<ceres::CostFunction> cost(GroundUpError::Create(ground));
    const Eigen::Quaterniond q(T.linear());
    const double *parameters[] = {q.coeffs().data()};
    cost->Evaluate(parameters, r->data(), nullptr);
    return r->norm();
}

TEST(GroundFactor, ResidualIsZeroOnlyAtTheRoadsRollAndPitchWhateverTheYaw) {
    GroundUp ground;
    ground.up_base = UpOf(3.0 * kDeg, -2.0 * kDeg);
    ground.covariance = std::pow(0.5 * kDeg, 2) * Eigen::Matrix2d::Identity();
    Eigen::Vector2d r;
    for (const double yaw : {-2.0, 0.0, 0.7, 3.0})
        EXPECT_LT(Residual(ground, Pose(3.0 * kDeg, -2.0 * kDeg, yaw, {5, -1, 2}), &r), 1e-9);
    // One degree of roll off is two sigmas (0.5 deg) in the up-vector's y; of pitch, in its x.
    Residual(ground, Pose(4.0 * kDeg, -2.0 * kDeg, 0.3, {0, 0, 0}), &r);
    EXPECT_NEAR(std::abs(r.y()), 2.0, 0.02);
    EXPECT_NEAR(r.x(), 0.0, 0.02);
    Residual(ground, Pose(3.0 * kDeg, -1.0 * kDeg, 0.3, {0, 0, 0}), &r);
    EXPECT_NEAR(std::abs(r.x()), 2.0, 0.02);
    EXPECT_NEAR(r.y(), 0.0, 0.02);
}

TEST(GroundFactor, GateRefusesAPlaneTheRotationsCovarianceDoesNotExplain) {
    GroundUp ground;
    ground.up_base = UpOf(0.0, 0.0);
    ground.covariance = std::pow(1.0 * kDeg, 2) * Eigen::Matrix2d::Identity();
    const Eigen::Isometry3d T = Pose(5.0 * kDeg, 0.0, 1.0, Eigen::Vector3d::Zero());
    // 5 deg of roll against 1 deg of plane noise: chi2 = 25 > 9.21.
    EXPECT_FALSE(GroundConsistent(ground, T, Eigen::Matrix3d::Zero()));
    // The same with 3 deg of rotation uncertainty: chi2 = 25 / 10 = 2.5.
    EXPECT_TRUE(GroundConsistent(ground, T, std::pow(3.0 * kDeg, 2) * Eigen::Matrix3d::Identity()));
    ground.max_innovation_chi2 = 0.0;  // no gate
    EXPECT_TRUE(GroundConsistent(ground, T, Eigen::Matrix3d::Zero()));
}

// A drifted map: the registration's matches and the prior agree on a pose tilted by 3 deg of roll
// and -2.5 deg of pitch from the truth (the map built at that attitude); the registration is weak
// in roll and pitch (noisy points near the sensor), the prior's rotation 5 deg wide. The road's
// plane, seen at the true attitude with 0.3 deg, must bring both steps' poses (the registered one
// the map is built from, and the output) back to the true roll and pitch, leaving yaw and
// position where the registration put them.
struct Drifted {
    Eigen::Isometry3d T_true = Pose(1.0 * kDeg, 2.0 * kDeg, 0.6, {10.0, 4.0, 0.5});
    Eigen::Isometry3d T_tilted = Pose(4.0 * kDeg, -0.5 * kDeg, 0.6, {10.0, 4.0, 0.5});
    std::vector<Correspondence> matches;
    MotionPrior prior;
    GroundUp ground;
    MapperConfig config;

    Drifted() {
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(-6.0, 6.0);
        for (int i = 0; i < 120; ++i) {
            const Eigen::Vector3d p(u(rng), u(rng), 0.2 * u(rng));
            matches.push_back({p, T_tilted * p, Eigen::Matrix3d::Identity() / 3.0});
        }
        prior.T_world_base = T_tilted;
        prior.covariance.diagonal() << 0.25, 0.25, 0.25, std::pow(5 * kDeg, 2),
            std::pow(5 * kDeg, 2), std::pow(5 * kDeg, 2);
        prior.kind = PriorKind::kDoppler;
        const Eigen::Vector3d rpy = RollPitchYaw(T_true.linear());
        ground.up_base = UpOf(rpy.x(), rpy.y());
        ground.covariance = std::pow(0.3 * kDeg, 2) * Eigen::Matrix2d::Identity();
        config.registration_covariance = RegistrationCovarianceModel::kIndependent;
        config.refine_max_iterations = 20;
    }

    RefinementOutput Refine(const GroundUp *g) const {
        RefinementInput input;
        input.T_world_base_initial = T_tilted;
        input.prior = &prior;
        input.matches = &matches;
        input.ground = g;
        return RefinePose(input, config);
    }
};

Eigen::Vector2d RollPitchErrorDeg(const Eigen::Isometry3d &T, const Eigen::Isometry3d &T_true) {
    return (RollPitchYaw(T.linear()) - RollPitchYaw(T_true.linear())).head<2>() / kDeg;
}

TEST(GroundFactor, RefinementRecoversTheTrueRollAndPitchOfADriftedMap) {
    const Drifted d;
    const RefinementOutput alone = d.Refine(nullptr);
    ASSERT_TRUE(alone.usable);
    EXPECT_FALSE(alone.ground_used);
    // Without the ground both poses keep the drifted attitude.
    EXPECT_GT(RollPitchErrorDeg(alone.T_world_base, d.T_true).cwiseAbs().maxCoeff(), 2.0);
    EXPECT_GT(RollPitchErrorDeg(alone.registered.T_world_base, d.T_true).cwiseAbs().maxCoeff(),
              2.0);

    const RefinementOutput with = d.Refine(&d.ground);
    ASSERT_TRUE(with.usable);
    EXPECT_TRUE(with.ground_used);
    for (const Eigen::Isometry3d &T : {with.T_world_base, with.registered.T_world_base}) {
        const Eigen::Vector2d e = RollPitchErrorDeg(T, d.T_true);
        EXPECT_LT(e.cwiseAbs().maxCoeff(), 0.5) << "roll, pitch error [deg] " << e.transpose();
        // Yaw is the ground's blind direction: it stays within a few tenths of the registration's.
        EXPECT_NEAR(RollPitchYaw(T.linear()).z(), 0.6, 0.01);
    }
}

TEST(GroundFactor, RefinementRefusesAnInconsistentPlane) {
    Drifted d;
    // A tight prior (0.2 deg) and a plane 3-4 deg away with 0.3 deg: a ridge, not drift.
    d.prior.covariance.bottomRightCorner<3, 3>() =
        std::pow(0.2 * kDeg, 2) * Eigen::Matrix3d::Identity();
    const RefinementOutput with = d.Refine(&d.ground);
    ASSERT_TRUE(with.usable);
    EXPECT_FALSE(with.ground_used);
    EXPECT_GT(RollPitchErrorDeg(with.T_world_base, d.T_true).cwiseAbs().maxCoeff(), 2.0);
}

}  // namespace
}  // namespace dorado::mapping
