#pragma once
/// @file radar_front_end.hpp
/// The per-scan pipeline as one object with no I/O: the Doppler odometry hands a motion prior and
/// a dynamic-point mask to the radar ICP mapper, scan by scan. `dorado odometry`, `dorado map`,
/// `dorado bench` and the ROS node `dorado_ros` are thin drivers of it.
///
/// Per scan (paper section IV):
///   1. ego-velocity (eq. 1-2, RANSAC) and its mask, and the vehicle twist through the kinematic
///      model (eq. 5, 7): odometry::DopplerOdometry, with every odometry setting;
///   2. the motion prior (PriorKind), with a substitution when its inputs are missing;
///   3. scan-to-map registration, refinement and map update (mapping::RadarMapper).

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/imu.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/radar_scan.hpp"
#include "dorado/core/trajectory.hpp"
#include "dorado/core/twist.hpp"
#include "dorado/mapping/motion_prior.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/odometry/doppler_odometry.hpp"

namespace dorado::frontend {

/// Everything the pipeline is configured with (the CLI's odometry and mapper YAML files, the
/// node's parameters).
struct FrontEndConfig {
    /// The Doppler chain (ego-velocity, zero-velocity update, angular-rate limit and prior). Its
    /// `method` is the odometry's; with the mapper on, the prior decides (see Validate).
    odometry::DopplerOdometryConfig odometry;
    /// Run the scan-to-map mapper after the odometry (false: odometry only, as `dorado odometry`).
    bool run_mapper = true;
    mapping::PriorKind prior = mapping::PriorKind::kDoppler;
    bool use_mask = true;  ///< register only the points the ego-velocity labels static
    mapping::MapperConfig mapper;
    mapping::PriorNoiseConfig prior_noise;

    /// Throws std::invalid_argument naming the first bad field ("mapper.max_range_m: ...").
    void Validate() const;
};

/// Milliseconds spent in each stage of Process.
struct FrontEndTimes {
    double doppler_ms = 0.0;     ///< ego-velocity + kinematic model
    double prior_ms = 0.0;       ///< building the motion prior
    mapping::StageTimes mapper;  ///< preprocess, registration, refinement, map update
    double total_ms = 0.0;
};

/// Why the requested prior could not be built and constvel stood in for it.
enum class PriorSubstitution {
    kNone,          ///< the requested prior was used
    kNoImuSamples,  ///< "no imu samples": an IMU prior without a gyro sample in the interval
    /// "doppler: no valid velocity": a Doppler prior without an ego-velocity (odometry.ego.failure
    /// says why)
    kInvalidDopplerVelocity,
    /// "doppler: twist discontinuous with the previous one" (doppler_twist_discontinuous)
    kDiscontinuousTwist,
    /// "doppler: angular rate above max_angular_rate_radps": the odometry's twist was a fallback
    kAngularRateLimit,
};
/// Every cause, in the order above.
inline constexpr PriorSubstitution kAllPriorSubstitutions[] = {
    PriorSubstitution::kNone, PriorSubstitution::kNoImuSamples,
    PriorSubstitution::kInvalidDopplerVelocity, PriorSubstitution::kDiscontinuousTwist,
    PriorSubstitution::kAngularRateLimit};

/// The cause in words, without numbers: "" for kNone, e.g. "no imu samples".
[[nodiscard]] const char *ToString(PriorSubstitution cause);

/// What the front end did with one scan.
struct FrontEndResult {
    int64_t stamp_ns = 0;
    /// False when the scan was not used (a stamp not after the previous scan's): skip_reason says
    /// why, and every pose below is the previous one.
    bool accepted = false;
    std::string skip_reason;
    double dt_s = 0.0;  ///< time since the previous accepted scan (0 for the first)

    /// The newest pose: the mapper's filtered estimate when it runs (its smoothed, written poses
    /// are registration.written), the odometry's otherwise.
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    /// The Doppler odometry's own dead-reckoned pose (the paper's node publishes this one).
    Eigen::Isometry3d T_world_base_odometry = Eigen::Isometry3d::Identity();
    /// The twist integrated by the odometry, in the base frame, with the joint covariance of
    /// [v_base; omega_base] (eq. 7 plus the kinematic model's own error).
    Twist twist_base;
    /// The odometry's step (ego-velocity, eq. 5 motion, fallback), as dorado odometry reports it.
    odometry::OdometryStep odometry;
    /// The mean gyro rate over the scan interval in the base frame (NaN without IMU samples).
    Eigen::Vector3d gyro_base_radps = Eigen::Vector3d::Constant(NAN);
    /// The dynamic mask: true = static, one per input point; empty when no valid ego-velocity.
    mapping::PointMask static_mask;

    /// The prior that was asked for, and the one used: they differ when a substitution happened
    /// (no IMU samples in the interval, no valid Doppler velocity), and then prior_substitution
    /// says why. The first scan has no prior (prior_first_scan).
    mapping::PriorKind prior_requested = mapping::PriorKind::kDoppler;
    mapping::PriorKind prior_used = mapping::PriorKind::kDoppler;
    bool prior_first_scan = false;
    PriorSubstitution prior_substitution = PriorSubstitution::kNone;
    /// The numbers behind the substitution, for messages (kInvalidDopplerVelocity: the
    /// ego-velocity's failure_detail); empty otherwise.
    std::string prior_substitution_detail;
    /// The Doppler twist jumped against the last continuous one (beyond the twists' covariances
    /// and the constvel prior's accelerations): the doppler priors substitute constvel and the
    /// scan is registered without the Doppler mask (its static set is suspect).
    bool doppler_twist_discontinuous = false;
    /// The prior handed to the mapper (when run_mapper).
    mapping::MotionPrior prior;
    /// The mapper's result (when run_mapper): fallback, correspondences, fitness, the points it
    /// added to its map (map_points_added_world: for an output map or a live display), ...
    mapping::RegistrationResult registration;
    /// The online calibration of eq. (5)'s yaw lever (odometry.online_calibration, with the
    /// mapper): what this scan did and the estimate after it, which the next scan's odometry and
    /// prior use. Status kDisabled when off.
    odometry::YawCalibrationStep yaw_calibration;

    FrontEndTimes times;
};

/// A substitution's cause for counting: the cause, with the ego-velocity's failure when it is
/// kInvalidDopplerVelocity (kNone otherwise).
using SubstitutionCause = std::pair<PriorSubstitution, odometry::EgoVelocityFailure>;
[[nodiscard]] SubstitutionCause SubstitutionCauseOf(const FrontEndResult &result);
/// The cause as a stable key without numbers (summary counts, CSV columns): ToString of the
/// substitution, except that kInvalidDopplerVelocity names the ego-velocity's cause,
/// "doppler: too few static inliers"; "" for kNone.
[[nodiscard]] std::string SubstitutionKey(const SubstitutionCause &cause);

/// The road's up-vector in the base frame from a scan's plane fit (`fit` valid), for the mapper's
/// ground residual (mapping::GroundUp): its covariance is the fit's plus the road's own slope about
/// level (ground.road_slope_sigma_deg, the ground is the road, not gravity), its gate the ground's
/// max_innovation_chi2.
[[nodiscard]] mapping::GroundUp GroundUpFromFit(const odometry::GroundObservation &fit,
                                                const odometry::GroundAttitudeConfig &ground);

class RadarFrontEnd {
  public:
    /// Validates the config; throws std::invalid_argument for a bad config or an unobservable
    /// mount (see odometry::KinematicModel).
    RadarFrontEnd(FrontEndConfig config, const Extrinsics &extrinsics,
                  const VehicleGeometry &geometry);
    ~RadarFrontEnd();
    RadarFrontEnd(RadarFrontEnd &&) noexcept;
    RadarFrontEnd &operator=(RadarFrontEnd &&) noexcept;

    /// Buffers one IMU sample (IMU frame). Samples are used by the scan whose interval
    /// (previous scan, this scan] holds their stamp; older ones are dropped.
    void AddImu(const ImuSample &sample);

    /// Processes one scan (radar frame). Never throws on bad data.
    FrontEndResult Process(const RadarScan &scan_radar);

    /// Changes the mapper's prior from the next scan on (dorado_ros falls back to kDoppler while
    /// its IMU stalls, and back when it resumes). The odometry's method is the one set at
    /// construction or at the last Reset.
    void SetPrior(mapping::PriorKind prior);

    /// Starts over at T_world_base: the next scan is a first scan (a new map, no prior). The
    /// poses still in the old map's smoother are written first (and returned).
    std::vector<mapping::WrittenPose> Reset(
        const Eigen::Isometry3d &T_world_base = Eigen::Isometry3d::Identity());
    /// The end of the drive: the poses still in the mapper's smoother, written (and appended to
    /// trajectory()); none without the mapper. No Process after it but a Reset.
    std::vector<mapping::WrittenPose> Finish();

    /// One pose per accepted scan as written: the mapper's smoothed poses (about
    /// mapper.smoother.lag_s behind the newest scan until Finish), the odometry's without it.
    [[nodiscard]] const Trajectory &trajectory() const;
    /// The mapper's local map (nullptr when the mapper is off).
    [[nodiscard]] const mapping::LocalMap *local_map() const;
    [[nodiscard]] const FrontEndConfig &config() const;
    /// Stamp of the last accepted scan (false when none yet).
    [[nodiscard]] bool has_last_stamp() const;
    [[nodiscard]] int64_t last_stamp_ns() const;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace dorado::frontend
