// The mapper end to end on synthetic radar: dynamic masks keep movers out of the map, a one-wall
// scene falls back to the prior, and a short drive stays within a stated RPE (the written,
// smoothed poses, read after Finish).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <limits>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/testing/mapper_input.hpp"
#include "dorado/testing/street_scene.hpp"

namespace dorado::mapping {
namespace {
using testing::PriorInput;

using namespace testing;

Eigen::Isometry3d RadarMount() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(1.8, 0.0, 1.2);
    return T;
}

// A car-sized block of points (4 x 1.5 x 1 m) starting at `front`.
Eigen::Matrix3Xd CarPoints(const Eigen::Vector3d &front) {
    std::vector<Eigen::Vector3d> pts;
    for (double x = 0.0; x <= 4.0; x += 0.2)
        for (double y = 0.0; y <= 1.5; y += 0.25)
            for (double z = 0.0; z <= 1.0; z += 0.25)
                pts.push_back(front + Eigen::Vector3d(x, y, z));
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(pts.size()));
    for (std::size_t i = 0; i < pts.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = pts[i];
    return out;
}

Twist NoisyTwist(const TruthSample &truth, std::mt19937 &rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    Twist twist;
    twist.v_base_mps = truth.v_base + 0.03 * Eigen::Vector3d(n(rng), n(rng), n(rng));
    // Roll rate set to zero as the kinematic model does; pitch and yaw rates noisy.
    twist.omega_base_radps = Eigen::Vector3d(0.0, truth.omega_base.y() + 0.02 * n(rng),
                                             truth.omega_base.z() + 0.005 * n(rng));
    twist.covariance.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() * 0.03 * 0.03;
    twist.covariance.bottomRightCorner<3, 3>() =
        Eigen::Vector3d(0.0, 0.02 * 0.02, 0.005 * 0.005).asDiagonal();
    return twist;
}

struct DriveResult {
    double map_points_in_lane = 0;
    double mean_rpe_translation_m = 0;
    double mean_rpe_rotation_rad = 0;
    /// The mean distance of the poses from the truth (each pose against its own, the first pose
    /// the truth's), and of the rotations.
    double mean_ate_m = 0;
    double mean_ate_rad = 0;
    double prior_only_rpe_translation_m = 0;
    /// The last pose's error against the truth, of the mapper and of the Doppler prior's twists
    /// alone composed from the first pose (dead reckoning): what the map's lock removes.
    double final_error_m = 0;
    double final_error_rad = 0;
    double prior_only_final_error_m = 0;
    double prior_only_final_error_rad = 0;
    int fallbacks = 0;
    /// Over the scans after the first: the largest distance from a map point a scan added, taken
    /// back to the base frame by the scan's written pose, to the nearest of the scan's own points
    /// (zero when the map is built from the written poses), and the same taken back by the scan's
    /// newest (filtered) pose instead.
    double map_offset_from_output_m = 0;
    double map_offset_from_newest_m = 0;
    std::size_t written_poses = 0;
};

// The largest distance from a point of `added_world`, taken back to the base frame by
// T_world_base, to the nearest of the scan's own points.
double MapOffset(const Eigen::Matrix3Xd &added_world, const Eigen::Isometry3d &T_world_base,
                 const RadarScan &scan, const Eigen::Isometry3d &T_base_radar) {
    double offset = 0.0;
    for (Eigen::Index i = 0; i < added_world.cols(); ++i) {
        const Eigen::Vector3d p_base = T_world_base.inverse() * added_world.col(i);
        double nearest = std::numeric_limits<double>::infinity();
        for (Eigen::Index j = 0; j < scan.size(); ++j)
            nearest = std::min(
                nearest, (T_base_radar * Eigen::Vector3d(scan.xyz_radar.col(j)) - p_base).norm());
        offset = std::max(offset, nearest);
    }
    return offset;
}

// What the mapper is told of the moving car: nothing (every point static), the truth, or a leaky
// Doppler mask that flags one car point in ten as moving and passes the rest as static (what a
// car crossing the beam, or a crowd moving together, looks like to the Doppler mask).
enum class Mask { kNone, kTrue, kLeaky };

// Drives `scans` scans down the street with a car overtaking in the next lane; the prior is the
// truth's twist with Doppler-odometry-like noise.
DriveResult Drive(int scans, Mask mask, const MapperConfig &config) {
    const Eigen::Matrix3Xd world = MakeStreetWorld(5);
    const auto truth = MakeDrive(scans, 0.1);
    std::mt19937 rng(21);
    RadarSimOptions sim;
    sim.points_per_scan = 3000;
    sim.angle_sigma_rad = 0.002;
    Extrinsics extrinsics;
    extrinsics.T_base_radar = RadarMount();
    RadarMapper mapper(config, extrinsics);
    PriorNoiseConfig noise;

    const Eigen::Vector3d v_car(12.0, 0.0, 0.0);
    // The newest (filtered) poses, which the next prior starts from, and the written ones.
    std::vector<Eigen::Isometry3d> newest;
    std::vector<WrittenPose> written;
    std::vector<RadarScan> scans_seen;
    Eigen::Isometry3d dead_reckoning = Eigen::Isometry3d::Identity();
    DriveResult out;
    double prior_error_sum = 0.0;
    for (int k = 0; k < scans; ++k) {
        const double t = truth[k].t;
        // The overtaking car (x from 4 to 40 m over the drive): in the lane y in [-2.5, -1], 0.5 m
        // above the road.
        const Eigen::Matrix3Xd car = CarPoints(Eigen::Vector3d(4.0 + v_car.x() * t, -2.5, 0.5));
        Eigen::Array<bool, Eigen::Dynamic, 1> is_static;
        const RadarScan scan =
            SimulateScan(world, truth[k].T_world_base, extrinsics.T_base_radar, truth[k].v_base,
                         truth[k].omega_base, car, v_car, sim, rng, &is_static);
        MotionPrior prior;
        if (k == 0) {
            prior.T_world_base = truth[0].T_world_base;
        } else {
            const TruthSample &previous = truth[k - 1];
            prior = PriorFromDoppler(newest.back(), NoisyTwist(previous, rng), 0.1, noise);
            const Eigen::Isometry3d step = newest.back().inverse() * prior.T_world_base;
            dead_reckoning = dead_reckoning * step;
            const Eigen::Isometry3d true_step =
                previous.T_world_base.inverse() * truth[k].T_world_base;
            prior_error_sum += (true_step.inverse() * step).translation().norm();
        }
        MapperInput input;
        input.prior = prior;
        input.dt_s = 0.1;
        if (mask == Mask::kTrue) input.static_mask = is_static;
        if (mask == Mask::kLeaky) {
            input.static_mask = PointMask::Constant(scan.size(), true);
            input.moving_mask = PointMask::Constant(scan.size(), false);
            int car_point = 0;
            for (Eigen::Index i = 0; i < scan.size(); ++i)
                if (!is_static(i) && car_point++ % 10 == 0) {
                    input.moving_mask(i) = true;
                    input.static_mask(i) = false;
                }
        }
        RegistrationResult r = mapper.Register(scan, input);
        if (getenv("DEBUG_MAPPER"))
            std::printf("scan %d: fb %d %s corr %d rms %.3f obs %.4f mah %.1f thr %.2f err %.3f\n",
                        k, r.fallback(), ToString(r.fallback_cause), r.correspondences,
                        r.fitness_rms_m, r.observability, r.prior_mahalanobis_squared,
                        r.threshold_m,
                        (truth[k].T_world_base.inverse() * r.T_world_base).translation().norm());
        // The pose's covariance: the stiff anchor's (1e-12) at the map's origin, positive
        // definite after it.
        if (k == 0)
            EXPECT_LT(r.covariance.cwiseAbs().maxCoeff(), 1e-9);
        else
            EXPECT_GT(
                Eigen::SelfAdjointEigenSolver<Matrix6d>(r.covariance).eigenvalues().minCoeff(), 0.0)
                << "scan " << k;
        newest.push_back(r.T_world_base);
        scans_seen.push_back(scan);
        for (WrittenPose &pose : r.written) written.push_back(std::move(pose));
    }
    for (WrittenPose &pose : mapper.Finish()) written.push_back(std::move(pose));
    // One written pose per scan, in scan order, each scan's points in the map at it.
    out.written_poses = written.size();
    EXPECT_EQ(written.size(), static_cast<std::size_t>(scans));
    if (written.size() != static_cast<std::size_t>(scans)) return out;
    std::vector<Eigen::Isometry3d> estimated;
    for (int k = 0; k < scans; ++k) {
        EXPECT_EQ(written[k].stamp_ns, scans_seen[k].stamp_ns) << k;
        estimated.push_back(written[k].T_world_base);
        if (k == 0) continue;
        const Eigen::Matrix3Xd &added = written[k].map_points_added_world;
        out.map_offset_from_output_m =
            std::max(out.map_offset_from_output_m,
                     MapOffset(added, written[k].T_world_base, scans_seen[k], extrinsics.T_base_radar));
        out.map_offset_from_newest_m =
            std::max(out.map_offset_from_newest_m,
                     MapOffset(added, newest[k], scans_seen[k], extrinsics.T_base_radar));
    }
    for (int k = 1; k < scans; ++k) {
        const Eigen::Isometry3d true_step =
            truth[k - 1].T_world_base.inverse() * truth[k].T_world_base;
        const Eigen::Isometry3d step = estimated[k - 1].inverse() * estimated[k];
        const Eigen::Isometry3d e = true_step.inverse() * step;
        out.mean_rpe_translation_m += e.translation().norm() / (scans - 1);
        out.mean_rpe_rotation_rad += RotationAngle(e.linear()) / (scans - 1);
        const Eigen::Isometry3d a = truth[k].T_world_base.inverse() * estimated[k];
        out.mean_ate_m += a.translation().norm() / (scans - 1);
        out.mean_ate_rad += RotationAngle(a.linear()) / (scans - 1);
    }
    out.prior_only_rpe_translation_m = prior_error_sum / (scans - 1);
    const Eigen::Isometry3d error = truth[scans - 1].T_world_base.inverse() * estimated.back();
    const Eigen::Isometry3d prior_error =
        truth[scans - 1].T_world_base.inverse() * truth[0].T_world_base * dead_reckoning;
    out.final_error_m = error.translation().norm();
    out.final_error_rad = RotationAngle(error.linear());
    out.prior_only_final_error_m = prior_error.translation().norm();
    out.prior_only_final_error_rad = RotationAngle(prior_error.linear());
    const Eigen::Matrix3Xd map = mapper.local_map().Points();
    for (Eigen::Index i = 0; i < map.cols(); ++i) {
        const Eigen::Vector3d p = map.col(i);
        if (p.x() > 0.0 && p.x() < 40.0 && p.y() > -2.4 && p.y() < -1.1 && p.z() > 0.6 &&
            p.z() < 1.4) {
            ++out.map_points_in_lane;
            if (getenv("DEBUG_MAPPER") && out.map_points_in_lane < 10)
                std::printf("lane point %.2f %.2f %.2f\n", p.x(), p.y(), p.z());
        }
    }
    out.fallbacks = mapper.fallbacks();
    return out;
}

DriveResult Drive(int scans, bool use_mask, const MapperConfig &config) {
    return Drive(scans, use_mask ? Mask::kTrue : Mask::kNone, config);
}

DriveResult Drive(int scans, bool use_mask) {
    return Drive(scans, use_mask, MapperConfig{});
}

// One scan's input: the prior and the interval, no masks.
TEST(RadarMapper, MaskKeepsTheMovingCarOutOfTheMap) {
    const DriveResult without = Drive(15, false);
    const DriveResult with = Drive(15, true);
    EXPECT_GT(without.map_points_in_lane, 20) << "the car should be in an unmasked map";
    EXPECT_LE(with.map_points_in_lane, 2) << "the mask should keep the car out";
}

// The mover rules (movers.hpp) on a mask that flags one car point in ten: the neighbours of a
// flagged point and the cells where one was seen stay out of the map. Without the rules the
// car's passed-as-static points fill its lane.
TEST(RadarMapper, MoverRulesKeepALeakilyMaskedCarOutOfTheMap) {
    MapperConfig config;
    config.movers.neighbour_radius_m = 1.0;  // both rules (each is off by default)
    config.movers.memory_s = 2.0;
    MapperConfig off = config;
    off.movers.neighbour_radius_m = 0.0;
    off.movers.memory_s = 0.0;
    const DriveResult without = Drive(15, Mask::kLeaky, off);
    const DriveResult with = Drive(15, Mask::kLeaky, config);
    MapperConfig neighbours_only = config;
    neighbours_only.movers.memory_s = 0.0;
    MapperConfig memory_only = config;
    memory_only.movers.neighbour_radius_m = 0.0;
    const double neighbours = Drive(15, Mask::kLeaky, neighbours_only).map_points_in_lane;
    const double memory = Drive(15, Mask::kLeaky, memory_only).map_points_in_lane;
    std::printf(
        "car points in the map: %.0f without the rules, %.0f with, %.0f neighbours only, "
        "%.0f memory only\n",
        without.map_points_in_lane, with.map_points_in_lane, neighbours, memory);
    EXPECT_GT(without.map_points_in_lane, 20) << "the leaky mask lets the car into the map";
    EXPECT_LE(with.map_points_in_lane, 0.2 * without.map_points_in_lane)
        << "the mover rules should keep most of the car out";
    // Each rule alone catches part of it.
    EXPECT_LT(neighbours, 0.3 * without.map_points_in_lane);
    EXPECT_LT(memory, 0.3 * without.map_points_in_lane);
}

TEST(RadarMapper, ShortDriveStaysWithinStatedRpe) {
    const DriveResult r = Drive(40, true);
    std::printf("RPE per frame: %.4f m, %.4f deg; Doppler prior alone %.4f m; fallbacks %d\n",
                r.mean_rpe_translation_m, RadToDeg(r.mean_rpe_rotation_rad),
                r.prior_only_rpe_translation_m, r.fallbacks);
    std::printf("last pose error: %.4f m, %.4f deg; Doppler prior alone %.4f m, %.4f deg\n",
                r.final_error_m, RadToDeg(r.final_error_rad), r.prior_only_final_error_m,
                RadToDeg(r.prior_only_final_error_rad));
    // Stated accuracy on this sequence (7.5 m/s, 0.75 m per frame): 1 cm and 0.15 deg per frame
    // (measured 5.3 mm, 0.12 deg), and no worse than the Doppler prior it starts from: fused by
    // their information, the registration (cm-noisy per frame) moves the translation little
    // (measured 5.333 vs 5.328 mm; it was 3.7 mm when its residuals were over-counted, at a cost
    // in rotation on the simulated drives, docs/covariance.md).
    EXPECT_LT(r.mean_rpe_translation_m, 0.01);
    EXPECT_LT(r.mean_rpe_translation_m, 1.02 * r.prior_only_rpe_translation_m);
    EXPECT_LT(r.mean_rpe_rotation_rad, DegToRad(0.15));
    EXPECT_EQ(r.fallbacks, 0);
    // What the registration adds: the map holds the pose where the prior's twists alone drift.
    // Measured after 40 scans (30 m): 0.074 m, 0.16 deg against 0.277 m, 0.87 deg (0.092 m,
    // 0.40 deg before the smoother); with the registration taken out of the output, the two are
    // equal and this fails.
    EXPECT_LT(r.final_error_m, 0.5 * r.prior_only_final_error_m);
    EXPECT_LT(r.final_error_rad, 0.75 * r.prior_only_final_error_rad);
}

// The smoother's purpose on the same drive: the written poses, smoothed by the scans on both
// sides of them (lag 1 s), are closer to the truth than the same estimator written at once (lag 0,
// a filter), at the stated accuracy. Measured: mean error 0.0500 m, 0.800 deg against 0.0515 m,
// 0.884 deg. Per frame the two are the Doppler prior's (RPE 5.26 mm, 0.1065 deg against 5.22 mm,
// 0.1041 deg): the relative motion is not where the smoothing helps, so per frame the smoothed
// poses are only held within 5 % of the filtered.
TEST(RadarMapper, SmoothedPosesBeatTheFilteredOnTheShortDrive) {
    MapperConfig filter;
    filter.smoother.lag_s = 0.0;
    const DriveResult smoothed = Drive(40, true, MapperConfig{});
    const DriveResult filtered = Drive(40, true, filter);
    std::printf("smoothed RPE per frame: %.4f m, %.4f deg (filtered %.4f m, %.4f deg); fallbacks %d\n",
                smoothed.mean_rpe_translation_m, RadToDeg(smoothed.mean_rpe_rotation_rad),
                filtered.mean_rpe_translation_m, RadToDeg(filtered.mean_rpe_rotation_rad),
                smoothed.fallbacks);
    std::printf("smoothed mean error: %.4f m, %.4f deg (filtered %.4f m, %.4f deg)\n",
                smoothed.mean_ate_m, RadToDeg(smoothed.mean_ate_rad), filtered.mean_ate_m,
                RadToDeg(filtered.mean_ate_rad));
    EXPECT_LT(smoothed.mean_rpe_translation_m, 0.01);
    EXPECT_LT(smoothed.mean_rpe_rotation_rad, DegToRad(0.15));
    EXPECT_EQ(smoothed.fallbacks, 0);
    EXPECT_LT(smoothed.mean_ate_m, filtered.mean_ate_m);
    EXPECT_LT(smoothed.mean_ate_rad, filtered.mean_ate_rad);
    EXPECT_LT(smoothed.mean_rpe_translation_m, 1.05 * filtered.mean_rpe_translation_m);
    EXPECT_LT(smoothed.mean_rpe_rotation_rad, 1.05 * filtered.mean_rpe_rotation_rad);
}

// One chain: every scan enters the map at its written pose (the map offset from it is rounding);
// taken back by the newest, filtered pose instead, the points are millimetres to centimetres off
// (the smoothing's correction, so the check can fail). 25 scans: the property does not depend on
// the drive's length.
TEST(RadarMapper, TheMapIsBuiltFromTheWrittenPoses) {
    const DriveResult r = Drive(25, true, MapperConfig{});
    std::printf("map offset from the written poses %.2e m, from the newest %.2e m\n",
                r.map_offset_from_output_m, r.map_offset_from_newest_m);
    EXPECT_EQ(r.written_poses, 25u);
    EXPECT_LT(r.map_offset_from_output_m, 1e-6);
    EXPECT_GT(r.map_offset_from_newest_m, 1e-4);
}

TEST(RadarMapper, OneWallFallsBackToThePrior) {
    // A single wall 20 m ahead: the translation along it and the rotation about its normal are
    // not observed.
    std::vector<Eigen::Vector3d> wall;
    for (double y = -30.0; y <= 30.0; y += 0.2)
        for (double z = -2.0; z <= 6.0; z += 0.2) wall.emplace_back(20.0, y, z);
    Eigen::Matrix3Xd world(3, static_cast<Eigen::Index>(wall.size()));
    for (std::size_t i = 0; i < wall.size(); ++i) world.col(static_cast<Eigen::Index>(i)) = wall[i];
    std::mt19937 rng(4);
    RadarSimOptions sim;
    sim.ghost_fraction = 0.0;
    sim.angle_sigma_rad = 0.003;  // 6-10 cm across the wall
    Extrinsics extrinsics;
    extrinsics.T_base_radar = RadarMount();
    RadarMapper mapper(MapperConfig{}, extrinsics);
    const Eigen::Matrix3Xd none(3, 0);
    const Eigen::Vector3d v(0.0, 3.0, 0.0);  // sliding along the wall
    const RadarScan first =
        SimulateScan(world, Eigen::Isometry3d::Identity(), extrinsics.T_base_radar, v,
                     Eigen::Vector3d::Zero(), none, Eigen::Vector3d::Zero(), sim, rng, nullptr);
    MotionPrior prior;
    prior.covariance = Matrix6d::Identity() * 0.01;
    ASSERT_TRUE(mapper.Register(first, PriorInput(prior, 0.1)).first_scan);

    const Eigen::Isometry3d T_true(Eigen::Translation3d(0.0, 0.3, 0.0));
    const RadarScan second =
        SimulateScan(world, T_true, extrinsics.T_base_radar, v, Eigen::Vector3d::Zero(), none,
                     Eigen::Vector3d::Zero(), sim, rng, nullptr);
    prior.T_world_base = Eigen::Isometry3d(Eigen::Translation3d(0.01, 0.25, 0.0));
    const RegistrationResult r = mapper.Register(second, PriorInput(prior, 0.1));
    EXPECT_TRUE(r.fallback());
    EXPECT_EQ(r.fallback_cause, FallbackCause::kDegenerate) << ToString(r.fallback_cause);
    EXPECT_TRUE(r.T_world_base.isApprox(prior.T_world_base));
    // The prior's, as its pose, plus the origin's (the smoother's stiff anchor, 1e-12).
    EXPECT_LT((r.covariance - prior.covariance).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT(r.observability, MapperConfig{}.min_observability);
    std::printf("one wall: observability %.5f\n", r.observability);
    EXPECT_EQ(mapper.fallbacks(), 1);
}

}  // namespace
}  // namespace dorado::mapping
