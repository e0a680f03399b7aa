#pragma once
/// @file ego_velocity.hpp
/// The radar's own velocity from one scan of Doppler measurements (paper section III-A, eq. 1, 2,
/// 6), robust to moving objects, with the per-point static/dynamic mask.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dorado/core/radar_scan.hpp"
#include "dorado/core/radar_sensor.hpp"

namespace dorado::odometry {

/// Per-point label of the dynamic-point mask.
enum class PointLabel : uint8_t {
    kStatic = 0,    ///< inlier of the ego-velocity model (a static point)
    kDynamic = 1,   ///< used, but inconsistent with the ego-velocity (a moving object or clutter)
    kFiltered = 2,  ///< removed before the fit (range, field of view, power, NaN)
};

/// How a point's weight in eq. (2) is derived from its power [dB].
enum class PowerWeighting {
    /// Inverse Doppler variance of a radar whose noise grows for weak returns:
    /// sigma_i^2 = sigma^2 (1 + 10^((snr_reference_db - power_i) / 10)), w_i = sigma^2 / sigma_i^2.
    kSnr,
    /// Linear power 10^(power/10), normalised by the scan's strongest return.
    kLinear,
    /// The power in dB itself, minus `decibel_floor_db` and clamped at 0 (the paper's reference
    /// code).
    kDecibel,
};

/// Outlier rejection strategy.
enum class RobustMethod {
    kRansac,       ///< 3-point RANSAC, spread-aware scoring, refit on inliers (default)
    kTrimmedIrls,  ///< the paper's reference trimmed iteratively-reweighted least squares
    kNone,         ///< plain weighted least squares on every point
};

/// Inlier rule of the trimmed IRLS (the paper's reference implementation).
enum class TrimMode {
    kPercent,  ///< keep the `trim_value` fraction of points with the smallest |residual|
    kMad,      ///< keep |r| <= median(|r|) + trim_value * MAD(|r|)
    kFixed,    ///< keep |r| <= trim_value [m/s]
};

/// Covariance of the estimated velocity.
enum class CovarianceModel {
    /// eq. (6): rho^T W rho / (N - 3) (A^T W A)^-1. Honest only when the weights are proportional
    /// to the inverse Doppler variances.
    kResidualScaled,
    /// Sandwich (heteroscedasticity-consistent) estimator
    /// N/(N-3) (A^T W A)^-1 A^T W diag(rho^2) W A (A^T W A)^-1: honest whatever the weights.
    kSandwich,
};

struct EgoVelocityConfig {
    // --- pre-filters (directions and angles come from xyz, azimuth from +X towards +Y) ---
    double min_range_m = 0.5;
    double max_range_m = 200.0;
    double min_azimuth_deg = -180.0;
    double max_azimuth_deg = 180.0;
    double min_elevation_deg = -90.0;
    double max_elevation_deg = 90.0;
    /// Points weaker than this are filtered; -inf keeps all.
    double min_power_db = -std::numeric_limits<double>::infinity();

    // --- weights (eq. 2) ---
    bool use_power = true;  ///< false: unit weights (also used when the scan has no power field)
    PowerWeighting power_weighting = PowerWeighting::kSnr;
    double snr_reference_db = 10.0;  ///< kSnr: power at which the Doppler variance doubles
    double decibel_floor_db = 0.0;   ///< kDecibel: weight = max(power - floor, 0)

    // --- robust fit ---
    RobustMethod method = RobustMethod::kRansac;
    /// Doppler noise of strong returns [m/s]; the inlier gate is gate_sigmas * sigma_i.
    double doppler_sigma_mps = 0.05;
    double gate_sigmas = 3.0;
    /// Upper bound of sigma_i / doppler_sigma_mps for weak returns (keeps their gate finite).
    double max_gate_scale = 4.0;
    double ransac_success_probability = 0.999;
    int ransac_min_iterations = 10;
    /// Hard cap on hypotheses; when it is hit, the best hypothesis so far is refit and used.
    int ransac_max_iterations = 300;
    /// Hypotheses are scored on a random subset of this many points (0 = all points); the final
    /// inlier set and refit always use every point.
    int ransac_score_points = 1024;
    /// Bail-out when scoring a hypothesis: after its first this many points of the (shuffled)
    /// scoring subset, a hypothesis whose inliers there fall below ransac_bailout_fraction times
    /// what the best hypothesis so far predicts is dropped unscored. Bounds the cost of the many
    /// bad hypotheses that crowded scans need; 0 = off.
    int ransac_bailout_points = 128;
    double ransac_bailout_fraction = 0.5;
    /// Spread-aware scoring: inliers are counted per direction cell (azimuth x elevation) and each
    /// cell contributes sqrt(its count), so that a static world that surrounds the sensor beats a
    /// compact crowd moving together (a passing bus) even when the crowd has more points.
    /// 1 x 1 cells gives plain MSAC scoring.
    int score_cells_azimuth = 12;
    int score_cells_elevation = 3;
    /// Refit-and-regate rounds after RANSAC (or IRLS rounds for kTrimmedIrls).
    int refit_iterations = 3;
    uint64_t seed =
        42;  ///< RANSAC is reseeded with this at every Estimate(): reproducible per scan

    TrimMode trim_mode = TrimMode::kPercent;
    double trim_value = 0.7;
    int irls_max_iterations = 20;

    CovarianceModel covariance = CovarianceModel::kSandwich;

    // --- the sensor (the dataset's radar section) ---
    /// Direction noise and Doppler ambiguity. With direction noise, the final fit after RANSAC
    /// gates each point by its total variance sigma_i^2 + v^T C_i v (C_i: the covariance of its
    /// measured direction, growing for weak returns like the Doppler noise) and removes the
    /// errors-in-variables bias (bias-compensated least squares); with
    /// doppler_unambiguous_mps > 0, each point's Doppler is unwrapped (by a multiple of 2 v_unamb)
    /// to the one closest to the hypothesis while RANSAC scores and refits.
    RadarSensorModel sensor;
    /// true: the bias-compensated final fit when the sensor has direction noise; false: eq. (2)'s
    /// plain weighted least squares. Off by default (opt-in): the v_z error budget
    /// (benchmarks/odometry/vz_error_budget.py) finds elevation noise the one systematic v_z error
    /// of the simulated Husky scans (-3 to -4 mm/s at 1-1.7 m/s, 0.4-0.5 deg/s of pitch rate
    /// through eq. 5), which this removes; pooled over 11 sequences the odometry's roll/pitch
    /// error drops from 3.9/4.3 to 2.9/3.0 deg (docs/attitude.md). The default:
    /// over 3 simulator seeds of each of the 10 built-in sequences it wins pooled (ATE rotation
    /// 17.0 -> 15.4 deg, ATE 1.98 -> 0.76 m) and loses none by more than the seeds' noise
    /// (docs/design/attitude.md, section 6).
    bool compensate_direction_noise = true;

    // --- validity ---
    int min_points = 10;  ///< points left after the pre-filters
    int min_inliers = 8;  ///< static inliers
    double min_inlier_ratio = 0.15;
    /// Largest allowed sqrt(lambda_max / lambda_min) of A^T W A on the inliers.
    double max_condition_number = 200.0;
    double max_speed_mps = 40.0;
    /// Below this speed the scan is flagged stationary (valid, velocity kept).
    double stationary_speed_mps = 0.05;

    /// Throws std::invalid_argument naming the first bad field.
    void Validate() const;
};

/// Why a scan gave no valid ego-velocity, in the order the estimators check; the numbers that
/// decided it are in EgoVelocityResult::failure_detail.
enum class EgoVelocityFailure {
    kNone,                ///< valid
    kNotEstimated,        ///< "not estimated": no Estimate() ran (a scan skipped for its stamp)
    kEmptyScan,           ///< "empty scan"
    kTooFewPoints,        ///< "too few points after the pre-filters": fewer than min_points
    kZeroWeight,          ///< every point's weight is 0 (power at or below decibel_floor_db)
    kDegenerateGeometry,  ///< "degenerate geometry": singular, or above max_condition_number
    kTooFewInliers,       ///< "too few static inliers": below min_inliers or min_inlier_ratio
    kNonFinite,           ///< "non-finite velocity or covariance"
    kSpeedLimit,          ///< "speed above max_speed_mps"
    kNoPlanarModel,       ///< "no planar vehicle model": a 2D radar on a mount it cannot handle
};
/// Every cause, in the order above.
inline constexpr EgoVelocityFailure kAllEgoVelocityFailures[] = {
    EgoVelocityFailure::kNone,          EgoVelocityFailure::kNotEstimated,
    EgoVelocityFailure::kEmptyScan,     EgoVelocityFailure::kTooFewPoints,
    EgoVelocityFailure::kZeroWeight,    EgoVelocityFailure::kDegenerateGeometry,
    EgoVelocityFailure::kTooFewInliers, EgoVelocityFailure::kNonFinite,
    EgoVelocityFailure::kSpeedLimit,    EgoVelocityFailure::kNoPlanarModel};

/// The cause in words, without numbers (a stable key for counts): "" for kNone, e.g.
/// "too few points after the pre-filters" for kTooFewPoints.
[[nodiscard]] const char *ToString(EgoVelocityFailure failure);

/// Where the radar's velocity can be at this scan, from the previous scan's: a ball of radius
/// radius_mps around v_radar_mps (DopplerOdometry: the previous velocity, grown by the largest
/// acceleration over the interval and its own 3 sigma).
struct VelocityPrediction {
    Eigen::Vector3d v_radar_mps = Eigen::Vector3d::Zero();
    double radius_mps = 0.0;
};

/// What a VelocityPrediction did to one scan.
enum class PredictionUse {
    kNone,      ///< "none": no prediction was given
    kInside,    ///< "inside": RANSAC's hypotheses were held inside the ball, and one explained the
                ///< scan
    kReleased,  ///< "released": no hypothesis inside explained enough points; estimated without it
};
/// "none" | "inside" | "released".
[[nodiscard]] const char *ToString(PredictionUse use);

struct EgoVelocityResult {
    /// kNone: the velocity is valid. Otherwise the cause, and failure_detail its numbers.
    EgoVelocityFailure failure = EgoVelocityFailure::kNotEstimated;
    std::string failure_detail;  ///< e.g. "3 < min_points 10" (for messages, never decisions)
    [[nodiscard]] bool valid() const { return failure == EgoVelocityFailure::kNone; }
    Eigen::Vector3d v_radar_mps = Eigen::Vector3d::Zero();  ///< radar velocity in the radar frame
    Eigen::Matrix3d cov_v_radar = Eigen::Matrix3d::Zero();  ///< its covariance [m^2/s^2]
    std::vector<PointLabel> labels;                         ///< one per input point
    int inliers = 0;
    int points_used = 0;              ///< points that passed the pre-filters
    double residual_sigma_mps = 0.0;  ///< weighted RMS residual of the inliers
    bool stationary = false;
    double condition_number = 0.0;
    int iterations = 0;  ///< RANSAC hypotheses or IRLS rounds
    /// Static inliers whose Doppler was unwrapped by a multiple of 2 doppler_unambiguous_mps
    /// (aliased returns used, not rejected).
    int unwrapped = 0;
    /// The final fit removed the direction-noise (errors-in-variables) bias.
    bool direction_noise_compensated = false;
    PredictionUse prediction = PredictionUse::kNone;
};

/// Why `result` is not valid, in words with its numbers ("too few points after the pre-filters:
/// 3 < min_points 10"); empty when it is valid.
[[nodiscard]] std::string Describe(const EgoVelocityResult &result);

/// Estimates v_radar from a scan: for a static point with unit direction d_i,
/// -doppler_i = d_i . v_radar (eq. 1).
class EgoVelocityEstimator {
  public:
    /// Validates the config (std::invalid_argument naming the field).
    explicit EgoVelocityEstimator(EgoVelocityConfig config);

    ~EgoVelocityEstimator();
    EgoVelocityEstimator(EgoVelocityEstimator &&) noexcept;
    EgoVelocityEstimator &operator=(EgoVelocityEstimator &&) noexcept;

    /// Not const: reuses internal buffers so that the RANSAC loop does not allocate. Never throws
    /// on bad data: a scan that cannot be used comes back with its failure cause.
    EgoVelocityResult Estimate(const RadarScan &scan_radar);
    /// The same, with RANSAC's hypotheses held inside the prediction's ball, so that a crowd
    /// moving together (more points, or better spread, than the static world) cannot take the
    /// scan by a jump no vehicle makes. Only kRansac uses it. When no hypothesis inside the ball
    /// gives min_inliers and min_inlier_ratio, the scan is estimated without it (kReleased): the
    /// prediction may be the one that is wrong.
    EgoVelocityResult Estimate(const RadarScan &scan_radar, const VelocityPrediction &prediction);

    [[nodiscard]] const EgoVelocityConfig &config() const { return config_; }

  private:
    EgoVelocityResult EstimateWithin(const RadarScan &scan_radar,
                                     const std::optional<VelocityPrediction> &prediction);
    struct Workspace;
    EgoVelocityConfig config_;
    std::unique_ptr<Workspace> workspace_;
};

/// Cramer-Rao bound (A^T W A)^-1 of v for unbiased estimators, with W = diag(1 / sigma_i^2)
/// (units: sigma in m/s). `directions` are unit columns.
[[nodiscard]] Eigen::Matrix3d VelocityCramerRaoBound(const Eigen::Matrix3Xd &directions,
                                                     const Eigen::VectorXd &sigma_mps);

}  // namespace dorado::odometry
