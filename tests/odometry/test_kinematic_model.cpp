// KinematicModel (eq. 3-5, 7) against a rigid-body forward model and finite differences.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "dorado/core/lie.hpp"
#include "dorado/odometry/kinematic_model.hpp"

namespace dorado::odometry {
namespace {

Extrinsics MakeExtrinsics() {
    Extrinsics e;
    e.T_base_radar.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    e.T_base_radar.translation() = Eigen::Vector3d(1.2, 0.15, 0.7);  // ahead, on a lever arm
    return e;
}

// Forward model: a twist that obeys the constraints (no roll, Z-ICR on the rear axle, Y-ICR at
// x = m) gives the radar velocity through v_s = v_base + omega x s (eq. 3), independently of
// the estimator's closed form.
Eigen::Vector3d RadarVelocity(const Extrinsics &e, const VehicleGeometry &g, double speed,
                              double pitch_rate, double yaw_rate, Eigen::Vector3d *v_base,
                              Eigen::Vector3d *omega) {
    *omega = Eigen::Vector3d(0.0, pitch_rate, yaw_rate);
    // Base origin (0,0,0): v_y = 0 (Z-ICR). Y-ICR point (m,0,0): v_z + (omega x (m,0,0))_z = 0.
    *v_base = Eigen::Vector3d(speed, 0.0, 0.0);
    v_base->z() = -omega->cross(Eigen::Vector3d(g.half_wheelbase_m, 0, 0)).z();
    const Eigen::Vector3d s = e.T_base_radar.translation();
    const Eigen::Vector3d v_s_base = *v_base + omega->cross(s);
    return e.T_base_radar.linear().transpose() * v_s_base;
}

TEST(KinematicModel, RecoversTheTwistOfAConstrainedVehicle) {
    const Extrinsics e = MakeExtrinsics();
    const VehicleGeometry g{0.256, KinematicModelNoise{}};
    const KinematicModel model(e, g);
    for (double yaw : {-0.8, 0.0, 0.5}) {
        for (double pitch : {-0.2, 0.0, 0.3}) {
            Eigen::Vector3d v_base, omega;
            const Eigen::Vector3d v_radar = RadarVelocity(e, g, 2.5, pitch, yaw, &v_base, &omega);
            const VehicleMotion m = model.Motion(v_radar, Eigen::Matrix3d::Identity());
            EXPECT_LT((m.omega_base_radps - omega).norm(), 1e-12) << yaw << " " << pitch;
            EXPECT_LT((m.v_base_mps - v_base).norm(), 1e-12);
        }
    }
}

TEST(KinematicModel, SignsMatchTheDerivation) {
    Extrinsics e;  // radar aligned with the base, 1 m ahead of the rear axle
    e.T_base_radar.translation() = Eigen::Vector3d(1.0, 0.0, 0.5);
    const KinematicModel model(e, VehicleGeometry{0.25, KinematicModelNoise{}});
    // Moving left at the radar, ahead of the rear axle: a left (counter-clockwise) turn.
    auto m = model.Motion(Eigen::Vector3d(2.0, 0.5, 0.0), Eigen::Matrix3d::Zero());
    EXPECT_DOUBLE_EQ(m.omega_base_radps.z(), 0.5);
    // Moving up at the radar, ahead of the Y-ICR (s_x > m): the nose rises, omega_y < 0.
    m = model.Motion(Eigen::Vector3d(2.0, 0.0, 0.3), Eigen::Matrix3d::Zero());
    EXPECT_DOUBLE_EQ(m.omega_base_radps.y(), 0.3 / (0.25 - 1.0));
    EXPECT_LT(m.omega_base_radps.y(), 0.0);
}

TEST(KinematicModel, CovarianceMatchesFiniteDifferenceJacobianAndEq7) {
    const Extrinsics e = MakeExtrinsics();
    const VehicleGeometry g{0.3, KinematicModelNoise{}};
    const KinematicModel model(e, g);
    const Eigen::Vector3d v0(3.0, 0.2, -0.1);
    Eigen::Matrix3d A = Eigen::Matrix3d::Random();
    const Eigen::Matrix3d C = A * A.transpose() * 0.01 + Eigen::Matrix3d::Identity() * 1e-4;
    Eigen::Matrix3d J_omega, J_v;
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d dv = Eigen::Vector3d::Zero();
        dv[k] = h;
        const auto plus = model.Motion(v0 + dv, C), minus = model.Motion(v0 - dv, C);
        J_omega.col(k) = (plus.omega_base_radps - minus.omega_base_radps) / (2 * h);
        J_v.col(k) = (plus.v_base_mps - minus.v_base_mps) / (2 * h);
    }
    const auto m = model.Motion(v0, C);
    EXPECT_LT((m.cov_omega_base - J_omega * C * J_omega.transpose()).norm(), 1e-8);
    EXPECT_LT((m.cov_v_base - J_v * C * J_v.transpose()).norm(), 1e-8);

    // eq. (7) in closed form, with C_v the covariance of v_s in the base frame.
    const Eigen::Matrix3d R = e.T_base_radar.linear();
    const Eigen::Matrix3d Cs = R * C * R.transpose();
    const double s_x = e.T_base_radar.translation().x(), mm = g.half_wheelbase_m;
    Eigen::Matrix3d eq7 = Eigen::Matrix3d::Zero();
    eq7(1, 1) = Cs(2, 2) / ((mm - s_x) * (mm - s_x));
    eq7(1, 2) = eq7(2, 1) = Cs(1, 2) / (s_x * mm - s_x * s_x);
    eq7(2, 2) = Cs(1, 1) / (s_x * s_x);
    EXPECT_LT((m.cov_omega_base - eq7).norm(), 1e-12);
}

TEST(KinematicModel, RejectsUnobservableMountings) {
    Extrinsics e;
    e.T_base_radar.translation() = Eigen::Vector3d(0.0, 0.0, 0.5);
    EXPECT_THROW(KinematicModel(e, VehicleGeometry{0.25, KinematicModelNoise{}}),
                 std::invalid_argument);
    e.T_base_radar.translation().x() = 0.25;
    EXPECT_THROW(KinematicModel(e, VehicleGeometry{0.25, KinematicModelNoise{}}),
                 std::invalid_argument);
}

// A vehicle that breaks all three constraints, simulated as a rigid body independently of the
// model's algebra: the rear-axle centre slides sideways (dy), the Y-ICR point moves vertically (dz)
// and the body rolls (omega_x). The model's estimate minus the truth, over many draws, must have
// the covariance the model reports (the violations enter linearly, so the match is exact up to
// sampling error).
TEST(KinematicModel, ModelCovarianceMatchesMonteCarloOfAVehicleBreakingTheConstraints) {
    const Extrinsics e = MakeExtrinsics();
    VehicleGeometry g{0.3, KinematicModelNoise{}};
    g.model_noise = {0.1, 0.005, 0.02, 0.05, 0.05, {0.5, 0.5, 1.5}};
    const KinematicModel model(e, g);
    const double speed = 6.0, pitch_rate = 0.05, yaw_rate = 0.4, m = g.half_wheelbase_m;
    const Eigen::Vector3d s = e.T_base_radar.translation();
    const Eigen::Matrix3d R = e.T_base_radar.linear();
    // The nominal (constraint-obeying) motion gives the reported model covariance.
    Eigen::Vector3d v_nominal, omega_nominal;
    const Eigen::Matrix<double, 6, 6> reported =
        model
            .Motion(RadarVelocity(e, g, speed, pitch_rate, yaw_rate, &v_nominal, &omega_nominal),
                    Eigen::Matrix3d::Zero())
            .cov_model;
    const auto &n = g.model_noise;
    const double sigma_y =
        std::hypot(n.sigma_icr_x_m * yaw_rate, n.rear_slip_rad_per_mps2 * speed * speed * yaw_rate,
                   n.sigma_lateral_mps);
    std::mt19937 rng(42);
    std::normal_distribution<double> gauss;
    const int trials = 200000;
    Eigen::Matrix<double, 6, 6> scatter = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
    for (int k = 0; k < trials; ++k) {
        const double dy = sigma_y * gauss(rng), dz = n.sigma_vertical_mps * gauss(rng);
        const Eigen::Vector3d omega(n.sigma_roll_rate_radps * gauss(rng), pitch_rate, yaw_rate);
        // Base origin on the rear axle: lateral velocity dy. Y-ICR point (m, 0, .): vertical
        // velocity dz, i.e. v_z + (omega x (m, 0, 0))_z = dz.
        const Eigen::Vector3d v_base(speed, dy, dz - omega.cross(Eigen::Vector3d(m, 0, 0)).z());
        const Eigen::Vector3d v_radar = R.transpose() * (v_base + omega.cross(s));
        const VehicleMotion est = model.Motion(v_radar, Eigen::Matrix3d::Zero());
        Eigen::Matrix<double, 6, 1> err;
        err << est.v_base_mps - v_base, est.omega_base_radps - omega;
        mean += err;
        scatter += err * err.transpose();
    }
    mean /= trials;
    const Eigen::Matrix<double, 6, 6> sample = scatter / trials - mean * mean.transpose();
    for (int i = 0; i < 6; ++i) {
        EXPECT_LT(std::abs(mean[i]), 0.01 * std::sqrt(reported(i, i))) << i;
        for (int j = 0; j < 6; ++j) {
            const double scale = std::sqrt(reported(i, i) * reported(j, j));
            EXPECT_LT(std::abs(sample(i, j) - reported(i, j)), 0.02 * scale)
                << "(" << i << "," << j << ") sample " << sample(i, j) << " reported "
                << reported(i, j);
        }
    }
    // Roll is the model's blind spot: its reported variance is the roll rate's.
    EXPECT_NEAR(reported(3, 3), n.sigma_roll_rate_radps * n.sigma_roll_rate_radps, 1e-15);
}

TEST(KinematicModel, ModelErrorGrowsWithYawRateAndSpeedAndVanishesWithoutNoise) {
    const Extrinsics e = MakeExtrinsics();
    VehicleGeometry g{0.3, KinematicModelNoise{}};
    const auto yaw_variance = [&](double speed, double yaw_rate) {
        Eigen::Vector3d v, w;
        return KinematicModel(e, g)
            .Motion(RadarVelocity(e, g, speed, 0.0, yaw_rate, &v, &w), Eigen::Matrix3d::Zero())
            .cov_model(5, 5);
    };
    const double straight = yaw_variance(5.0, 0.0), slow_turn = yaw_variance(2.0, 0.5),
                 fast_turn = yaw_variance(10.0, 0.5);
    EXPECT_GT(straight, 0.0);
    EXPECT_GT(slow_turn, straight);
    EXPECT_GT(fast_turn, 4.0 * slow_turn);
    g.model_noise = {0.0, 0.0, 0.0, 0.0, 0.0};
    EXPECT_EQ(yaw_variance(10.0, 0.5), 0.0);
}

// A radar 4.4 cm behind the Y-ICR axis (a side mount near mid-wheelbase): eq. (5) divides the
// vertical velocity by m - s_x, so its pitch rate is noise. With the vehicle's rates drawn from the
// angular-rate prior (a linear-Gaussian world), the plausible twist's error must have exactly the
// covariance it reports, and be far smaller than eq. (5)'s.
TEST(KinematicModel, PlausibleTwistCovarianceMatchesMonteCarloNearTheYIcrAxis) {
    Extrinsics e;
    e.T_base_radar.linear() = (Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(0.09, Eigen::Vector3d::UnitY()))
                                  .toRotationMatrix();
    e.T_base_radar.translation() = Eigen::Vector3d(0.30, -0.28, 0.50);
    VehicleGeometry g{0.256, KinematicModelNoise{}};
    g.model_noise = {0.0, 0.0, 0.0, 0.0, 0.0, {0.5, 0.4, 1.2}};
    const KinematicModel model(e, g);
    const Eigen::Matrix3d cov_v_radar = Eigen::Vector3d(1e-4, 4e-4, 9e-4).asDiagonal();
    const Eigen::Matrix3d L = cov_v_radar.llt().matrixL();
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss;
    const int trials = 100000;
    Eigen::Matrix<double, 6, 6> scatter = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 6> reported = Eigen::Matrix<double, 6, 6>::Zero();
    double raw_pitch_sq = 0.0;
    for (int k = 0; k < trials; ++k) {
        const double pitch_rate = 0.4 * gauss(rng), yaw_rate = 1.2 * gauss(rng);
        Eigen::Vector3d v_base, omega;
        const Eigen::Vector3d v_radar =
            RadarVelocity(e, g, 1.0 + gauss(rng), pitch_rate, yaw_rate, &v_base, &omega) +
            L * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
        const VehicleMotion motion = model.Motion(v_radar, cov_v_radar);
        const Twist twist = model.PlausibleTwist(motion);
        Eigen::Matrix<double, 6, 1> err;
        err << twist.v_base_mps - v_base, twist.omega_base_radps - omega;
        scatter += err * err.transpose();
        reported = twist.covariance;  // the same for every draw (fixed noise, no model error)
        raw_pitch_sq += std::pow(motion.omega_base_radps.y() - pitch_rate, 2);
    }
    const Eigen::Matrix<double, 6, 6> sample = scatter / trials;
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            const double scale = std::sqrt(reported(i, i) * reported(j, j));
            if (scale == 0.0) continue;  // roll: not estimated, not drawn
            EXPECT_LT(std::abs(sample(i, j) - reported(i, j)), 0.03 * scale)
                << "(" << i << "," << j << ") sample " << sample(i, j) << " reported "
                << reported(i, j);
        }
    }
    // eq. (5)'s pitch rate error is ~0.7 rad/s here; the plausible one is below the prior's 0.4.
    EXPECT_GT(std::sqrt(raw_pitch_sq / trials), 0.5);
    EXPECT_LT(std::sqrt(sample(4, 4)), 0.4);
}

// Where eq. (5) is well conditioned the prior barely moves the estimate.
TEST(KinematicModel, PlausibleTwistKeepsAWellObservedTwist) {
    const Extrinsics e = MakeExtrinsics();
    // Well observed: a stiff vehicle (model violations of mm/s) and a precise radar velocity give
    // rates to ~0.02 rad/s, ten times tighter than the prior's 0.2 rad/s spread of roll and pitch
    // rates. With the default violations (5 cm/s vertical over this mount's 0.94 m lever to the
    // Y-ICR) the pitch rate is known to ~0.06 rad/s only, and the prior rightly pulls it.
    KinematicModelNoise stiff;
    stiff.sigma_icr_x_m = 0.01;
    stiff.sigma_lateral_mps = 0.002;
    stiff.sigma_vertical_mps = 0.005;
    stiff.sigma_roll_rate_radps = 0.005;
    const VehicleGeometry g{0.256, stiff};
    const KinematicModel model(e, g);
    Eigen::Vector3d v_base, omega;
    const VehicleMotion motion = model.Motion(RadarVelocity(e, g, 5.0, 0.1, 0.4, &v_base, &omega),
                                              Eigen::Vector3d(1e-4, 1e-4, 4e-4).asDiagonal());
    const Twist twist = model.PlausibleTwist(motion);
    for (int i = 1; i < 3; ++i)
        EXPECT_NEAR(twist.omega_base_radps[i], omega[i], 0.05 * std::abs(omega[i])) << i;
    EXPECT_LT((twist.v_base_mps - v_base).norm(), 0.01);
    // Never more uncertain than before the prior.
    for (int i = 0; i < 6; ++i) {
        const double before =
            i < 3 ? (motion.cov_v_base + motion.cov_model.topLeftCorner<3, 3>())(i, i)
                  : (motion.cov_omega_base + motion.cov_model.bottomRightCorner<3, 3>())(i - 3,
                                                                                         i - 3);
        EXPECT_LE(twist.covariance(i, i), before + 1e-15) << i;
    }
}

}  // namespace
}  // namespace dorado::odometry
