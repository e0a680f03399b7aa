#pragma once
/// @file yaw_calibration.hpp
/// Online calibration of the kinematic model's yaw lever s_x (the ICR offset of the paper's
/// section IV-A) from yaw changes measured independently of eq. (5), e.g. by the mapper's
/// registration against its map.
///
/// eq. (5) gives the yaw rate as omega_z = v_sy / s_x, with v_sy the radar's lateral velocity in
/// the base frame. Over a window of scans that yaw integrates to
///     dpsi = g * h,   g = 1 / s_x,   h = sum_k v_sy,k dt_k,
/// linear in g. A scalar Kalman filter on g (random walk between windows) takes each window whose
/// yaw change dpsi was measured by something else (the registered poses at the window's two ends,
/// locked to the map, so the error of dpsi does not grow with the window) and reports
/// s_x = 1 / g with its 1-sigma. A skid-steer vehicle whose Z-ICR sits ahead of the rear axle
/// (slip) reads as a shorter s_x: the estimate is the effective lever, the one eq. (5) needs.
/// No I/O.

#include <Eigen/Core>

namespace dorado::odometry {

struct YawCalibrationConfig {
    /// Estimate s_x online and feed it back to the kinematic model (the odometry and the next
    /// priors). false: the configured s_x throughout (the paper). On by default:
    /// the doppler-prior maps' yaw drift -69 %, ATE rotation -58 % pooled over the 10 built-in
    /// sequences, no sequence worse beyond the seeds' noise (docs/design/attitude.md, section 7).
    bool enabled = true;
    /// No measurement in the map's first seconds (a young map registers worse; on hills_slopes its
    /// first windows pushed s_x to the clamp) [s].
    double warmup_s = 5.0;
    /// Shortest window between the two registered poses that make one measurement [s].
    double window_s = 1.0;
    /// Longest window: a window still not turning enough by then restarts [s].
    double max_window_s = 4.0;
    /// A window whose predicted yaw change |g h| stays below this is straight driving: the lever
    /// is unobservable there, no update [rad].
    double min_turn_rad = 0.05;
    /// Mean speed below this over the window: standing or creeping, no update [m/s].
    double min_speed_mps = 0.3;
    /// Noise of one measured yaw change: the two registered poses' yaw errors together [rad].
    double measurement_sigma_rad = 0.01;
    /// Noise of the model over a window, relative to the yaw change (slip that varies from turn
    /// to turn) [-].
    double relative_sigma = 0.05;
    /// 1-sigma of the starting g = 1 / s_x, relative to the configured value [-].
    double initial_relative_sigma = 0.2;
    /// Random walk of g, relative to the configured value, per sqrt(second) [1/sqrt(s)].
    double relative_random_walk_per_sqrt_s = 0.002;
    /// A window whose innovation is farther than this squared Mahalanobis distance is refused
    /// (a registration that slipped) [chi2, 1 dof]. 6.63, the 99 % quantile: at 16 one window
    /// of a map that had slipped moved xsim rotated_mount s101's s_x from 0.90 to 1.76 m at
    /// once (map ATE 9.6 m; 0.78 m at 6.63; docs/robust_mapping.md).
    double max_innovation_chi2 = 6.63;
    /// The estimate is kept within [1 / this, this] times the configured s_x [-].
    double max_ratio = 2.0;

    /// Throws std::invalid_argument naming the first bad field ("online_calibration.<key>: ...").
    void Validate() const;
};

/// What the calibrator did with one scan.
enum class YawCalibrationStatus {
    kDisabled,       ///< calibration off
    kWarmup,         ///< within warmup_s of the map's start: no window yet
    kAccumulating,   ///< inside a window
    kNotRegistered,  ///< this scan's pose is not registered (fallback, degenerate): window restarts
    kStanding,       ///< the window's mean speed below min_speed_mps: no update
    kStraight,       ///< the window's yaw change below min_turn_rad: no update
    kOutlier,        ///< innovation beyond max_innovation_chi2: refused
    kUpdated,        ///< a measurement was used
};

/// "disabled" | "warmup" | "accumulating" | "not_registered" | "standing" | "straight" |
/// "outlier" | "updated".
[[nodiscard]] const char *ToString(YawCalibrationStatus status);

/// One scan's outcome, with the estimate after it.
struct YawCalibrationStep {
    YawCalibrationStatus status = YawCalibrationStatus::kDisabled;
    double s_x_m = 0.0;  ///< the estimate after this scan
    double sigma_s_x_m = 0.0;
    double innovation_chi2 = 0.0;  ///< of the window's measurement (kUpdated, kOutlier)
};

class YawRateCalibrator {
  public:
    /// `configured_s_x_m` is where the estimate starts (the extrinsics' radar X position).
    /// Throws std::invalid_argument for a bad config or |s_x| < 1 mm.
    YawRateCalibrator(const YawCalibrationConfig &config, double configured_s_x_m);

    /// One scan, in order. `dt_s`: time since the previous scan (0 for the first); `v_sy_base_mps`
    /// the radar's lateral velocity in the base frame over that interval (as eq. 5 used it) and
    /// `speed_mps` the base speed; `registered`: this scan's pose is the registration's, trusted
    /// (well conditioned, no fallback); `R_world_base` that pose's rotation. A window runs from
    /// one registered scan to a later registered one; an unregistered scan restarts it.
    YawCalibrationStep AddScan(double dt_s, double v_sy_base_mps, double speed_mps, bool registered,
                               const Eigen::Matrix3d &R_world_base);

    /// The measurement model on its own: a yaw change `dpsi_rad` measured over a window whose
    /// lateral-velocity integral is `h_m` (= sum v_sy dt) and mean speed `mean_speed_mps`, after
    /// `elapsed_s` seconds of random walk.
    YawCalibrationStep Update(double dpsi_rad, double h_m, double mean_speed_mps, double elapsed_s);

    /// Ends the open window without a measurement (a new map frame): the next registered scan
    /// after warmup_s starts one. The estimate is kept.
    void BreakWindow() {
        window_open_ = false;
        age_s_ = 0.0;
    }

    [[nodiscard]] double s_x_m() const { return 1.0 / g_; }
    [[nodiscard]] double sigma_s_x_m() const;
    [[nodiscard]] double configured_s_x_m() const { return 1.0 / g0_; }
    [[nodiscard]] int updates() const { return updates_; }
    [[nodiscard]] const YawCalibrationConfig &config() const { return config_; }

  private:
    YawCalibrationStep Report(YawCalibrationStatus status, double chi2 = 0.0) const;
    void RestartWindow(bool at_registered_scan, const Eigen::Matrix3d &R_world_base);

    YawCalibrationConfig config_;
    double g0_;  ///< configured 1 / s_x
    double g_;   ///< estimate of 1 / s_x
    double P_;   ///< its variance
    int updates_ = 0;
    // The open window.
    bool window_open_ = false;
    Eigen::Matrix3d R_start_ = Eigen::Matrix3d::Identity();
    double h_m_ = 0.0, elapsed_s_ = 0.0, distance_m_ = 0.0;
    double since_update_s_ = 0.0;
    double age_s_ = 0.0;  ///< time since the map started (construction or BreakWindow)
};

}  // namespace dorado::odometry
