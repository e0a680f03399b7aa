// The real TI IWR6843AOP + ADIS16448 hand-held recording (christopherdoer/rio's ti_mmwave_rospkg
// demo, GPL-3.0, read from ../shared/data/real/; skipped with a message where it is absent). No
// ground truth: every assertion is one the data itself can check (docs/real_recordings.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "dorado/core/angles.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/odometry/inertial_check.hpp"

namespace dorado {
namespace {

const std::string kConfig = std::string(DORADO_SOURCE_DIR) + "/configs/ti_mmwave.yaml";

struct ScanRecord {
    int64_t stamp_ns = 0;
    RadarScan scan;
    frontend::FrontEndResult result;
};

// The whole recording through the odometry (imu+doppler, default settings), once.
struct RecordingRun {
    io::DatasetConfig dataset;
    std::vector<ScanRecord> scans;
    std::vector<ImuSample> imu;
    std::size_t bad_scans = 0;
};

const RecordingRun *RealRun() {
    static std::unique_ptr<RecordingRun> run;
    if (run) return run.get();
    run = std::make_unique<RecordingRun>();
    run->dataset = io::LoadDatasetConfig(kConfig);
    frontend::FrontEndConfig config;
    config.run_mapper = false;
    config.odometry.method = odometry::OdometryMethod::kImuDoppler;
    config.odometry.ego_velocity.sensor = run->dataset.radar;
    frontend::RadarFrontEnd front_end(config, run->dataset.extrinsics, run->dataset.vehicle);
    auto reader = io::OpenDataset(run->dataset);
    io::DatasetEvent event;
    while (reader->Next(event)) {
        if (event.kind == io::DatasetEvent::Kind::kImu) {
            front_end.AddImu(event.imu);
            run->imu.push_back(event.imu);
        } else if (event.kind == io::DatasetEvent::Kind::kBadScan) {
            ++run->bad_scans;
        } else if (event.kind == io::DatasetEvent::Kind::kRadarScan) {
            ScanRecord record{event.stamp_ns, event.scan, front_end.Process(event.scan)};
            run->scans.push_back(std::move(record));
        }
    }
    return run.get();
}

class RealRecording : public ::testing::Test {
  protected:
    void SetUp() override {
        const std::string bag = std::string(DORADO_SOURCE_DIR) +
                                "/../shared/data/real/ti_mmwave_demo/ti_mmwave_rospkg_demo.bag";
        if (!std::filesystem::exists(bag))
            GTEST_SKIP() << "the real recording is absent (" << bag
                         << "): see docs/real_recordings.md for where it comes from";
        run_ = RealRun();
    }
    const RecordingRun *run_ = nullptr;
};

double Median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// Every scan is stamped from its trigger, and >= 95 % have a valid ego-velocity and their own
// twist (the gyro in every interval): before the trigger stamps, no interval had a gyro sample.
TEST_F(RealRecording, NearlyEveryScanHasAValidVelocityAndTheGyro) {
    ASSERT_EQ(run_->scans.size() + run_->bad_scans, 412u);
    EXPECT_LE(run_->bad_scans, 1u);  // the first scan may come before any trigger
    std::size_t valid = 0, fallbacks = 0, with_gyro = 0;
    for (const auto &s : run_->scans) {
        const auto &step = s.result.odometry;
        valid += step.ego.valid();
        fallbacks += step.used_fallback;
        with_gyro += s.result.gyro_base_radps.allFinite();
        // A fallback always has a cause.
        EXPECT_EQ(step.used_fallback, step.fallback_cause != odometry::FallbackCause::kNone);
    }
    const double n = static_cast<double>(run_->scans.size());
    EXPECT_GE(valid / n, 0.95);
    EXPECT_LE(fallbacks / n, 0.05);
    EXPECT_GE(with_gyro, run_->scans.size() - 1);  // all but the first scan
}

// The static points' Doppler residuals on moving scans: their robust scale (1.4826 MAD) against
// the configured doppler_sigma_mps (0.05). The driver quantises the Doppler in 0.1249 m/s steps,
// whose uniform error alone has a robust scale of 1.4826 * 0.1249 / 4 = 0.046 m/s.
TEST_F(RealRecording, StaticDopplerResidualsMatchTheConfiguredSigma) {
    std::vector<double> residuals;
    for (const auto &s : run_->scans) {
        const auto &ego = s.result.odometry.ego;
        if (!ego.valid() || ego.v_radar_mps.norm() < 0.3) continue;
        for (Eigen::Index i = 0; i < s.scan.size(); ++i) {
            if (ego.labels[i] != odometry::PointLabel::kStatic) continue;
            const Eigen::Vector3d d = s.scan.xyz_radar.col(i).normalized();
            residuals.push_back(-s.scan.doppler_mps[i] - d.dot(ego.v_radar_mps));  // eq. (1)
        }
    }
    ASSERT_GT(residuals.size(), 3000u);
    const double med = Median(residuals);
    for (double &r : residuals) r = std::abs(r - med);
    const double scale = 1.4826 * Median(residuals);
    const double sigma = odometry::EgoVelocityConfig{}.doppler_sigma_mps;
    RecordProperty("robust_scale_mps", std::to_string(scale));
    EXPECT_GT(scale, 0.5 * sigma);
    EXPECT_LT(scale, 1.5 * sigma);
    EXPECT_LT(std::abs(med), 0.02);
}

// The Doppler velocity against the IMU: over 0.5 s windows the velocity change (rotated by the
// integrated gyro, lever arm from the gyro) equals the accelerometer's integral with slope ~1;
// with every Doppler negated the slope is ~-1 (the sign the data says), and with the calibration
// file's rotation taken as is (not turned 180 deg about X) the two do not agree at all.
TEST_F(RealRecording, DopplerVelocityFollowsTheAccelerometer) {
    std::vector<odometry::StampedRadarVelocity> velocities;
    for (const auto &s : run_->scans)
        if (s.result.odometry.ego.valid())
            velocities.push_back(
                odometry::StampedRadarVelocity{s.stamp_ns, s.result.odometry.ego.v_radar_mps});
    const odometry::InertialCheck check =
        odometry::CompareWithImu(velocities, run_->imu, run_->dataset.extrinsics);
    RecordProperty("slope", std::to_string(check.as_given.slope));
    RecordProperty("rms_residual_mps", std::to_string(check.as_given.rms_residual_mps));
    ASSERT_GE(check.as_given.windows, 150);
    EXPECT_EQ(check.doppler_sign, 1);
    EXPECT_NEAR(check.as_given.slope, 1.0, 0.1);
    EXPECT_LT(check.as_given.rms_residual_mps, 0.3 * check.as_given.rms_delta_v_mps);
    EXPECT_LT(check.flipped.slope, -0.8);
    EXPECT_GT(check.flipped.rms_residual_mps, 3.0 * check.as_given.rms_residual_mps);
    // The shipped rotation is the fitted one (configs/ti_mmwave.yaml): nothing left to correct.
    EXPECT_LT(check.rotation_correction_base_rad.norm(), DegToRad(1.0));

    Extrinsics as_in_file = run_->dataset.extrinsics;
    as_in_file.T_base_radar.linear() =
        Eigen::Quaterniond(-0.0746967504749, 0.923218461092, 0.375992995522, -0.0267831268675)
            .normalized()
            .toRotationMatrix();
    const auto wrong = odometry::CompareWithImu(velocities, run_->imu, as_in_file);
    EXPECT_LT(std::abs(wrong.as_given.slope), 0.3);
    // The file's rotation turned 180 deg about X, before the fit: a 7.9 deg correction.
    as_in_file.T_base_radar.linear() =
        Eigen::Quaterniond(-0.0746967504749, 0.923218461092, -0.375992995522, 0.0267831268675)
            .toRotationMatrix();
    const auto conjugated = odometry::CompareWithImu(velocities, run_->imu, as_in_file);
    EXPECT_NEAR(RadToDeg(conjugated.rotation_correction_base_rad.norm()), 7.9, 1.0);
}

// The rig rests for the first ~13 s: the gyro is quiet, every scan is stationary (the driver
// reports zero Doppler for every point) and the zero-velocity update keeps the pose at the origin.
TEST_F(RealRecording, StationaryStartStaysAtTheOrigin) {
    const int64_t t0 = run_->scans.front().stamp_ns;
    int at_rest = 0;
    for (const auto &s : run_->scans) {
        if (s.stamp_ns - t0 > 10'000'000'000) break;
        EXPECT_TRUE(s.result.odometry.ego.valid());
        EXPECT_TRUE(s.result.odometry.zero_velocity_update);
        if (s.result.gyro_base_radps.allFinite()) {
            EXPECT_LT(s.result.gyro_base_radps.norm(), 0.02);  // bias-corrected, at rest
        }
        EXPECT_LT(s.result.T_world_base.translation().norm(), 1e-9);
        ++at_rest;
    }
    EXPECT_GE(at_rest, 95);
}

}  // namespace
}  // namespace dorado
