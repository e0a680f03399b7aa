#include "dorado/odometry/doppler_odometry.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/odometry/vehicle_velocity_prior.hpp"

namespace dorado::odometry {

const char *ToString(OdometryMethod method) {
    switch (method) {
        case OdometryMethod::kDoppler:
            return "doppler";
        case OdometryMethod::kImu:
            return "imu";
        case OdometryMethod::kImuDoppler:
            return "imu+doppler";
    }
    return "?";
}

const char *ToString(FallbackCause cause) {
    switch (cause) {
        case FallbackCause::kNone:
            return "none";
        case FallbackCause::kInvalidVelocity:
            return "invalid_velocity";
        case FallbackCause::kNoImuSamples:
            return "no_imu_samples";
        case FallbackCause::kAngularRateLimit:
            return "angular_rate_limit";
        case FallbackCause::kDopplerRotation:
            return "doppler_rotation";
    }
    return "?";
}

OdometryMethod ParseOdometryMethod(const std::string &name) {
    for (OdometryMethod m :
         {OdometryMethod::kDoppler, OdometryMethod::kImu, OdometryMethod::kImuDoppler}) {
        if (name == ToString(m)) return m;
    }
    std::string hint;
    if (name == "imu-only") hint = " ('imu-only' is now 'imu'; the old 'imu' is 'imu+doppler')";
    throw std::invalid_argument("'" + name + "' is not one of: doppler, imu, imu+doppler" + hint);
}

void DopplerOdometryConfig::Validate() const {
    ego_velocity.Validate();
    ground.Validate();
    online_calibration.Validate();
    if (!(max_acceleration_mps2 >= 0.0) || !std::isfinite(max_acceleration_mps2))
        throw std::invalid_argument("odometry.max_acceleration_mps2: must be >= 0 (0 = off)");
    if (!(max_angular_rate_radps > 0.0))
        throw std::invalid_argument("odometry.max_angular_rate_radps: must be > 0");
}

namespace {

// The Doppler alone gives a rotation only through a kinematic constraint.
const DopplerOdometryConfig &CheckedFor(const DopplerOdometryConfig &config,
                                        const VehicleGeometry &geometry) {
    config.Validate();
    if (geometry.model == VehicleModel::kUnconstrained && config.method == OdometryMethod::kDoppler)
        throw std::invalid_argument(
            "vehicle.model: unconstrained (no kinematic constraint: hand-held, drone, legged) "
            "gives no rotation from the Doppler; use the gyro: --method imu+doppler (Doppler "
            "velocity, gyro rotation) or --method imu (prior imu+doppler for dorado map)");
    return config;
}

}  // namespace

DopplerOdometry::DopplerOdometry(DopplerOdometryConfig config, const Extrinsics &extrinsics,
                                 const VehicleGeometry &geometry)
    : config_(CheckedFor(config, geometry)),
      estimator_(config_.ego_velocity),
      model_(extrinsics, geometry),
      T_base_radar_(extrinsics.T_base_radar),
      ground_filter_([this, &geometry] {
          GroundAttitudeConfig ground = config_.ground;
          const double sigma = config_.ego_velocity.sensor.elevation_sigma_deg;
          if (sigma > 0.0) ground.plane.elevation_sigma_deg = sigma;
          ground.plane.base_height_m = geometry.base_height_m;
          return ground;
      }()),
      planar_estimator_(config_.ego_velocity),
      extrinsics_(extrinsics),
      geometry_(geometry) {
    const ScanGeometry kind = config_.ego_velocity.sensor.geometry;
    geometry_decided_ = kind != ScanGeometry::kAuto;
    planar_ = kind == ScanGeometry::kPlanar;
    if (planar_) planar_model_.emplace(extrinsics, geometry);  // throws for s_x = 0
}

void DopplerOdometry::DecideGeometry(const RadarScan &scan_radar, OdometryStep &step) {
    if (geometry_decided_ || scan_radar.size() < 3) return;
    geometry_decided_ = true;
    planar_ = IsPlanarScan(scan_radar);
    step.planar_detected = planar_;
    if (!planar_) return;
    try {
        planar_model_.emplace(extrinsics_, geometry_);
    } catch (const std::invalid_argument &e) {
        planar_model_error_ = e.what();
    }
}

void DopplerOdometry::EstimatePlanar(const RadarScan &scan_radar, OdometryStep &step) {
    step.planar = true;
    step.ego = planar_estimator_.Estimate(scan_radar);
    if (!planar_model_) {
        step.ego.failure = EgoVelocityFailure::kNoPlanarModel;
        step.ego.failure_detail = planar_model_error_;
        return;
    }
    if (step.ego.valid() && config_.method != OdometryMethod::kImu)
        step.motion = planar_model_->Motion(step.ego.v_radar_mps, step.ego.cov_v_radar);
}

EgoVelocityResult DopplerOdometry::EstimateVelocity(const RadarScan &scan_radar) {
    EgoVelocityResult ego;
    if (last_velocity_ && config_.max_acceleration_mps2 > 0.0 && !restarted_) {
        VelocityPrediction within = *last_velocity_;
        within.radius_mps +=
            config_.max_acceleration_mps2 * NanosToSeconds(scan_radar.stamp_ns - last_stamp_ns_);
        ego = estimator_.Estimate(scan_radar, within);
    } else {
        ego = estimator_.Estimate(scan_radar);
    }
    last_velocity_.reset();
    if (ego.valid() && config_.max_acceleration_mps2 > 0.0) {
        // The ball starts at the velocity's own 3 sigma (its largest direction).
        const double variance_max =
            Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(ego.cov_v_radar, Eigen::EigenvaluesOnly)
                .eigenvalues()
                .maxCoeff();
        last_velocity_ =
            VelocityPrediction{ego.v_radar_mps, 3.0 * std::sqrt(std::max(variance_max, 0.0))};
    }
    return ego;
}

OdometryStep DopplerOdometry::Register(const RadarScan &scan_radar,
                                       const Eigen::Vector3d &gyro_base_radps) {
    OdometryStep step;
    step.stamp_ns = scan_radar.stamp_ns;
    if (has_last_stamp_ && scan_radar.stamp_ns <= last_stamp_ns_) {
        step.skip_reason = "stamp " + std::to_string(scan_radar.stamp_ns) +
                           " ns is not after the previous scan's " + std::to_string(last_stamp_ns_);
        step.T_world_base = T_world_base_;
        return step;
    }
    DecideGeometry(scan_radar, step);
    if (planar_) {
        EstimatePlanar(scan_radar, step);
    } else {
        // Also for kImu: its `stationary` flag lets the front end estimate the gyro bias at rest.
        step.ego = EstimateVelocity(scan_radar);
        if (!step.ego.valid() && IsPlanarScan(scan_radar)) {  // radar.geometry 3d on a 2D radar
            const std::string hint = "every z is 0: a 2D radar; set radar.geometry planar or auto";
            std::string &detail = step.ego.failure_detail;
            detail = detail.empty() ? hint : detail + " (" + hint + ")";
        }
        if (step.ego.valid() && config_.method != OdometryMethod::kImu) {
            // The vehicle constraint (off by default): the base's lateral and vertical velocity
            // through eq. (5)'s model, v_base = J_v v_radar.
            const ConstrainedVelocity v = ApplyVehicleVelocityPrior(
                geometry_.velocity_prior, model_.VelocityJacobian(), Eigen::Vector3d::Zero(),
                step.ego.v_radar_mps, step.ego.cov_v_radar);
            step.motion = model_.Motion(v.v_radar_mps, v.cov_v_radar);
        }
    }
    ChooseTwist(gyro_base_radps, step);

    step.dt_s =
        has_last_stamp_ && !restarted_ ? NanosToSeconds(scan_radar.stamp_ns - last_stamp_ns_) : 0.0;
    restarted_ = false;
    Vector6d xi;
    xi << step.v_base_used_mps * step.dt_s, step.omega_base_used_radps * step.dt_s;
    // Frames: T_world_base(k) = T_world_base(k-1) * T_base(k-1)_base(k); the increment is the
    // body-frame twist integrated over dt.
    if (step.dt_s > 0.0) T_world_base_ = T_world_base_ * ExpSE3(xi);
    T_world_base_.linear() = ExpSO3(LogSO3(T_world_base_.linear()));  // keep R orthonormal
    if (config_.ground.enabled && !planar_) CorrectAttitude(scan_radar, step);
    trajectory_.Append(scan_radar.stamp_ns, T_world_base_);
    step.T_world_base = T_world_base_;
    step.integrated = true;
    has_last_stamp_ = true;
    last_stamp_ns_ = scan_radar.stamp_ns;
    return step;
}

void DopplerOdometry::Restart(const Eigen::Isometry3d &T_world_base) {
    T_world_base_ = T_world_base;
    restarted_ = true;
    ground_filter_.Reset();
    last_velocity_.reset();
    has_last_twist_ = false;
    last_v_base_.setZero();
    last_omega_base_.setZero();
}

void DopplerOdometry::CorrectAttitude(const RadarScan &scan_radar, OdometryStep &step) {
    ground_filter_.Predict(step.covariance_used.bottomRightCorner<3, 3>(), step.dt_s);
    if (!step.ego.valid()) {
        // No static mask: no ground either (counted with the scan's own fallback).
        step.ground.observation.fallback = GroundFallback::kNoVelocity;
        step.ground.cov_roll_pitch = ground_filter_.covariance();
        return;
    }
    // Frames: x_base = T_base_radar x_radar; the ground is sought among the static points, in
    // their order in the scan (only they are moved to the base frame). Each coordinate is
    // t + ((R_0 x + R_1 y) + R_2 z), rounded as Eigen's product of the isometry with the scan.
    const std::vector<PointLabel> &labels = step.ego.labels;
    const auto static_count = std::count(labels.begin(), labels.end(), PointLabel::kStatic);
    const Eigen::Matrix3d &R = T_base_radar_.linear();
    const Eigen::Vector3d &t = T_base_radar_.translation();
    Eigen::Matrix3Xd static_base(3, static_count);
    for (Eigen::Index i = 0, k = 0; i < scan_radar.size(); ++i) {
        if (labels[static_cast<std::size_t>(i)] != PointLabel::kStatic) continue;
        const double x = scan_radar.xyz_radar(0, i), y = scan_radar.xyz_radar(1, i),
                     z = scan_radar.xyz_radar(2, i);
        for (int r = 0; r < 3; ++r)
            static_base(r, k) = t[r] + ((R(r, 0) * x + R(r, 1) * y) + R(r, 2) * z);
        ++k;
    }
    const GroundObservation observation =
        FitGroundPlane(ground_filter_.config().plane, static_base,
                       std::vector<bool>(static_cast<std::size_t>(static_count), true));
    step.ground = ground_filter_.Update(observation, step.v_base_used_mps.norm() * step.dt_s,
                                        T_world_base_.linear());
    T_world_base_.linear() = step.ground.R_world_base;
}

void DopplerOdometry::ChooseTwist(const Eigen::Vector3d &gyro_base_radps, OdometryStep &step) {
    const bool has_gyro = gyro_base_radps.allFinite();
    auto fallback = [&](FallbackCause cause, const std::string &why) {
        step.used_fallback = true;
        step.fallback_cause = cause;
        step.fallback_reason = why + (has_last_twist_ ? "; used the last valid twist"
                                                      : "; no valid twist yet, used zero");
        step.v_base_used_mps = last_v_base_;
        step.omega_base_used_radps = last_omega_base_;
    };
    auto accept = [&](const Eigen::Vector3d &v, const Eigen::Vector3d &omega,
                      const Matrix6d &covariance) {
        step.v_base_used_mps = v;
        step.omega_base_used_radps = omega;
        step.covariance_used = covariance;
        last_v_base_ = v;
        last_omega_base_ = omega;
        has_last_twist_ = true;
    };

    if (config_.method == OdometryMethod::kImu) {
        if (has_gyro)
            accept(Eigen::Vector3d::Zero(), gyro_base_radps, Matrix6d::Zero());
        else
            fallback(FallbackCause::kNoImuSamples, "no IMU samples in the interval");
        return;
    }
    if (!step.ego.valid()) return fallback(FallbackCause::kInvalidVelocity, Describe(step.ego));
    // eq. (7)'s covariance with the model's own error, or the angular-rate prior's posterior.
    Eigen::Vector3d v_base = step.motion.v_base_mps, omega_base = step.motion.omega_base_radps;
    Matrix6d covariance;
    covariance << step.motion.cov_v_base, step.motion.cov_v_omega_base,
        step.motion.cov_v_omega_base.transpose(), step.motion.cov_omega_base;
    covariance += step.motion.cov_model;
    // The angular-rate prior is the 3-D model's (roll and pitch rates): not for the planar chain.
    if (config_.angular_rate_prior && model_.constrained() && !step.planar) {
        const Twist plausible = model_.PlausibleTwist(step.motion);
        v_base = plausible.v_base_mps;
        omega_base = plausible.omega_base_radps;
        covariance = plausible.covariance;
    }
    if (config_.zero_velocity_update && step.ego.stationary) {
        step.zero_velocity_update = true;
        return accept(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), covariance);
    }

    if (config_.method == OdometryMethod::kImuDoppler) {
        if (has_gyro) {
            // The gyro gives omega and v_base = v_s - omega x s: no model error.
            Matrix6d gyro_covariance = Matrix6d::Zero();
            gyro_covariance.topLeftCorner<3, 3>() = step.motion.cov_v_base;
            gyro_covariance.bottomRightCorner<3, 3>() = step.motion.cov_omega_base;
            if (step.planar) {  // in the plane: the gyro's yaw rate only
                const Eigen::Vector3d omega(0.0, 0.0, gyro_base_radps.z());
                return accept(planar_model_->BaseVelocity(step.ego.v_radar_mps, omega.z()), omega,
                              gyro_covariance);
            }
            // The vehicle constraint with the gyro's rotation: v_base = R v_radar - omega x s.
            const ConstrainedVelocity v =
                ApplyVehicleVelocityPrior(geometry_.velocity_prior, model_.SensorVelocityJacobian(),
                                          -gyro_base_radps.cross(model_.p_base_radar()),
                                          step.ego.v_radar_mps, step.ego.cov_v_radar);
            return accept(model_.BaseVelocity(v.v_radar_mps, gyro_base_radps), gyro_base_radps,
                          gyro_covariance);
        }
        if (!model_.constrained() || (step.planar && !planar_model_->constrained()))
            return fallback(FallbackCause::kNoImuSamples,
                            "no IMU samples in the interval (an unconstrained platform has no "
                            "rotation without the gyro)");
        step.fallback_reason = "no IMU samples in the interval: rotation from the Doppler model";
        step.fallback_cause = FallbackCause::kDopplerRotation;
        step.used_fallback = true;
    }
    if (omega_base.norm() > config_.max_angular_rate_radps) {
        return fallback(FallbackCause::kAngularRateLimit,
                        "angular rate " + std::to_string(omega_base.norm()) +
                            " rad/s above max_angular_rate_radps");
    }
    const std::string note = step.fallback_reason;
    accept(v_base, omega_base, covariance);
    step.fallback_reason = note;
}

}  // namespace dorado::odometry
