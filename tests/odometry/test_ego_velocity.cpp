// EgoVelocityEstimator against synthetic scenes with known truth (see
// dorado/testing/doppler_scan.hpp).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <set>
#include <string>

#include "dorado/core/angles.hpp"
#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/testing/doppler_scan.hpp"
#include "robust_fit.hpp"

namespace dorado::odometry {
namespace {

using testing::MakeScan;
using testing::SceneOptions;
using testing::SyntheticScan;

struct MaskQuality {
    double precision = 0.0;  ///< of the dynamic label
    double recall = 0.0;     ///< over dynamic points whose Doppler differs from a static one's
};

// Precision and recall of the dynamic label. A moving point whose motion is perpendicular to its
// line of sight is indistinguishable from a static one: recall counts only the points whose
// Doppler departs from the static model by more than 4 sigma_i.
MaskQuality Quality(const SyntheticScan &s, const EgoVelocityResult &r, const Eigen::Vector3d &v) {
    int true_pos = 0, labelled_dynamic = 0, detectable = 0, detected = 0;
    for (Eigen::Index i = 0; i < s.scan.size(); ++i) {
        const bool labelled = r.labels[i] == PointLabel::kDynamic;
        const double departure = std::abs(s.scan.doppler_mps[i] + s.directions.col(i).dot(v));
        labelled_dynamic += labelled;
        true_pos += labelled && s.dynamic[i];
        if (s.dynamic[i] && departure > 4.0 * s.sigma_mps[i]) {
            ++detectable;
            detected += labelled;
        }
    }
    MaskQuality q;
    q.precision = labelled_dynamic ? static_cast<double>(true_pos) / labelled_dynamic : 1.0;
    q.recall = detectable ? static_cast<double>(detected) / detectable : 1.0;
    return q;
}

TEST(EgoVelocity, NoiseFreeStaticSceneIsRecoveredExactly) {
    SceneOptions o;
    o.doppler_sigma_mps = 0.0;
    o.v_radar = Eigen::Vector3d(3.0, -1.0, 0.5);
    for (auto method : {RobustMethod::kRansac, RobustMethod::kTrimmedIrls, RobustMethod::kNone}) {
        EgoVelocityConfig c;
        c.method = method;
        c.trim_mode = TrimMode::kFixed;
        c.trim_value = 0.1;
        EgoVelocityEstimator estimator(c);
        const auto r = estimator.Estimate(MakeScan(o).scan);
        ASSERT_TRUE(r.valid()) << Describe(r);
        EXPECT_LT((r.v_radar_mps - o.v_radar).norm(), 1e-9);
        EXPECT_EQ(r.inliers, o.points);
        EXPECT_FALSE(r.stationary);
    }
}

// With Gaussian Doppler noise the reported covariance must match the spread of the estimates:
// the mean normalised squared error e^T C^-1 e over trials is 3 (chi-square, 3 dof), and the
// per-axis sample variances match the mean reported ones.
void CheckCovarianceHonesty(CovarianceModel model, bool heteroscedastic, bool use_power) {
    EgoVelocityConfig c;
    c.covariance = model;
    c.use_power = use_power;
    EgoVelocityEstimator estimator(c);
    const int trials = 400;
    Eigen::Matrix3d sample = Eigen::Matrix3d::Zero(), reported = Eigen::Matrix3d::Zero();
    double nees = 0.0;
    SceneOptions o;
    o.points = 1500;
    o.heteroscedastic = heteroscedastic;
    o.dynamic_fraction = 0.0;
    for (int t = 0; t < trials; ++t) {
        o.seed = 1000 + t;
        const auto r = estimator.Estimate(MakeScan(o).scan);
        ASSERT_TRUE(r.valid()) << Describe(r);
        const Eigen::Vector3d e = r.v_radar_mps - o.v_radar;
        sample += e * e.transpose() / trials;
        reported += r.cov_v_radar / trials;
        nees += e.dot(r.cov_v_radar.ldlt().solve(e)) / trials;
    }
    std::printf(
        "covariance %s, %s noise, %s weights: NEES %.3f (expect 3), sample/reported "
        "variance x %.3f y %.3f z %.3f\n",
        model == CovarianceModel::kSandwich ? "sandwich" : "eq. 6",
        heteroscedastic ? "power-dependent" : "uniform", use_power ? "SNR" : "unit", nees,
        sample(0, 0) / reported(0, 0), sample(1, 1) / reported(1, 1),
        sample(2, 2) / reported(2, 2));
    // NEES mean over 400 trials has a standard deviation of sqrt(6 / 400) = 0.12.
    EXPECT_NEAR(nees, 3.0, 0.45);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(sample(k, k) / reported(k, k), 1.0, 0.25) << "axis " << k;
}

TEST(EgoVelocity, Eq6CovarianceIsHonestWhenWeightsMatchTheNoise) {
    CheckCovarianceHonesty(CovarianceModel::kResidualScaled, true, true);
    CheckCovarianceHonesty(CovarianceModel::kResidualScaled, false, false);
}

TEST(EgoVelocity, SandwichCovarianceIsHonestEvenWithWrongWeights) {
    CheckCovarianceHonesty(CovarianceModel::kSandwich, true, true);
    // SNR weights on uniform noise: eq. (6) would be wrong here, the sandwich is not.
    CheckCovarianceHonesty(CovarianceModel::kSandwich, false, true);
}

TEST(EgoVelocity, PowerWeightsReduceTheErrorWhenWeakReturnsAreNoisier) {
    double sum2[2] = {0.0, 0.0};
    for (int use_power = 0; use_power < 2; ++use_power) {
        // Half of the returns are below the reference SNR: their noise is 1.4x to 5x the floor.
        EgoVelocityConfig c;
        c.use_power = use_power == 1;
        c.snr_reference_db = 20.0;
        EgoVelocityEstimator estimator(c);
        SceneOptions o;
        o.snr_reference_db = 20.0;
        o.points = 1000;
        for (int t = 0; t < 100; ++t) {
            o.seed = 77 + t;
            const auto r = estimator.Estimate(MakeScan(o).scan);
            ASSERT_TRUE(r.valid());
            sum2[use_power] += (r.v_radar_mps - o.v_radar).squaredNorm();
        }
    }
    std::printf("RMSE unit weights %.4f m/s, SNR weights %.4f m/s\n", std::sqrt(sum2[0] / 100),
                std::sqrt(sum2[1] / 100));
    EXPECT_LT(sum2[1], 0.6 * sum2[0]);
}

struct OutlierCase {
    double fraction;
    bool coherent;
};

class EgoVelocityOutliers : public ::testing::TestWithParam<OutlierCase> {};

TEST_P(EgoVelocityOutliers, RansacRecoversVelocityAndMask) {
    const auto [fraction, coherent] = GetParam();
    EgoVelocityEstimator estimator{EgoVelocityConfig{}};
    double worst_error_sigmas = 0.0, min_precision = 1.0, min_recall = 1.0;
    for (int t = 0; t < 20; ++t) {
        SceneOptions o;
        o.points = 3000;
        o.dynamic_fraction = fraction;
        o.coherent_crowd = coherent;
        o.seed = 500 + t;
        const auto s = MakeScan(o);
        const auto r = estimator.Estimate(s.scan);
        ASSERT_TRUE(r.valid()) << Describe(r);
        // Error in units of the Cramer-Rao bound of the static points alone.
        Eigen::Matrix3Xd d_static(3, 0);
        std::vector<int> idx;
        for (int i = 0; i < o.points; ++i)
            if (!s.dynamic[i]) idx.push_back(i);
        Eigen::Matrix3Xd dirs(3, idx.size());
        Eigen::VectorXd sig(idx.size());
        for (std::size_t k = 0; k < idx.size(); ++k) {
            dirs.col(k) = s.directions.col(idx[k]);
            sig[k] = s.sigma_mps[idx[k]];
        }
        const Eigen::Matrix3d crb = VelocityCramerRaoBound(dirs, sig);
        const Eigen::Vector3d e = r.v_radar_mps - o.v_radar;
        worst_error_sigmas = std::max(worst_error_sigmas, std::sqrt(e.dot(crb.ldlt().solve(e))));
        const auto q = Quality(s, r, o.v_radar);
        min_precision = std::min(min_precision, q.precision);
        min_recall = std::min(min_recall, q.recall);
    }
    std::printf(
        "%.0f %% %s outliers: worst Mahalanobis error %.2f (CRB), dynamic-mask precision "
        "%.4f recall %.4f (worst of 20 scans)\n",
        100 * fraction, coherent ? "coherent-crowd" : "random-object", worst_error_sigmas,
        min_precision, min_recall);
    EXPECT_LT(worst_error_sigmas, 5.0);  // chi(3) beyond 5 has probability 3e-5
    EXPECT_GT(min_precision, 0.97);
    EXPECT_GT(min_recall, 0.97);
}

INSTANTIATE_TEST_SUITE_P(Crowds, EgoVelocityOutliers,
                         ::testing::Values(OutlierCase{0.3, false}, OutlierCase{0.5, false},
                                           OutlierCase{0.3, true}, OutlierCase{0.5, true},
                                           OutlierCase{0.6, true}));

TEST(EgoVelocity, TrimmedIrlsHandlesFewOutliersButRansacIsNeededForABus) {
    EgoVelocityConfig irls;
    irls.method = RobustMethod::kTrimmedIrls;
    EgoVelocityEstimator trimmed(irls);
    SceneOptions o;
    o.dynamic_fraction = 0.1;
    auto r = trimmed.Estimate(MakeScan(o).scan);
    ASSERT_TRUE(r.valid());
    EXPECT_LT((r.v_radar_mps - o.v_radar).norm(), 0.05);
    o.dynamic_fraction = 0.4;
    o.coherent_crowd = true;
    r = trimmed.Estimate(MakeScan(o).scan);
    EgoVelocityEstimator ransac{EgoVelocityConfig{}};
    const auto good = ransac.Estimate(MakeScan(o).scan);
    std::printf("40 %% bus: trimmed IRLS error %.3f m/s, RANSAC error %.3f m/s\n",
                (r.v_radar_mps - o.v_radar).norm(), (good.v_radar_mps - o.v_radar).norm());
    EXPECT_LT((good.v_radar_mps - o.v_radar).norm(), 0.05);
}

TEST(EgoVelocity, APredictionKeepsACrowdThatOutnumbersTheWorldFromTakingTheScan) {
    // A crowd moving together over the whole field of view, 60 % of the points: unheld, RANSAC
    // takes it for the world (the premise, asserted). Held near the previous velocity it finds
    // the static world; held where nothing is, it is released and answers as unheld.
    SceneOptions o;
    o.dynamic_fraction = 0.6;
    o.coherent_crowd = true;
    o.crowd_azimuth_deg = 0.0;
    o.crowd_width_deg = 120.0;
    o.crowd_velocity = Eigen::Vector3d(1.5, 0.0, 0.0);
    const SyntheticScan s = MakeScan(o);
    EgoVelocityEstimator estimator{EgoVelocityConfig{}};
    const auto unheld = estimator.Estimate(s.scan);
    ASSERT_TRUE(unheld.valid());
    ASSERT_GT((unheld.v_radar_mps - o.v_radar).norm(), 1.0) << "the crowd must win unheld";
    EXPECT_EQ(unheld.prediction, PredictionUse::kNone);

    const auto held = estimator.Estimate(
        s.scan, VelocityPrediction{o.v_radar + Eigen::Vector3d(0.3, -0.2, 0.1), 1.0});
    ASSERT_TRUE(held.valid());
    EXPECT_EQ(held.prediction, PredictionUse::kInside);
    EXPECT_LT((held.v_radar_mps - o.v_radar).norm(), 0.05);
    int crowd_as_static = 0;
    for (std::size_t i = 0; i < s.dynamic.size(); ++i)
        crowd_as_static += s.dynamic[i] && held.labels[i] == PointLabel::kStatic;
    EXPECT_LT(crowd_as_static, 20);

    const auto released =
        estimator.Estimate(s.scan, VelocityPrediction{Eigen::Vector3d(30.0, 0.0, 0.0), 1.0});
    EXPECT_EQ(released.prediction, PredictionUse::kReleased);
    EXPECT_LT((released.v_radar_mps - unheld.v_radar_mps).norm(), 1e-9);
}

TEST(EgoVelocity, IsReproducible) {
    SceneOptions o;
    o.dynamic_fraction = 0.3;
    const auto s = MakeScan(o);
    EgoVelocityEstimator a{EgoVelocityConfig{}}, b{EgoVelocityConfig{}};
    const auto r1 = a.Estimate(s.scan);
    a.Estimate(MakeScan(SceneOptions{}).scan);  // state from another scan must not leak
    const auto r2 = a.Estimate(s.scan), r3 = b.Estimate(s.scan);
    EXPECT_EQ(r1.v_radar_mps, r2.v_radar_mps);
    EXPECT_EQ(r1.v_radar_mps, r3.v_radar_mps);
    EXPECT_EQ(r1.labels, r3.labels);
}

TEST(EgoVelocity, PreFiltersLabelPointsFiltered) {
    SceneOptions o;
    o.doppler_sigma_mps = 0.0;
    auto s = MakeScan(o);
    s.scan.xyz_radar.col(0) = Eigen::Vector3d(100.0, 0.0, 0.0);  // beyond max range
    s.scan.power_db[1] = -5.0;                                   // weaker than min power
    s.scan.doppler_mps[2] = NAN;
    s.scan.xyz_radar.col(3) = Eigen::Vector3d(5.0, 5.0, 0.0);  // azimuth 45 deg, outside FOV
    EgoVelocityConfig c;
    c.max_range_m = 90.0;
    c.min_power_db = 0.0;
    c.max_azimuth_deg = 44.0;
    EgoVelocityEstimator estimator(c);
    const auto r = estimator.Estimate(s.scan);
    ASSERT_TRUE(r.valid());
    for (int i = 0; i < 4; ++i) EXPECT_EQ(r.labels[i], PointLabel::kFiltered) << i;
    for (int i = 0; i < o.points; ++i) {
        const double az = std::atan2(s.scan.xyz_radar(1, i), s.scan.xyz_radar(0, i));
        if (i >= 4 && az <= DegToRad(44.0)) {
            EXPECT_EQ(r.labels[i], PointLabel::kStatic) << i;
        }
    }
    EXPECT_LT((r.v_radar_mps - o.v_radar).norm(), 1e-9);
}

TEST(EgoVelocity, StationaryVehicleIsReported) {
    SceneOptions o;
    o.v_radar.setZero();
    o.dynamic_fraction = 0.2;  // people walking past a parked car
    EgoVelocityEstimator estimator{EgoVelocityConfig{}};
    const auto r = estimator.Estimate(MakeScan(o).scan);
    ASSERT_TRUE(r.valid()) << Describe(r);
    EXPECT_TRUE(r.stationary);
    EXPECT_LT(r.v_radar_mps.norm(), 0.02);
}

TEST(EgoVelocity, BadScansAreFlaggedWithTheirCause) {
    EgoVelocityEstimator estimator{EgoVelocityConfig{}};
    const auto expect_invalid = [&](const RadarScan &scan, EgoVelocityFailure cause) {
        const auto r = estimator.Estimate(scan);
        EXPECT_FALSE(r.valid());
        EXPECT_EQ(r.failure, cause) << Describe(r);
        EXPECT_TRUE(r.v_radar_mps.allFinite());
        EXPECT_EQ(r.labels.size(), static_cast<std::size_t>(scan.size()));
        return r;
    };
    expect_invalid(RadarScan{}, EgoVelocityFailure::kEmptyScan);

    SceneOptions o;
    o.points = 6;
    const auto few = expect_invalid(MakeScan(o).scan, EgoVelocityFailure::kTooFewPoints);
    // The message carries the numbers; the cause's key does not.
    EXPECT_EQ(Describe(few), "too few points after the pre-filters: 6 < min_points 10");
    EXPECT_EQ(std::string(ToString(few.failure)), "too few points after the pre-filters");

    o.points = 500;
    auto nan_scan = MakeScan(o);
    nan_scan.scan.doppler_mps.setConstant(NAN);
    expect_invalid(nan_scan.scan, EgoVelocityFailure::kTooFewPoints);

    auto collinear = MakeScan(o);  // every point straight ahead
    for (int i = 0; i < o.points; ++i)
        collinear.scan.xyz_radar.col(i) = Eigen::Vector3d(i + 1.0, 0, 0);
    expect_invalid(collinear.scan, EgoVelocityFailure::kDegenerateGeometry);

    auto planar = MakeScan(o);  // a 2-D radar: no elevation, v_z unobservable
    planar.scan.xyz_radar.row(2).setZero();
    expect_invalid(planar.scan, EgoVelocityFailure::kDegenerateGeometry);

    auto all_dynamic = MakeScan(o);  // nothing agrees with anything
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> doppler(-15.0, 15.0);
    for (int i = 0; i < o.points; ++i) all_dynamic.scan.doppler_mps[i] = doppler(rng);
    expect_invalid(all_dynamic.scan, EgoVelocityFailure::kTooFewInliers);

    o.v_radar = Eigen::Vector3d(60.0, 0.0, 0.0);
    const auto fast = expect_invalid(MakeScan(o).scan, EgoVelocityFailure::kSpeedLimit);
    EXPECT_NEAR(fast.v_radar_mps.norm(), 60.0, 0.5);  // the estimate is kept, only flagged

    EgoVelocityConfig db;
    db.power_weighting = PowerWeighting::kDecibel;
    db.decibel_floor_db = 50.0;
    EgoVelocityEstimator floor_estimator(db);
    const auto r = floor_estimator.Estimate(MakeScan(SceneOptions{}).scan);
    EXPECT_FALSE(r.valid());
    EXPECT_EQ(r.failure, EgoVelocityFailure::kZeroWeight) << Describe(r);
}

// Every cause has its own key (summary.json counts by it), without numbers; kNone has none, and a
// result that was never estimated is not valid.
TEST(EgoVelocity, FailureKeysAreDistinct) {
    std::set<std::string> keys;
    for (EgoVelocityFailure failure : kAllEgoVelocityFailures) {
        const std::string key = ToString(failure);
        EXPECT_EQ(key.empty(), failure == EgoVelocityFailure::kNone);
        EXPECT_EQ(key.find_first_of("0123456789:"), std::string::npos) << key;
        keys.insert(key);
    }
    EXPECT_EQ(keys.size(), std::size(kAllEgoVelocityFailures));
    EXPECT_FALSE(EgoVelocityResult{}.valid());
    EXPECT_EQ(Describe(EgoVelocityResult{}), "not estimated");
}

TEST(EgoVelocity, ZeroPowerMeansUniformWeights) {
    SceneOptions o;
    o.heteroscedastic = false;
    auto s = MakeScan(o);
    s.scan.power_db.setZero();
    // (kSnr is not uniform here: zero power means weak returns, hence wider gates.)
    for (auto w : {PowerWeighting::kLinear, PowerWeighting::kDecibel}) {
        EgoVelocityConfig c;
        c.power_weighting = w;
        c.decibel_floor_db = -1.0;
        EgoVelocityConfig unit;
        unit.use_power = false;
        const auto a = EgoVelocityEstimator(c).Estimate(s.scan);
        const auto b = EgoVelocityEstimator(unit).Estimate(s.scan);
        ASSERT_TRUE(a.valid()) << Describe(a);
        EXPECT_LT((a.v_radar_mps - b.v_radar_mps).norm(), 1e-9);
    }
}

// The bail-out drops bad hypotheses after a sample of the subset; it must not change the answer:
// on crowded scans the estimate with it stays within a fraction of the Cramer-Rao sigma of the
// estimate that scores every hypothesis on the whole subset.
TEST(EgoVelocity, BailOutKeepsTheAnswerOfFullScoring) {
    EgoVelocityConfig off;
    off.ransac_bailout_points = 0;
    EgoVelocityEstimator with{EgoVelocityConfig{}}, without{off};
    double worst_sigmas = 0.0;
    for (int t = 0; t < 10; ++t) {
        SceneOptions o;
        o.points = 3000;
        o.dynamic_fraction = 0.5;
        o.coherent_crowd = t % 2 == 0;
        o.seed = 900 + t;
        const auto s = MakeScan(o);
        const auto a = with.Estimate(s.scan), b = without.Estimate(s.scan);
        ASSERT_TRUE(a.valid() && b.valid()) << Describe(a) << Describe(b);
        const Eigen::Vector3d e = a.v_radar_mps - b.v_radar_mps;
        worst_sigmas = std::max(worst_sigmas, std::sqrt(e.dot(b.cov_v_radar.ldlt().solve(e))));
    }
    EXPECT_LT(worst_sigmas, 0.5);
}

TEST(EgoVelocity, ConfigErrorsNameTheField) {
    EgoVelocityConfig c;
    c.doppler_sigma_mps = -1.0;
    try {
        c.Validate();
        FAIL() << "no throw";
    } catch (const std::invalid_argument &e) {
        EXPECT_NE(std::string(e.what()).find("doppler_sigma_mps"), std::string::npos);
    }
    c = EgoVelocityConfig{};
    c.max_range_m = 0.1;
    EXPECT_THROW(EgoVelocityEstimator{c}, std::invalid_argument);
    c = EgoVelocityConfig{};
    c.ransac_bailout_fraction = 1.0;
    EXPECT_THROW(EgoVelocityEstimator{c}, std::invalid_argument);
    c = EgoVelocityConfig{};
    c.ransac_bailout_points = -1;
    EXPECT_THROW(EgoVelocityEstimator{c}, std::invalid_argument);
}

// RANSAC's minimal solve against Eigen's PartialPivLU, bit for bit: random unit directions (as
// eq. (1)'s rows are), rows of equal magnitude (pivot ties), nearly dependent and exact-zero
// pivots.
TEST(EgoVelocity, MinimalSolveEqualsEigensPartialPivLuBitForBit) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g(0.0, 1.0);
    int compared = 0;
    for (int trial = 0; trial < 200000; ++trial) {
        Eigen::Matrix3d M;
        for (int i = 0; i < 3; ++i) M.row(i) = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
        if (trial % 5 == 1) M(1, 0) = -M(0, 0);                     // a tie for the first pivot
        if (trial % 5 == 2) M.row(2) = M.row(0) + 1e-6 * M.row(1);  // nearly dependent
        if (trial % 5 == 3) M(0, 0) = M(1, 0) = M(2, 0) = 0.0;      // a zero column
        const Eigen::Vector3d r(g(rng), g(rng), g(rng));
        const Eigen::Vector3d expected = M.partialPivLu().solve(r);
        const Eigen::Vector3d got = internal::SolvePartialPivot3(M, r);
        if (!expected.allFinite()) continue;
        ++compared;
        ASSERT_EQ(std::memcmp(expected.data(), got.data(), sizeof(double) * 3), 0)
            << "trial " << trial << ": " << got.transpose() << " vs " << expected.transpose();
    }
    EXPECT_GT(compared, 150000);
}

}  // namespace
}  // namespace dorado::odometry
