#include "dorado/frontend/radar_front_end.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "dorado/core/gyro_bias.hpp"
#include "dorado/core/time.hpp"

namespace dorado::frontend {
namespace {

using Clock = std::chrono::steady_clock;

// With the mapper on, the odometry's method follows the prior: the imu+doppler prior needs the
// gyro-rotation chain, every other prior the Doppler model's (gyro-only odometry has no Doppler
// velocity, hence no mask).
// On an unconstrained platform (no Doppler rotation) the priors that do not use the odometry's
// twist (none, constvel, imu) run the gyro chain (kImu) for the mask; the doppler prior is refused.
odometry::DopplerOdometryConfig OdometryConfigFor(const FrontEndConfig &config,
                                                  const VehicleGeometry &geometry) {
    odometry::DopplerOdometryConfig odometry = config.odometry;
    if (config.run_mapper) {
        const bool unconstrained = geometry.model == VehicleModel::kUnconstrained;
        if (unconstrained && config.prior == mapping::PriorKind::kDoppler)
            throw std::invalid_argument(
                "vehicle.model: unconstrained (no kinematic constraint) gives no rotation from the "
                "Doppler: the doppler prior is refused; use --prior imu+doppler (gyro rotation, "
                "Doppler velocity)");
        odometry.method = config.prior == mapping::PriorKind::kImuDoppler
                              ? odometry::OdometryMethod::kImuDoppler
                          : unconstrained ? odometry::OdometryMethod::kImu
                                          : odometry::OdometryMethod::kDoppler;
    }
    return odometry;
}

// The window smoother's kinematic factor is the paper's constraint: none on an unconstrained
// platform.
mapping::MapperConfig MapperConfigFor(mapping::MapperConfig mapper,
                                      const VehicleGeometry &geometry) {
    if (geometry.model == VehicleModel::kUnconstrained) mapper.window.use_kinematic_model = false;
    return mapper;
}

// The prior's twist from the odometry's (block-diagonal: the mapper's prior drops the v-omega
// cross-covariance).
mapping::BaseTwist PriorTwist(const odometry::OdometryStep &step) {
    return {step.v_base_used_mps, step.omega_base_used_radps,
            step.covariance_used.topLeftCorner<3, 3>(),
            step.covariance_used.bottomRightCorner<3, 3>()};
}

// The mask's outliers whose Doppler is farther than min_speed_mps from a static point's,
// -d . v_radar (unwrapped into the radar's unambiguous interval): seen moving, not noisy.
mapping::PointMask SeenMoving(const RadarScan &scan, const odometry::EgoVelocityResult &ego,
                              const RadarSensorModel &sensor, double min_speed_mps) {
    mapping::PointMask moving = mapping::PointMask::Constant(scan.size(), false);
    const double v = sensor.doppler_unambiguous_mps;
    for (Eigen::Index i = 0; i < scan.size(); ++i) {
        if (ego.labels[static_cast<std::size_t>(i)] != odometry::PointLabel::kDynamic) continue;
        const Eigen::Vector3d p = scan.xyz_radar.col(i);
        if (!p.allFinite() || !std::isfinite(scan.doppler_mps(i)) || p.norm() <= 0.0) continue;
        double residual = scan.doppler_mps(i) + p.normalized().dot(ego.v_radar_mps);
        if (v > 0.0) residual -= 2.0 * v * std::round(residual / (2.0 * v));
        moving(i) = std::abs(residual) > min_speed_mps;
    }
    return moving;
}

}  // namespace

const char *ToString(PriorSubstitution cause) {
    switch (cause) {
        case PriorSubstitution::kNone:
            return "";
        case PriorSubstitution::kNoImuSamples:
            return "no imu samples";
        case PriorSubstitution::kInvalidDopplerVelocity:
            return "doppler: no valid velocity";
        case PriorSubstitution::kDiscontinuousTwist:
            return "doppler: twist discontinuous with the previous one";
        case PriorSubstitution::kAngularRateLimit:
            return "doppler: angular rate above max_angular_rate_radps";
    }
    return "?";
}

SubstitutionCause SubstitutionCauseOf(const FrontEndResult &result) {
    const bool ego = result.prior_substitution == PriorSubstitution::kInvalidDopplerVelocity;
    return {result.prior_substitution,
            ego ? result.odometry.ego.failure : odometry::EgoVelocityFailure::kNone};
}

std::string SubstitutionKey(const SubstitutionCause &cause) {
    if (cause.first == PriorSubstitution::kInvalidDopplerVelocity)
        return std::string("doppler: ") + odometry::ToString(cause.second);
    return ToString(cause.first);
}

void FrontEndConfig::Validate() const {
    odometry.Validate();
    if (run_mapper) {
        mapper.Validate();
        prior_noise.Validate();
    }
}

struct RadarFrontEnd::State {
    State(FrontEndConfig c, const Extrinsics &e, const VehicleGeometry &g)
        : config((c.Validate(), std::move(c))),
          extrinsics(e),
          geometry(g),
          odometry(OdometryConfigFor(config, g), e, g),
          prior_ground(odometry.ground_config()) {
        if (config.run_mapper) mapper.emplace(MapperConfigFor(config.mapper, g), e, g);
        if (config.run_mapper && config.odometry.online_calibration.enabled &&
            g.model != VehicleModel::kUnconstrained)
            yaw_calibrator.emplace(config.odometry.online_calibration,
                                   e.T_base_radar.translation().x());
    }

    FrontEndConfig config;
    Extrinsics extrinsics;
    VehicleGeometry geometry;
    odometry::DopplerOdometry odometry;
    std::optional<mapping::RadarMapper> mapper;
    ImuWindow imu;
    GyroBiasEstimator gyro_bias;  // from the stationary scans, subtracted from every gyro rate
    // The ground-plane attitude on the mapper's chain: the doppler prior's roll and pitch
    // corrected by the scan's ground plane, as the odometry corrects its own (ground.enabled).
    odometry::GroundAttitudeFilter prior_ground;
    // eq. (5)'s yaw lever from the map's registered yaw (odometry.online_calibration).
    std::optional<odometry::YawRateCalibrator> yaw_calibrator;
    Trajectory trajectory;
    Eigen::Isometry3d T_world_base_initial = Eigen::Isometry3d::Identity();
    // The last two accepted poses since the last reset (constvel, imu priors).
    int scans_since_reset = 0;
    Eigen::Isometry3d T_prev = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_prev2 = Eigen::Isometry3d::Identity();
    double last_dt_s = 0.0;
    bool has_last = false;
    int64_t last_stamp_ns = 0;
    // The previous scan's Doppler twist, when it was a measurement (the trapezoid prior).
    std::optional<mapping::BaseTwist> last_twist;
    // The last twist that passed the continuity test, and the time since it [s].
    std::optional<mapping::BaseTwist> last_plausible_twist;
    double since_plausible_s = 0.0;

    // Whether this scan's Doppler twist is continuous with the last plausible one: the change
    // within the twists' covariances plus the constvel prior's accelerations over the time
    // between them (chi^2 at 99.9 % per 3-dof block; the v block alone with the gyro's rotation,
    // imu+doppler).
    // A RANSAC that locked onto a crowd moving with the vehicle jumps by metres per second in one
    // scan. After a second of refusals the twist is taken again (the vehicle did change).
    bool TwistIsContinuous(const odometry::OdometryStep &step) {
        const mapping::BaseTwist twist = PriorTwist(step);
        const bool fresh = !last_plausible_twist || since_plausible_s + step.dt_s > 1.0;
        if (!fresh) {
            const mapping::BaseTwist &last = *last_plausible_twist;
            const double dt = since_plausible_s + step.dt_s;
            const mapping::PriorNoiseConfig &noise = config.prior_noise;
            // One block's change against both twists' covariances plus an acceleration over dt.
            const auto chi2_of = [dt](const Eigen::Vector3d &d, const Eigen::Matrix3d &C,
                                      double sigma_accel) {
                const Eigen::Matrix3d S =
                    C + Eigen::Matrix3d::Identity() * std::pow(sigma_accel * dt, 2);
                return d.dot(S.ldlt().solve(d));
            };
            double chi2 =
                chi2_of(twist.v_base_mps - last.v_base_mps, twist.cov_v_base + last.cov_v_base,
                        noise.constvel_sigma_accel_mps2);
            if (config.prior == mapping::PriorKind::kDoppler)
                chi2 = std::max(chi2, chi2_of(twist.omega_base_radps - last.omega_base_radps,
                                              twist.cov_omega_base + last.cov_omega_base,
                                              noise.constvel_sigma_angular_accel_radps2));
            constexpr double kGate = 16.27;  // chi^2(3) at 99.9 %, each block
            if (!(chi2 <= kGate)) {
                since_plausible_s += step.dt_s;
                return false;
            }
        }
        last_plausible_twist = twist;
        since_plausible_s = 0.0;
        return true;
    }

    // Hands the registered pose's yaw to the calibrator; its new estimate drives the next scans.
    void CalibrateYawLever(FrontEndResult &result);

    mapping::MotionPrior BuildPrior(const odometry::OdometryStep &step, int64_t stamp_ns,
                                    double dt_s, FrontEndResult &result) const;
    // The twist the doppler priors hold over the interval (prior.doppler_integration). The
    // trapezoid needs the previous scan's twist at the interval's start, at the usual cadence:
    // after a gap (a dropped scan or more: an interval over 1.5 times the previous one) that twist
    // is stale and the scan's own is held, as the odometry does.
    mapping::BaseTwist IntervalTwist(const odometry::OdometryStep &step) const {
        const mapping::BaseTwist twist = PriorTwist(step);
        if (config.prior_noise.doppler_integration != mapping::TwistIntegration::kTrapezoid ||
            !last_twist || !(last_dt_s > 0.0 && step.dt_s <= 1.5 * last_dt_s))
            return twist;
        return mapping::TrapezoidTwist(*last_twist, twist);
    }
};

mapping::MotionPrior RadarFrontEnd::State::BuildPrior(const odometry::OdometryStep &step,
                                                      int64_t stamp_ns, double dt_s,
                                                      FrontEndResult &result) const {
    using mapping::PriorKind;
    const PriorKind kind = config.prior;
    result.prior_requested = kind;
    result.prior_used = kind;
    if (scans_since_reset == 0) {  // the first scan defines the world
        mapping::MotionPrior prior;
        prior.T_world_base = T_world_base_initial;
        prior.covariance = Matrix6d::Identity() * 1e-6;
        prior.kind = kind;  // unused: the first scan starts the map
        result.prior_first_scan = true;
        return prior;
    }
    const bool has_two = scans_since_reset >= 2 && last_dt_s > 0.0;
    const mapping::PriorNoiseConfig &noise = config.prior_noise;
    auto constvel = [&] {
        return has_two ? mapping::PriorConstantVelocity(T_prev2, T_prev, last_dt_s, dt_s, noise)
                       : mapping::PriorFromPreviousPose(T_prev, noise);
    };
    std::optional<mapping::MotionPrior> built;
    PriorSubstitution why_not = PriorSubstitution::kNone;
    const std::vector<ImuSample> imu_samples = gyro_bias.Corrected(imu.samples());
    switch (kind) {
        case PriorKind::kNone:
            built = mapping::PriorFromPreviousPose(T_prev, noise);
            break;
        case PriorKind::kConstVel:
            built = constvel();
            break;
        case PriorKind::kImu: {
            std::optional<Eigen::Vector3d> v_world;  // unknown from one pose
            if (has_two) v_world = (T_prev.translation() - T_prev2.translation()) / last_dt_s;
            built = mapping::PriorFromImu(T_prev, v_world, imu_samples, last_stamp_ns, stamp_ns,
                                          extrinsics.T_base_imu, noise);
            if (!built) why_not = PriorSubstitution::kNoImuSamples;
            break;
        }
        case PriorKind::kDoppler:
        case PriorKind::kImuDoppler:
            // The odometry's twist honours every odometry setting; a fallback twist (no valid
            // velocity, an implausible angular rate) is not a measurement: substitute.
            if (step.fallback_cause == odometry::FallbackCause::kInvalidVelocity) {
                why_not = PriorSubstitution::kInvalidDopplerVelocity;
            } else if (result.doppler_twist_discontinuous) {
                why_not = PriorSubstitution::kDiscontinuousTwist;
            } else if (step.fallback_cause == odometry::FallbackCause::kAngularRateLimit) {
                why_not = PriorSubstitution::kAngularRateLimit;
            } else if (step.fallback_cause == odometry::FallbackCause::kNoImuSamples) {
                why_not = PriorSubstitution::kNoImuSamples;
            } else if (kind == PriorKind::kDoppler) {
                built = mapping::PriorFromDoppler(T_prev, IntervalTwist(step), dt_s, noise);
            } else {
                built = mapping::PriorFromImuAndDoppler(T_prev, IntervalTwist(step), imu_samples,
                                                        last_stamp_ns + 1, stamp_ns,
                                                        extrinsics.T_base_imu, dt_s, noise);
                if (!built) why_not = PriorSubstitution::kNoImuSamples;
            }
            // Not after a gap (the last motion is stale, as for the trapezoid) nor on a
            // stationary scan (the zero twist is exact).
            if (built && noise.doppler_with_constvel && has_two && dt_s <= 1.5 * last_dt_s &&
                !step.zero_velocity_update)
                built = mapping::FusePriors(*built, constvel());
            break;
    }
    if (!built) {
        result.prior_used = PriorKind::kConstVel;
        result.prior_substitution = why_not;
        if (why_not == PriorSubstitution::kInvalidDopplerVelocity)
            result.prior_substitution_detail = step.ego.failure_detail;
        built = constvel();
    }
    return *built;
}

void RadarFrontEnd::State::CalibrateYawLever(FrontEndResult &result) {
    const odometry::OdometryStep &step = result.odometry;
    if (step.planar) {  // a 2D radar's model (Ackermann in the plane) has no eq. 5 lever
        result.yaw_calibration = {};
        return;
    }
    const mapping::RegistrationResult &reg = result.registration;
    // A window needs every scan's own Doppler yaw (eq. 5 on this scan's velocity, no fallback)
    // and every pose registered, with the yaw among the directions the map observes.
    const bool own_twist = step.ego.valid() && !step.used_fallback && !step.planar;
    const bool yaw_observed = reg.first_scan || (reg.registered.valid && !reg.fallback() &&
                                                 reg.registered.strong_projector(5, 5) > 0.5);
    const Eigen::Matrix3d R_world_base =
        reg.registered.valid ? reg.registered.T_world_base.linear() : reg.T_world_base.linear();
    const double v_sy =
        own_twist ? (odometry.model().SensorVelocityJacobian() * step.ego.v_radar_mps).y() : 0.0;
    result.yaw_calibration = yaw_calibrator->AddScan(step.dt_s, v_sy, step.v_base_used_mps.norm(),
                                                     own_twist && yaw_observed, R_world_base);
    if (result.yaw_calibration.status == odometry::YawCalibrationStatus::kUpdated)
        odometry.SetYawLever(result.yaw_calibration.s_x_m);
}

// The plane's normal (-a, -b, 1) normalised; its x and y are -sin(pitch) and sin(roll) cos(pitch),
// so to first order their covariance is the fit's roll/pitch covariance turned by 90 degrees.
mapping::GroundUp GroundUpFromFit(const odometry::GroundObservation &fit,
                                  const odometry::GroundAttitudeConfig &ground) {
    mapping::GroundUp up;
    up.up_base = Eigen::Vector3d(-fit.slope.x(), -fit.slope.y(), 1.0).normalized();
    Eigen::Matrix2d M;
    M << 0.0, -1.0, 1.0, 0.0;  // [up_x, up_y] = M [roll, pitch] to first order
    const double slope_rad = ground.road_slope_sigma_deg * M_PI / 180.0;
    up.covariance = M * fit.cov_roll_pitch * M.transpose() +
                    slope_rad * slope_rad * Eigen::Matrix2d::Identity();
    up.max_innovation_chi2 = ground.max_innovation_chi2;
    return up;
}

RadarFrontEnd::RadarFrontEnd(FrontEndConfig config, const Extrinsics &extrinsics,
                             const VehicleGeometry &geometry)
    : state_(std::make_unique<State>(std::move(config), extrinsics, geometry)) {}
RadarFrontEnd::~RadarFrontEnd() = default;
RadarFrontEnd::RadarFrontEnd(RadarFrontEnd &&) noexcept = default;
RadarFrontEnd &RadarFrontEnd::operator=(RadarFrontEnd &&) noexcept = default;

void RadarFrontEnd::AddImu(const ImuSample &sample) {
    state_->imu.Add(sample);
}

FrontEndResult RadarFrontEnd::Process(const RadarScan &scan_radar) {
    State &s = *state_;
    FrontEndResult result;
    result.stamp_ns = scan_radar.stamp_ns;
    result.T_world_base = s.scans_since_reset > 0 ? s.T_prev : s.T_world_base_initial;
    const auto t_start = Clock::now();
    // 1. Doppler: ego-velocity, mask, the vehicle twist (eq. 2, 5, 7) and dead reckoning.
    const Eigen::Vector3d gyro_base =
        s.has_last ? Eigen::Vector3d(s.extrinsics.T_base_imu.linear() *
                                     (s.imu.MeanGyro(s.last_stamp_ns, scan_radar.stamp_ns) -
                                      s.gyro_bias.bias_imu_radps()))
                   : Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    result.gyro_base_radps = gyro_base;
    result.odometry = s.odometry.Register(scan_radar, gyro_base);
    const odometry::OdometryStep &step = result.odometry;
    if (s.has_last)
        s.gyro_bias.AddInterval(step.ego.valid() && step.ego.stationary,
                                s.imu.Between(s.last_stamp_ns, scan_radar.stamp_ns));
    result.T_world_base_odometry = step.T_world_base;
    if (!step.integrated) {  // the one timestamp-order check, the odometry's (across resets too)
        result.skip_reason = step.skip_reason;
        return result;
    }
    result.accepted = true;
    result.dt_s = step.dt_s;
    result.twist_base = {step.v_base_used_mps, step.omega_base_used_radps, step.covariance_used};
    if (step.ego.valid()) {
        result.static_mask.resize(scan_radar.size());
        for (Eigen::Index i = 0; i < scan_radar.size(); ++i)
            result.static_mask(i) = step.ego.labels[i] == odometry::PointLabel::kStatic;
    }
    result.times.doppler_ms = MillisecondsSince(t_start);

    // 2-3. The prior, then registration, refinement and map update. A Doppler twist that jumps
    //      (RANSAC on a crowd moving with the vehicle) is neither the prior nor its mask's source.
    if (s.mapper && mapping::NeedsDoppler(s.config.prior) && step.ego.valid() &&
        step.fallback_cause == odometry::FallbackCause::kNone && s.scans_since_reset > 0)
        result.doppler_twist_discontinuous = !s.TwistIsContinuous(step);
    const mapping::PointMask *mask =
        s.config.use_mask && step.ego.valid() && !result.doppler_twist_discontinuous
            ? &result.static_mask
            : nullptr;
    if (s.mapper) {
        const auto t_prior = Clock::now();
        const double dt_s = s.scans_since_reset == 0 ? mapping::kFirstScanIntervalS : step.dt_s;
        result.prior = s.BuildPrior(step, scan_radar.stamp_ns, dt_s, result);
        // The ground (ground.enabled) reaches the radar-only map once: as a residual on the
        // refined poses' absolute roll and pitch when the mapper's refinement takes one (ceres,
        // filter; 3-D; priors without the gyro), otherwise in the doppler prior (below). Not
        // both: the prior's roll/pitch and the residual would count the same plane twice.
        const bool ground_factor = s.config.odometry.ground.enabled && !step.planar &&
                                   !mapping::NeedsImu(s.config.prior) &&
                                   mapping::RefinesWithCeres(s.config.mapper.refinement);
        std::optional<mapping::GroundUp> ground_up;
        if (ground_factor && step.ground.fit.valid)
            ground_up = GroundUpFromFit(step.ground.fit, s.odometry.ground_config());
        if (s.config.odometry.ground.enabled && !ground_factor &&
            result.prior_used == mapping::PriorKind::kDoppler) {
            // The twist carries no attitude correction: the prior's roll and pitch get the
            // ground's, filtered on the mapper's own chain (the first scan initialises them).
            odometry::GroundAttitudeStep ground;
            s.prior_ground.Predict(step.covariance_used.bottomRightCorner<3, 3>(), step.dt_s);
            s.prior_ground.Update(step.ground.fit, step.v_base_used_mps.norm() * step.dt_s,
                                  result.prior.T_world_base, ground);
        }
        result.times.prior_ms = MillisecondsSince(t_prior);
        if (step.planar && !s.mapper->planar()) s.mapper->SetPlanar();  // a 2D radar
        mapping::MapperInput input;
        input.prior = result.prior;
        input.dt_s = dt_s;
        if (mask != nullptr) {
            input.static_mask = *mask;
            input.moving_mask =
                SeenMoving(scan_radar, step.ego, s.config.odometry.ego_velocity.sensor,
                           s.config.mapper.movers.min_radial_speed_mps);
        }
        // The gyro feeds the window smoother when the prior is an IMU one.
        if (mapping::NeedsImu(s.config.prior) && gyro_base.allFinite())
            input.gyro_base_radps = gyro_base;
        input.ground_base = ground_up;
        result.registration = s.mapper->Register(scan_radar, input);
        result.times.mapper = result.registration.times;
        result.T_world_base = result.registration.T_world_base;
        if (s.yaw_calibrator) s.CalibrateYawLever(result);
    } else {
        result.T_world_base = step.T_world_base;
    }
    result.times.total_ms = MillisecondsSince(t_start);

    s.trajectory.Append(scan_radar.stamp_ns, result.T_world_base);
    s.T_prev2 = s.T_prev;
    s.T_prev = result.T_world_base;
    s.last_dt_s = s.scans_since_reset == 0 ? 0.0 : step.dt_s;
    if (step.fallback_cause == odometry::FallbackCause::kNone &&
        !result.doppler_twist_discontinuous)
        s.last_twist = PriorTwist(step);
    else
        s.last_twist.reset();
    ++s.scans_since_reset;
    s.has_last = true;
    s.last_stamp_ns = scan_radar.stamp_ns;
    // Samples before this scan are used; the one at its stamp still opens the next interval.
    s.imu.DropUpTo(scan_radar.stamp_ns - 1);
    return result;
}

void RadarFrontEnd::Reset(const Eigen::Isometry3d &T_world_base) {
    State &s = *state_;
    s.odometry.Restart(T_world_base);
    s.prior_ground.Reset();
    if (s.yaw_calibrator) s.yaw_calibrator->BreakWindow();
    if (s.mapper)
        s.mapper.emplace(MapperConfigFor(s.config.mapper, s.geometry), s.extrinsics, s.geometry);
    s.T_world_base_initial = T_world_base;
    s.scans_since_reset = 0;
    s.last_dt_s = 0.0;
    s.has_last = false;
    s.last_twist.reset();
    s.last_plausible_twist.reset();
    s.since_plausible_s = 0.0;
    // The trajectory keeps its poses: stamps stay increasing across a reset.
}

const Trajectory &RadarFrontEnd::trajectory() const {
    return state_->trajectory;
}
const mapping::LocalMap *RadarFrontEnd::local_map() const {
    return state_->mapper ? &state_->mapper->local_map() : nullptr;
}
void RadarFrontEnd::SetPrior(mapping::PriorKind prior) {
    state_->config.prior = prior;
}
const FrontEndConfig &RadarFrontEnd::config() const {
    return state_->config;
}
bool RadarFrontEnd::has_last_stamp() const {
    return state_->has_last;
}
int64_t RadarFrontEnd::last_stamp_ns() const {
    return state_->last_stamp_ns;
}

}  // namespace dorado::frontend
