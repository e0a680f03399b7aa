#pragma once
/// @file doppler_odometry.hpp
/// The paper's Doppler-only odometry loop: per scan, the radar velocity (eq. 1-2), the vehicle
/// twist from the kinematic model (eq. 5), integrated on SE(3) over the real time between scans.

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/radar_scan.hpp"
#include "dorado/core/trajectory.hpp"
#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/odometry/ground_attitude.hpp"
#include "dorado/odometry/kinematic_model.hpp"
#include "dorado/odometry/planar_ego_velocity.hpp"
#include "dorado/odometry/planar_kinematic_model.hpp"
#include "dorado/odometry/yaw_calibration.hpp"

namespace dorado::odometry {

/// The odometry methods of the paper's Fig. 5; the one spelling of each is ToString's.
enum class OdometryMethod {
    kDoppler,     ///< "doppler": the kinematic model (eq. 5), radar only, the paper's method
    kImu,         ///< "imu": gyro rotation, no translation (the paper's "IMU"; rotation RPE only)
    kImuDoppler,  ///< "imu+doppler": gyro rotation + Doppler translation (the paper's "I+D")
};

/// "doppler" | "imu" | "imu+doppler".
[[nodiscard]] const char *ToString(OdometryMethod method);
/// The inverse of ToString; throws std::invalid_argument listing the choices otherwise.
[[nodiscard]] OdometryMethod ParseOdometryMethod(const std::string &name);
/// Whether the method needs gyro samples.
[[nodiscard]] inline bool NeedsImu(OdometryMethod method) {
    return method != OdometryMethod::kDoppler;
}

/// Why a scan's twist is not its own Doppler + model (or gyro) twist: every fallback and every
/// substitution has exactly one cause, which `dorado odometry` counts.
enum class FallbackCause {
    kNone,              ///< the scan's own twist
    kInvalidVelocity,   ///< no valid ego-velocity (EgoVelocityResult::failure says why)
    kNoImuSamples,      ///< imu / imu+doppler: no gyro sample in the scan interval
    kAngularRateLimit,  ///< the Doppler model's |omega| above max_angular_rate_radps
    kDopplerRotation,   ///< imu+doppler without gyro samples: the Doppler model's rotation used
};

/// "none" | "invalid_velocity" | "no_imu_samples" | "angular_rate_limit" | "doppler_rotation".
[[nodiscard]] const char *ToString(FallbackCause cause);

struct DopplerOdometryConfig {
    EgoVelocityConfig ego_velocity;
    OdometryMethod method = OdometryMethod::kDoppler;
    /// Stationary scans (see EgoVelocityConfig::stationary_speed_mps) integrate a zero twist.
    bool zero_velocity_update = true;
    /// A Doppler-derived |omega| above this is treated like an invalid scan (fallback) [rad/s].
    double max_angular_rate_radps = 2.0;
    /// The radar's velocity changes by at most this between scans [m/s^2] (a car braking at
    /// 1 g; the lever arm's share of a turn's angular acceleration included): RANSAC's hypotheses
    /// are held within (this * dt + 3 sigma of the previous velocity) of the previous scan's
    /// velocity, so that a crowd moving together cannot take the scan by a jump no vehicle makes
    /// (EgoVelocityEstimator::Estimate with a VelocityPrediction). Only after a scan with a valid
    /// velocity; a scan nothing inside explains is estimated without it. 0 = off. 10 by default:
    /// with the online calibration's gate at chi^2 6.63 the doppler-prior maps' ATE goes
    /// 0.564 -> 0.385 m pooled over xsim seeds 100-102 (flat_fast s101 1.87 -> 0.09 m) and
    /// 0.261 -> 0.245 m over 20 built-in runs (docs/robust_mapping.md).
    double max_acceleration_mps2 = 10.0;
    /// Integrate KinematicModel::PlausibleTwist (eq. 5 combined with the vehicle's angular-rate
    /// prior) instead of eq. (5)'s twist as is. They agree to a few percent where eq. (5) is well
    /// conditioned; near an ICR axis (a side mount) the raw pitch or yaw rate is noise.
    bool angular_rate_prior = true;
    /// Roll and pitch corrected per scan by the ground plane (ground_attitude.hpp). The plane
    /// fit's elevation noise comes from ego_velocity.sensor when it has one, the road's height
    /// from VehicleGeometry::base_height_m (unknown: no observation, kNoBaseHeight).
    GroundAttitudeConfig ground;
    /// Online calibration of eq. (5)'s yaw lever s_x from the map's registered yaw (the front end
    /// runs it when the mapper runs; DopplerOdometry itself only takes the result, SetYawLever).
    YawCalibrationConfig online_calibration;

    /// Throws std::invalid_argument naming the first bad field.
    void Validate() const;
};

/// What happened to one scan.
struct OdometryStep {
    int64_t stamp_ns = 0;
    double dt_s = 0.0;        ///< time integrated for this scan (0 for the first)
    bool integrated = false;  ///< false for a scan skipped for its stamp
    std::string skip_reason;
    EgoVelocityResult ego;
    VehicleMotion motion;  ///< from the kinematic model, eq. (5) and (7) (when ego.valid)
    Eigen::Vector3d v_base_used_mps = Eigen::Vector3d::Zero();  ///< the twist integrated
    Eigen::Vector3d omega_base_used_radps = Eigen::Vector3d::Zero();
    /// Covariance of [v_base_used; omega_base_used]: eq. (7) plus the kinematic model's own error
    /// (the angular-rate prior's posterior when angular_rate_prior is on); with the gyro
    /// (kImuDoppler), eq. (7)'s blocks. Zero for a fallback twist.
    Matrix6d covariance_used = Matrix6d::Zero();
    bool used_fallback = false;
    FallbackCause fallback_cause = FallbackCause::kNone;  ///< kNone iff !used_fallback
    std::string fallback_reason;                          ///< the cause in words, with numbers
    bool zero_velocity_update = false;  ///< a stationary scan: a zero twist was integrated
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();  ///< pose after this scan
    /// The ground-plane attitude update (when config.ground.enabled and the scan was integrated);
    /// ground.observation.fallback names why a scan gave no ground.
    GroundAttitudeStep ground;
    /// The scan went through the planar chain (a 2D radar: ego-velocity in the plane, yaw rate
    /// from PlanarKinematicModel, z, roll and pitch held).
    bool planar = false;
    /// ScanGeometry::kAuto decided on this scan that the radar is 2D (every z is 0): once.
    bool planar_detected = false;
};

class DopplerOdometry {
  public:
    /// Validates the config; throws std::invalid_argument for a bad config, an unobservable
    /// mounting (see KinematicModel) or Doppler-only rotation (OdometryMethod::kDoppler) on a
    /// VehicleModel::kUnconstrained platform.
    DopplerOdometry(DopplerOdometryConfig config, const Extrinsics &extrinsics,
                    const VehicleGeometry &geometry);

    /// Processes one scan. `gyro_base_radps` is the mean gyro rate over the interval since the
    /// previous scan, rotated into the base frame (NaN when there is no IMU); it is needed only
    /// for OdometryMethod::kImu / kImuDoppler. The pose integrates the twist over the real time
    /// since the previously integrated scan, so dropped scans lose no time:
    ///   T_world_base(k) = T_world_base(k-1) * ExpSE3([v_base; omega_base] * dt)
    /// (exact for a twist constant over the interval). Never throws on bad data.
    OdometryStep Register(const RadarScan &scan_radar,
                          const Eigen::Vector3d &gyro_base_radps = Eigen::Vector3d::Constant(NAN));

    /// Base poses, one per integrated scan; the first is T_world_base = initial pose.
    [[nodiscard]] const Trajectory &trajectory() const { return trajectory_; }
    [[nodiscard]] const KinematicModel &model() const { return model_; }
    /// The ground-plane settings in use (the config's, with the vehicle's base height and the
    /// radar's elevation noise).
    [[nodiscard]] const GroundAttitudeConfig &ground_config() const {
        return ground_filter_.config();
    }
    void SetInitialPose(const Eigen::Isometry3d &T_world_base) { T_world_base_ = T_world_base; }
    /// eq. (5)'s yaw lever from the next scan on (KinematicModel::SetYawLever; the online
    /// calibration's estimate). The 3-D chain only.
    void SetYawLever(double s_x_m) { model_.SetYawLever(s_x_m); }
    /// Starts over at T_world_base: the next scan integrates nothing (as a first scan) and no
    /// earlier twist is reused, but stamps must still come after the last scan's.
    void Restart(const Eigen::Isometry3d &T_world_base);

  private:
    // Chooses the twist to integrate for this scan (fills step.*_used and the fallback fields).
    void ChooseTwist(const Eigen::Vector3d &gyro_base_radps, OdometryStep &step);
    // Fits the ground to the scan's static points and corrects roll and pitch with it.
    void CorrectAttitude(const RadarScan &scan_radar, OdometryStep &step);
    // ScanGeometry::kAuto: decides 2D or 3-D at the first scan with points.
    void DecideGeometry(const RadarScan &scan_radar, OdometryStep &step);
    // The planar chain's ego-velocity and motion (planar_ego_velocity.hpp, eq. 5 in the plane).
    void EstimatePlanar(const RadarScan &scan_radar, OdometryStep &step);
    // The 3-D ego-velocity, held near the previous scan's (max_acceleration_mps2).
    EgoVelocityResult EstimateVelocity(const RadarScan &scan_radar);

    DopplerOdometryConfig config_;
    EgoVelocityEstimator estimator_;
    KinematicModel model_;
    Eigen::Isometry3d T_base_radar_;
    GroundAttitudeFilter ground_filter_;
    Trajectory trajectory_;
    Eigen::Isometry3d T_world_base_ = Eigen::Isometry3d::Identity();
    bool has_last_stamp_ = false;
    bool restarted_ = false;  ///< the next scan integrates nothing
    int64_t last_stamp_ns_ = 0;
    // The previous scan's radar velocity, when it was valid (the next scan's prediction).
    std::optional<VelocityPrediction> last_velocity_;
    bool has_last_twist_ = false;
    Eigen::Vector3d last_v_base_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d last_omega_base_ = Eigen::Vector3d::Zero();
    // The planar chain (a 2D radar): chosen by ego_velocity.sensor.geometry, or at the first
    // scan when it is kAuto.
    PlanarEgoVelocityEstimator planar_estimator_;
    std::optional<PlanarKinematicModel> planar_model_;
    std::string planar_model_error_;  ///< why planar_model_ could not be built (auto mode)
    bool planar_ = false;
    bool geometry_decided_ = false;
    Extrinsics extrinsics_;
    VehicleGeometry geometry_;
};

}  // namespace dorado::odometry
