// The fixed-lag smoother against independent truths: on a translation-only chain (where SE(3) is
// linear) its newest pose, its written poses and their motion covariances equal a dense batch
// least-squares solution of the same factors; on a drive with rotation and noise its written
// motions beat the prior's, and its written poses beat both the prior and the registrations.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/pose_smoother.hpp"

namespace dorado::mapping {
namespace {

// A translation-only problem: scan k at x_k; motion factors x_k - x_{k-1} = d_k (sigma_d),
// registrations x_k = z_k (sigma_z) on some scans; x_0 is held (the map's origin).
struct LinearChain {
    std::vector<Eigen::Vector3d> d, z;
    std::vector<bool> registered;
    double sigma_d = 0.05, sigma_z = 0.1;
    Eigen::Vector3d x0 = Eigen::Vector3d(1.0, -2.0, 0.5);
};

LinearChain MakeChain(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> unit(0.0, 1.0);
    LinearChain c;
    Eigen::Vector3d x = c.x0;
    for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d step(1.0, 0.1 * std::sin(k), 0.02);
        if (k > 0) x += step;
        c.d.push_back(step + c.sigma_d * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
        c.z.push_back(x + c.sigma_z * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
        c.registered.push_back(k % 4 != 2);  // every fourth scan has nothing to register
    }
    return c;
}

// Dense batch solution over scans 0..last: positions and their joint covariance.
struct Batch {
    Eigen::VectorXd x;
    Eigen::MatrixXd covariance;
};
Batch SolveBatch(const LinearChain &c, int last) {
    const int n = last + 1;
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(3 * n);
    const double w0 = 1e12, wd = 1.0 / (c.sigma_d * c.sigma_d), wz = 1.0 / (c.sigma_z * c.sigma_z);
    H.block<3, 3>(0, 0) += w0 * Eigen::Matrix3d::Identity();
    b.segment<3>(0) += w0 * c.x0;
    for (int k = 1; k < n; ++k) {
        H.block<3, 3>(3 * k, 3 * k) += wd * Eigen::Matrix3d::Identity();
        H.block<3, 3>(3 * k - 3, 3 * k - 3) += wd * Eigen::Matrix3d::Identity();
        H.block<3, 3>(3 * k, 3 * k - 3) -= wd * Eigen::Matrix3d::Identity();
        H.block<3, 3>(3 * k - 3, 3 * k) -= wd * Eigen::Matrix3d::Identity();
        b.segment<3>(3 * k) += wd * c.d[k];
        b.segment<3>(3 * k - 3) -= wd * c.d[k];
        if (c.registered[k]) {
            H.block<3, 3>(3 * k, 3 * k) += wz * Eigen::Matrix3d::Identity();
            b.segment<3>(3 * k) += wz * c.z[k];
        }
    }
    return {H.ldlt().solve(b), H.inverse()};
}

SmootherScan ScanOf(const LinearChain &c, int k, double dt) {
    SmootherScan scan;
    scan.stamp_ns = 1000 + k;
    scan.time_s = k * dt;
    scan.motion.translation() = k == 0 ? c.x0 : c.d[k];
    Matrix6d C = Matrix6d::Identity() * 1e-14;  // rotation held: it stays the identity
    C.topLeftCorner<3, 3>() = c.sigma_d * c.sigma_d * Eigen::Matrix3d::Identity();
    scan.motion_covariance = C;
    if (k > 0 && c.registered[k]) {
        Eigen::Isometry3d z = Eigen::Isometry3d::Identity();
        z.translation() = c.z[k];
        scan.T_world_base_registered = z;
        Matrix6d I = Matrix6d::Zero();  // translation only: the rotation is not observed
        I.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() / (c.sigma_z * c.sigma_z);
        scan.registration_information = I;
    }
    return scan;
}

TEST(PoseSmoother, NewestAndWrittenPosesAreTheBatchSolutionOfTheirData) {
    const int n = 40;
    const double dt = 0.1;
    const LinearChain c = MakeChain(n, 7);
    SmootherConfig config;
    config.lag_s = 0.45;  // 4 scans behind the newest
    PoseSmoother smoother(config);
    std::vector<SmoothedPose> written;
    std::vector<int> written_after;  // the newest scan when each pose was written
    for (int k = 0; k < n; ++k) {
        const Eigen::Isometry3d newest = smoother.Add(ScanOf(c, k, dt));
        const Batch batch = SolveBatch(c, k);
        EXPECT_LT((newest.translation() - batch.x.segment<3>(3 * k)).norm(), 1e-7) << k;
        EXPECT_LT(RotationAngle(newest.linear()), 1e-9);
        for (const SmoothedPose &p : smoother.TakeSmoothed()) {
            written.push_back(p);
            written_after.push_back(k);
        }
    }
    ASSERT_EQ(written.size(), static_cast<std::size_t>(n - 5));  // the last 5 are still held
    for (std::size_t i = 0; i < written.size(); ++i) {
        const int k = static_cast<int>(i);
        EXPECT_EQ(written[i].stamp_ns, 1000 + k);
        EXPECT_EQ(written_after[i], k + 5);  // 0.5 s > lag: written when scan k + 5 arrived
        const Batch batch = SolveBatch(c, written_after[i]);
        EXPECT_LT((written[i].T_world_base.translation() - batch.x.segment<3>(3 * k)).norm(), 1e-7)
            << k;
    }
    // Flushed: every remaining pose is the full batch's, with the batch's motion covariance
    // (the covariance of x_k - x_{k-1}, from the joint covariance at the time x_{k-1} left).
    const std::vector<SmoothedPose> rest = smoother.Flush();
    ASSERT_EQ(rest.size(), 5u);
    const Batch all = SolveBatch(c, n - 1);
    for (int j = 0; j < 5; ++j) {
        const int k = n - 5 + j;
        EXPECT_LT((rest[j].T_world_base.translation() - all.x.segment<3>(3 * k)).norm(), 1e-7);
        const Eigen::MatrixXd &S = all.covariance;
        const Eigen::Matrix3d motion =
            S.block<3, 3>(3 * k, 3 * k) + S.block<3, 3>(3 * k - 3, 3 * k - 3) -
            S.block<3, 3>(3 * k, 3 * k - 3) - S.block<3, 3>(3 * k - 3, 3 * k);
        // (each left after scan n - 1 was added: the full batch)
        EXPECT_LT((rest[j].motion_covariance.topLeftCorner<3, 3>() - motion).norm(),
                  1e-6 * motion.norm())
            << k;
    }
    EXPECT_TRUE(written.front().motion_covariance.isZero());  // the first scan: the origin
}

// A drive with turns: prior motions with noise in every axis, registrations with larger noise,
// as the Doppler prior and the scan-to-map registration are per frame. The written motions must
// beat the prior's, the written poses both the prior's dead reckoning and the registrations.
TEST(PoseSmoother, WrittenMotionsBeatThePriorAndPosesBeatBothInputs) {
    std::mt19937 rng(3);
    std::normal_distribution<double> unit(0.0, 1.0);
    auto noise = [&](const Vector6d &sigma) {
        Vector6d v;
        for (int i = 0; i < 6; ++i) v(i) = sigma(i) * unit(rng);
        return v;
    };
    const Vector6d sigma_prior = (Vector6d() << 0.02, 0.01, 0.01, 0.002, 0.002, 0.004).finished();
    const Vector6d sigma_reg = (Vector6d() << 0.05, 0.05, 0.05, 0.006, 0.006, 0.008).finished();
    SmootherConfig config;
    config.lag_s = 1.0;
    PoseSmoother smoother(config);
    std::vector<Eigen::Isometry3d> truth, dead_reckoning, registrations;
    std::vector<Eigen::Isometry3d> motions_prior;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity(), T_dr = T;
    const int n = 300;
    for (int k = 0; k < n; ++k) {
        const Vector6d xi =
            (Vector6d() << 1.0, 0.0, 0.0, 0.0, 0.01 * std::sin(0.05 * k), 0.05 * std::sin(0.02 * k))
                .finished();
        SmootherScan scan;
        scan.stamp_ns = k;
        scan.time_s = 0.1 * k;
        if (k > 0) {
            T = T * ExpSE3(xi);
            scan.motion = ExpSE3(xi) * ExpSE3(noise(sigma_prior));
            scan.motion_covariance = sigma_prior.cwiseAbs2().asDiagonal();
            T_dr = T_dr * scan.motion;
            const Eigen::Isometry3d z = T * ExpSE3(noise(sigma_reg));
            scan.T_world_base_registered = z;
            scan.registration_information = sigma_reg.cwiseAbs2().cwiseInverse().asDiagonal();
            registrations.push_back(z);
        } else {
            registrations.push_back(T);
        }
        truth.push_back(T);
        dead_reckoning.push_back(T_dr);
        motions_prior.push_back(scan.motion);
        smoother.Add(scan);
    }
    std::vector<SmoothedPose> written = smoother.TakeSmoothed();
    for (const SmoothedPose &p : smoother.Flush()) written.push_back(p);
    ASSERT_EQ(written.size(), static_cast<std::size_t>(n));
    double motion_prior = 0.0, motion_written = 0.0, pose_dr = 0.0, pose_reg = 0.0,
           pose_written = 0.0;
    double nees = 0.0;
    for (int k = 1; k < n; ++k) {
        const Eigen::Isometry3d true_motion = truth[k - 1].inverse() * truth[k];
        motion_prior += LogSE3(true_motion.inverse() * motions_prior[k]).squaredNorm();
        const Eigen::Isometry3d written_motion =
            written[k - 1].T_world_base.inverse() * written[k].T_world_base;
        const Vector6d e = LogSE3(true_motion.inverse() * written_motion);
        motion_written += e.squaredNorm();
        nees += e.dot(written[k].motion_covariance.ldlt().solve(e));
        pose_dr += LogSE3(truth[k].inverse() * dead_reckoning[k]).head<3>().squaredNorm();
        pose_reg += LogSE3(truth[k].inverse() * registrations[k]).head<3>().squaredNorm();
        pose_written +=
            LogSE3(truth[k].inverse() * written[k].T_world_base).head<3>().squaredNorm();
    }
    EXPECT_LT(motion_written, 0.9 * motion_prior);  // measured 0.83
    EXPECT_LT(pose_written, 0.5 * pose_reg);        // measured 0.12
    EXPECT_LT(pose_written, 0.1 * pose_dr);
    // Honest factors give an honest written covariance: mean NEES of 6 dof near 6.
    EXPECT_NEAR(nees / (n - 1), 6.0, 1.2);
}

// The mapper feeds the smoother's newest pose back: the next scan's prior is built from it
// (T_prior = T_newest D) and its motion taken back out (T_newest^-1 T_prior, an Isometry3d inverse,
// which transposes the rotation). The poses must stay rotations over a long drive: a rotation
// that leaves SO(3) by e is transposed into a motion off by about 2e and composed into a newest
// pose off by about 3e, so rounding errors would triple per scan and reach O(1) in ~33 scans (the
// drives of test_mapping_radar_mapper and test_mapping_planar diverge there). 100 scans of a
// turning drive, no registration, lag 0.3 s.
TEST(PoseSmoother, PosesStayRotationsWhenTheNewestIsFedBack) {
    SmootherConfig config;
    config.lag_s = 0.3;
    PoseSmoother smoother(config);
    Vector6d xi;
    xi << 0.75, 0.01, 0.002, 0.003, -0.002, 0.02;
    const Eigen::Isometry3d D = ExpSE3(xi);
    Eigen::Isometry3d newest = Eigen::Isometry3d::Identity(), truth = newest;
    double worst = 0.0;
    for (int k = 0; k < 100; ++k) {
        SmootherScan scan;
        scan.stamp_ns = k;
        scan.time_s = 0.1 * k;
        scan.motion_covariance = 1e-4 * Matrix6d::Identity();
        if (k > 0) {
            const Eigen::Isometry3d T_prior = newest * D;
            scan.motion = newest.inverse() * T_prior;
            truth = truth * D;
        }
        newest = smoother.Add(scan);
        const Eigen::Matrix3d R = newest.linear();
        worst = std::max(worst, (R.transpose() * R - Eigen::Matrix3d::Identity()).norm());
        ASSERT_LT(worst, 1e-9) << "scan " << k;
    }
    // With the prior alone the newest pose is the prior's chain.
    EXPECT_LT((newest.translation() - truth.translation()).norm(), 1e-6 * 75.0);
}

TEST(PoseSmoother, RejectsANegativeLag) {
    SmootherConfig config;
    config.lag_s = -1.0;
    EXPECT_THROW(PoseSmoother{config}, std::invalid_argument);
}

}  // namespace
}  // namespace dorado::mapping
