#include "dorado/frontend/radar_front_end.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "dorado/core/time.hpp"
#include "front_end_state.hpp"

namespace dorado::frontend {
namespace {

using Clock = std::chrono::steady_clock;

// The ego-velocity's labels as the mapper's mask: true = static (empty without a valid
// ego-velocity).
mapping::PointMask StaticMask(const odometry::EgoVelocityResult &ego, Eigen::Index points) {
    mapping::PointMask mask;
    if (!ego.valid()) return mask;
    mask.resize(points);
    for (Eigen::Index i = 0; i < points; ++i)
        mask(i) = ego.labels[i] == odometry::PointLabel::kStatic;
    return mask;
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

RadarFrontEnd::State::State(FrontEndConfig c, const Extrinsics &e, const VehicleGeometry &g)
    : config((c.Validate(), std::move(c))),
      extrinsics(e),
      geometry(g),
      odometry(OdometryConfigFor(config, g), e, g) {
    if (config.run_mapper) mapper.emplace(config.mapper, e);
    if (config.run_mapper && config.odometry.online_calibration.enabled &&
        g.model != VehicleModel::kUnconstrained)
        yaw_calibrator.emplace(config.odometry.online_calibration,
                               e.T_base_radar.translation().x());
}

Eigen::Vector3d RadarFrontEnd::State::MeanGyroBase(int64_t stamp_ns) const {
    if (!has_last) return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    return extrinsics.T_base_imu.linear() *
           (imu.MeanGyro(last_stamp_ns, stamp_ns) - gyro_bias.bias_imu_radps());
}

MappedScan RadarFrontEnd::State::MapScan(const RadarScan &scan_radar,
                                         const odometry::OdometryStep &step,
                                         const mapping::PointMask &static_mask, bool use_mask,
                                         bool twist_discontinuous) {
    MappedScan out;
    const auto t_prior = Clock::now();
    const double dt_s = scans_since_reset == 0 ? mapping::kFirstScanIntervalS : step.dt_s;
    out.prior = BuildPrior(step, scan_radar.stamp_ns, dt_s, twist_discontinuous);
    // The ground (ground.enabled) holds the map's roll and pitch in the mapper's smoother (3-D;
    // not with the gyro's priors, whose attitude the IMU holds).
    const bool ground_factor =
        config.odometry.ground.enabled && !step.planar && !mapping::NeedsImu(config.prior);
    out.prior_ms = MillisecondsSince(t_prior);

    if (step.planar && !mapper->planar()) mapper->SetPlanar();  // a 2D radar
    mapping::MapperInput input;
    input.prior = out.prior.prior;
    input.dt_s = dt_s;
    if (use_mask) {
        input.static_mask = static_mask;
        input.moving_mask = SeenMoving(scan_radar, step.ego, config.odometry.ego_velocity.sensor,
                                       config.mapper.movers.min_radial_speed_mps);
    }
    if (ground_factor && step.ground.fit.valid)
        input.ground_base = GroundUpFromFit(step.ground.fit, odometry.ground_config());
    out.registration = mapper->Register(scan_radar, input);
    if (yaw_calibrator) out.yaw_calibration = CalibrateYawLever(step, out.registration);
    return out;
}

odometry::YawCalibrationStep RadarFrontEnd::State::CalibrateYawLever(
    const odometry::OdometryStep &step, const mapping::RegistrationResult &reg) {
    if (step.planar) return {};  // a 2D radar's model (Ackermann in the plane) has no eq. 5 lever
    // A window needs every scan's own Doppler yaw (eq. 5 on this scan's velocity, no fallback)
    // and every pose registered, with the yaw among the directions the map observes.
    const bool own_twist = step.ego.valid() && !step.used_fallback && !step.planar;
    const bool yaw_observed = reg.first_scan || (reg.registered.valid && !reg.fallback() &&
                                                 reg.registered.strong_projector(5, 5) > 0.5);
    const Eigen::Matrix3d R_world_base =
        reg.registered.valid ? reg.registered.T_world_base.linear() : reg.T_world_base.linear();
    const double v_sy =
        own_twist ? (odometry.model().SensorVelocityJacobian() * step.ego.v_radar_mps).y() : 0.0;
    const odometry::YawCalibrationStep calibration = yaw_calibrator->AddScan(
        step.dt_s, v_sy, step.v_base_used_mps.norm(), own_twist && yaw_observed, R_world_base);
    if (calibration.status == odometry::YawCalibrationStatus::kUpdated)
        odometry.SetYawLever(calibration.s_x_m);
    return calibration;
}

void RadarFrontEnd::State::Advance(int64_t stamp_ns, const odometry::OdometryStep &step,
                                   const Eigen::Isometry3d &T_world_base, bool twist_discontinuous,
                                   const std::vector<mapping::WrittenPose> *written) {
    if (written == nullptr)
        trajectory.Append(stamp_ns, T_world_base);
    else
        for (const mapping::WrittenPose &pose : *written)
            trajectory.Append(pose.stamp_ns, pose.T_world_base);
    T_world_base_prev2 = T_world_base_prev;
    T_world_base_prev = T_world_base;
    last_dt_s = scans_since_reset == 0 ? 0.0 : step.dt_s;
    if (step.fallback_cause == odometry::FallbackCause::kNone && !twist_discontinuous)
        last_twist = PriorTwist(step);
    else
        last_twist.reset();
    ++scans_since_reset;
    has_last = true;
    last_stamp_ns = stamp_ns;
    // Samples before this scan are used; the one at its stamp still opens the next interval.
    imu.DropUpTo(stamp_ns - 1);
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
    result.T_world_base = s.scans_since_reset > 0 ? s.T_world_base_prev : s.T_world_base_initial;
    const auto t_start = Clock::now();
    // 1. Doppler: ego-velocity, mask, the vehicle twist (eq. 2, 5, 7) and dead reckoning.
    result.gyro_base_radps = s.MeanGyroBase(scan_radar.stamp_ns);
    result.odometry = s.odometry.Register(scan_radar, result.gyro_base_radps);
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
    result.static_mask = StaticMask(step.ego, scan_radar.size());
    result.times.doppler_ms = MillisecondsSince(t_start);

    // 2-3. The prior, then registration, refinement and map update. A Doppler twist that jumps
    //      (RANSAC on a crowd moving with the vehicle) is neither the prior nor its mask's source.
    if (s.mapper && mapping::NeedsDoppler(s.config.prior) && step.ego.valid() &&
        step.fallback_cause == odometry::FallbackCause::kNone && s.scans_since_reset > 0)
        result.doppler_twist_discontinuous = !s.TwistIsContinuous(step);
    if (s.mapper) {
        const bool use_mask =
            s.config.use_mask && step.ego.valid() && !result.doppler_twist_discontinuous;
        MappedScan mapped = s.MapScan(scan_radar, step, result.static_mask, use_mask,
                                      result.doppler_twist_discontinuous);
        result.prior = mapped.prior.prior;
        result.prior_requested = mapped.prior.requested;
        result.prior_used = mapped.prior.used;
        result.prior_first_scan = mapped.prior.first_scan;
        result.prior_substitution = mapped.prior.substitution;
        result.prior_substitution_detail = std::move(mapped.prior.substitution_detail);
        result.times.prior_ms = mapped.prior_ms;
        result.registration = std::move(mapped.registration);
        result.times.mapper = result.registration.times;
        result.T_world_base = result.registration.T_world_base;
        result.yaw_calibration = mapped.yaw_calibration;
    } else {
        result.T_world_base = step.T_world_base;
    }
    result.times.total_ms = MillisecondsSince(t_start);
    s.Advance(scan_radar.stamp_ns, step, result.T_world_base, result.doppler_twist_discontinuous,
              s.mapper ? &result.registration.written : nullptr);
    return result;
}

std::vector<mapping::WrittenPose> RadarFrontEnd::Finish() {
    State &s = *state_;
    if (!s.mapper) return {};
    std::vector<mapping::WrittenPose> written = s.mapper->Finish();
    for (const mapping::WrittenPose &pose : written)
        s.trajectory.Append(pose.stamp_ns, pose.T_world_base);
    return written;
}

std::vector<mapping::WrittenPose> RadarFrontEnd::Reset(const Eigen::Isometry3d &T_world_base) {
    State &s = *state_;
    std::vector<mapping::WrittenPose> written = Finish();
    s.odometry.Restart(T_world_base);
    if (s.yaw_calibrator) s.yaw_calibrator->BreakWindow();
    if (s.mapper) s.mapper.emplace(s.config.mapper, s.extrinsics);
    s.T_world_base_initial = T_world_base;
    s.scans_since_reset = 0;
    s.last_dt_s = 0.0;
    s.has_last = false;
    s.last_twist.reset();
    s.last_plausible_twist.reset();
    s.since_plausible_s = 0.0;
    // The trajectory keeps its poses: stamps stay increasing across a reset.
    return written;
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
