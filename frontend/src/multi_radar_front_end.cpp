// Several 2D radars into one map (the steps in multi_radar_front_end.hpp).
#include "dorado/frontend/multi_radar_front_end.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "built_prior.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/mapping/measurements.hpp"
#include "dorado/odometry/planar_ego_velocity.hpp"

namespace dorado::frontend {
namespace {

using Clock = std::chrono::steady_clock;

// One radar's scan waiting for its sweep to close: its finite points in its own frame.
struct KeptScan {
    std::size_t radar = 0;
    int64_t stamp_ns = 0;
    Eigen::Matrix3Xd xyz_radar;
    Eigen::VectorXd power_db;
    mapping::PointMask static_mask, moving_mask;
};

// The filter's twist as the priors' Twist (the v-omega cross-covariance is not used). The plane's
// other three (v_z, roll and pitch rates) are held by the planar mapper: small spreads keep the
// prior positive definite.
Twist PriorTwistOf(const Eigen::Vector3d &twist, const Eigen::Matrix3d &P,
                   const VehicleVelocityPrior &velocity_prior) {
    Twist out;
    out.v_base_mps << twist(0), twist(1), 0.0;
    out.omega_base_radps << 0.0, 0.0, twist(2);
    out.covariance.topLeftCorner<2, 2>() = P.topLeftCorner<2, 2>();
    out.covariance(2, 2) = velocity_prior.sigma_vertical_mps * velocity_prior.sigma_vertical_mps;
    out.covariance.bottomRightCorner<3, 3>() = Eigen::Vector3d(1e-4, 1e-4, P(2, 2)).asDiagonal();
    return out;
}

}  // namespace

struct MultiRadarFrontEnd::State {
    State(FrontEndConfig c, std::vector<Eigen::Isometry3d> mounts, const Eigen::Isometry3d &imu,
          const VehicleGeometry &g, odometry::PlanarTwistFilterConfig filter_config)
        : config((c.Validate(), std::move(c))),
          T_base_radars(std::move(mounts)),
          T_base_imu(imu),
          geometry(g),
          estimator(config.odometry.ego_velocity),
          filter(filter_config, g.velocity_prior, T_base_radars),
          mapper(config.mapper, Extrinsics{}) {
        if (T_base_radars.empty()) throw std::invalid_argument("multi-radar front end: no radar");
        if (config.odometry.ego_velocity.sensor.geometry == ScanGeometry::k3d)
            throw std::invalid_argument(
                "multi-radar front end: radar.geometry 3d: several radars are mapped in the plane "
                "(2D radars); a 3-D radar maps alone (one radar, `folder:`)");
        if (!config.run_mapper) throw std::invalid_argument("multi-radar front end: mapper off");
        mapper.SetPlanar();
    }

    void Keep(std::size_t radar, const RadarScan &scan, const odometry::EgoVelocityResult &ego);
    /// The kept scans as one cloud in the base frame, with their masks.
    struct MergedSweep {
        RadarScan scan;
        mapping::PointMask static_mask, moving_mask;
    };
    [[nodiscard]] MergedSweep MergedCloud(int64_t stamp_ns) const;
    [[nodiscard]] BuiltPrior BuildPrior(int64_t stamp_ns, double dt_s) const;
    FrontEndResult CloseSweep(int64_t stamp_ns);

    FrontEndConfig config;
    std::vector<Eigen::Isometry3d> T_base_radars;
    Eigen::Isometry3d T_base_imu;
    VehicleGeometry geometry;
    odometry::PlanarEgoVelocityEstimator estimator;
    odometry::PlanarTwistFilter filter;
    mapping::RadarMapper mapper;
    ImuWindow imu;
    Trajectory trajectory;
    std::vector<KeptScan> kept;
    bool twist_measured_in_sweep = false;  // some radar updated the filter since the last sweep
    int sweeps = 0;
    int64_t last_sweep_ns = 0;
    double last_dt_s = 0.0;
    double sweep_doppler_ms = 0.0;  // the kept scans' ego-velocities and twist updates
    Eigen::Isometry3d T_world_base_prev = Eigen::Isometry3d::Identity(),
                      T_world_base_prev2 = T_world_base_prev;
    Eigen::Isometry3d T_world_base_odometry = Eigen::Isometry3d::Identity();
    std::optional<Twist> last_twist;
};

// The scan's finite points and their labels: the radar's own mask when its ego-velocity is
// valid; else, once the filter knows the twist, the points whose Doppler agrees with what the
// twist predicts for a static point at this radar (within the movers' min_radial_speed_mps);
// else none (a radar that saw only movers adds nothing).
void MultiRadarFrontEnd::State::Keep(std::size_t radar, const RadarScan &scan,
                                     const odometry::EgoVelocityResult &ego) {
    const double min_speed = config.mapper.movers.min_radial_speed_mps;
    const bool filter_knows = filter.stamp_ns().has_value() && filter.covariance()(0, 0) < 1.0;
    const Eigen::Vector3d v_radar = ego.valid() ? ego.v_radar_mps : filter.RadarVelocity(radar);
    KeptScan k;
    k.radar = radar;
    k.stamp_ns = scan.stamp_ns;
    std::vector<Eigen::Index> finite;
    for (Eigen::Index i = 0; i < scan.size(); ++i)
        if (scan.xyz_radar.col(i).allFinite() && scan.xyz_radar.col(i).norm() > 0.0)
            finite.push_back(i);
    const auto n = static_cast<Eigen::Index>(finite.size());
    k.xyz_radar.resize(3, n);
    k.power_db.resize(n);
    k.static_mask.resize(n);
    k.moving_mask.resize(n);
    for (Eigen::Index j = 0; j < n; ++j) {
        const Eigen::Index i = finite[static_cast<std::size_t>(j)];
        k.xyz_radar.col(j) = scan.xyz_radar.col(i);
        k.power_db(j) = scan.power_db.size() > i ? scan.power_db(i) : 0.0;
        const double residual =
            scan.doppler_mps(i) + scan.xyz_radar.col(i).normalized().dot(v_radar);
        const bool seen_moving = std::isfinite(residual) && std::abs(residual) > min_speed;
        if (ego.valid()) {
            const bool is_static =
                ego.labels[static_cast<std::size_t>(i)] == odometry::PointLabel::kStatic;
            k.static_mask(j) = is_static;
            k.moving_mask(j) = !is_static && seen_moving;
        } else {
            k.static_mask(j) = filter_knows && std::isfinite(residual) && !seen_moving;
            k.moving_mask(j) = filter_knows && seen_moving;
        }
    }
    kept.push_back(std::move(k));
}

// Every kept scan's points in the base frame at stamp_ns: p = ExpSE3(xi (t_j - t)) T_base_radar p_j
// (the base moved with the filter's twist between the scan's stamp and the sweep's).
MultiRadarFrontEnd::State::MergedSweep MultiRadarFrontEnd::State::MergedCloud(
    int64_t stamp_ns) const {
    Eigen::Index n = 0;
    for (const KeptScan &k : kept) n += k.xyz_radar.cols();
    MergedSweep sweep;
    RadarScan &merged = sweep.scan;
    mapping::PointMask &static_mask = sweep.static_mask, &moving_mask = sweep.moving_mask;
    merged.Resize(n);
    merged.stamp_ns = stamp_ns;
    merged.frame_id = "base";
    merged.has_power = true;
    static_mask.resize(n);
    moving_mask.resize(n);
    Eigen::Index at = 0;
    for (const KeptScan &k : kept) {
        const Eigen::Isometry3d T_sweep_radar =
            ExpSE3(filter.MotionOver(NanosToSeconds(k.stamp_ns - stamp_ns))) *
            filter.T_base_radar(k.radar);
        const Eigen::Index m = k.xyz_radar.cols();
        merged.xyz_radar.middleCols(at, m) = T_sweep_radar * k.xyz_radar;
        merged.power_db.segment(at, m) = k.power_db;
        static_mask.segment(at, m) = k.static_mask;
        moving_mask.segment(at, m) = k.moving_mask;
        at += m;
    }
    // The radars' Doppler is each radar's own: the mapper's Doppler residuals (one sensor) skip it.
    merged.doppler_mps.setConstant(std::numeric_limits<double>::quiet_NaN());
    merged.DeriveSphericalFromXyz();
    return sweep;
}

BuiltPrior MultiRadarFrontEnd::State::BuildPrior(int64_t stamp_ns, double dt_s) const {
    PriorInputs in;
    in.kind = config.prior;
    in.poses = sweeps;
    in.T_world_base_prev = T_world_base_prev;
    in.T_world_base_prev2 = T_world_base_prev2;
    in.last_stamp_ns = last_sweep_ns;
    in.stamp_ns = stamp_ns;
    in.last_dt_s = last_dt_s;
    in.dt_s = dt_s;
    if (twist_measured_in_sweep) {
        in.twist = PriorTwistOf(filter.twist(), filter.covariance(), geometry.velocity_prior);
        in.last_twist = last_twist;
    } else {
        in.refused = PriorSubstitution::kInvalidDopplerVelocity;
        in.refused_detail = "no radar's ego-velocity updated the twist";
    }
    in.imu_samples = imu.samples();
    in.T_base_imu = T_base_imu;
    return BuildMotionPrior(in, config.prior_noise);
}

FrontEndResult MultiRadarFrontEnd::State::CloseSweep(int64_t stamp_ns) {
    const auto t_start = Clock::now();
    FrontEndResult result;
    result.stamp_ns = stamp_ns;
    result.accepted = true;
    result.dt_s = sweeps == 0 ? 0.0 : NanosToSeconds(stamp_ns - last_sweep_ns);
    const double dt_s = sweeps == 0 ? mapping::kFirstScanIntervalS : result.dt_s;
    const Twist now = PriorTwistOf(filter.twist(), filter.covariance(), geometry.velocity_prior);
    result.twist_base = now;
    if (sweeps > 0)
        T_world_base_odometry = T_world_base_odometry * ExpSE3(filter.MotionOver(result.dt_s));
    result.T_world_base_odometry = T_world_base_odometry;

    const auto t_prior = Clock::now();
    BuiltPrior built = BuildPrior(stamp_ns, dt_s);
    result.prior = built.prior;
    result.prior_requested = built.requested;
    result.prior_used = built.used;
    result.prior_first_scan = built.first_scan;
    result.prior_substitution = built.substitution;
    result.prior_substitution_detail = std::move(built.substitution_detail);
    result.times.prior_ms = MillisecondsSince(t_prior);
    mapping::MapperInput input;
    input.prior = result.prior;
    input.dt_s = dt_s;
    MergedSweep sweep = MergedCloud(stamp_ns);
    if (config.use_mask) {
        result.static_mask = sweep.static_mask;
        input.static_mask = std::move(sweep.static_mask);
        input.moving_mask = std::move(sweep.moving_mask);
    }
    result.registration = mapper.Register(sweep.scan, input);
    result.times.mapper = result.registration.times;
    result.T_world_base = result.registration.T_world_base;
    // The sweep's cost includes its radars' ego-velocities, estimated as each scan arrived.
    result.times.doppler_ms = sweep_doppler_ms;
    result.times.total_ms = MillisecondsSince(t_start) + sweep_doppler_ms;
    sweep_doppler_ms = 0.0;

    for (const mapping::WrittenPose &written : result.registration.written)
        trajectory.Append(written.stamp_ns, written.T_world_base);
    T_world_base_prev2 = T_world_base_prev;
    T_world_base_prev = result.T_world_base;
    last_dt_s = result.dt_s;
    if (twist_measured_in_sweep)
        last_twist = now;
    else
        last_twist.reset();
    twist_measured_in_sweep = false;
    ++sweeps;
    last_sweep_ns = stamp_ns;
    kept.clear();
    imu.DropUpTo(stamp_ns - 1);
    return result;
}

MultiRadarFrontEnd::MultiRadarFrontEnd(FrontEndConfig config,
                                       std::vector<Eigen::Isometry3d> T_base_radars,
                                       const Eigen::Isometry3d &T_base_imu,
                                       const VehicleGeometry &geometry,
                                       odometry::PlanarTwistFilterConfig twist_filter)
    : state_(std::make_unique<State>(std::move(config), std::move(T_base_radars), T_base_imu,
                                     geometry, twist_filter)) {}
MultiRadarFrontEnd::~MultiRadarFrontEnd() = default;
MultiRadarFrontEnd::MultiRadarFrontEnd(MultiRadarFrontEnd &&) noexcept = default;
MultiRadarFrontEnd &MultiRadarFrontEnd::operator=(MultiRadarFrontEnd &&) noexcept = default;

void MultiRadarFrontEnd::AddImu(const ImuSample &sample) {
    state_->imu.Add(sample);
}

RadarScanStep MultiRadarFrontEnd::Process(std::size_t radar, const RadarScan &scan_radar) {
    State &s = *state_;
    if (radar >= s.T_base_radars.size())
        throw std::out_of_range("multi-radar front end: radar index " + std::to_string(radar) +
                                " of " + std::to_string(s.T_base_radars.size()));
    RadarScanStep step;
    step.radar = radar;
    step.stamp_ns = scan_radar.stamp_ns;
    const bool reference = radar == 0;
    if (s.sweeps > 0 && (scan_radar.stamp_ns < s.last_sweep_ns ||
                         (reference && scan_radar.stamp_ns == s.last_sweep_ns))) {
        step.skip_reason = "stamp " + std::to_string(scan_radar.stamp_ns) +
                           " ns not after the last sweep's " + std::to_string(s.last_sweep_ns);
        return step;
    }
    step.accepted = true;
    const auto t_doppler = Clock::now();
    step.ego = s.estimator.Estimate(scan_radar);
    step.twist_update = s.filter.Update(scan_radar.stamp_ns, radar, step.ego);
    s.sweep_doppler_ms += MillisecondsSince(t_doppler);
    s.twist_measured_in_sweep |= step.twist_update == odometry::TwistUpdate::kTaken ||
                                 step.twist_update == odometry::TwistUpdate::kRestarted;
    step.twist = s.filter.twist();
    step.twist_covariance = s.filter.covariance();
    s.Keep(radar, scan_radar, step.ego);
    if (reference) {
        std::vector<bool> seen(s.T_base_radars.size(), false);
        for (const KeptScan &k : s.kept) seen[k.radar] = true;
        for (bool b : seen) step.sweep_radars += b ? 1 : 0;
        step.sweep = s.CloseSweep(scan_radar.stamp_ns);
    }
    return step;
}

std::vector<mapping::WrittenPose> MultiRadarFrontEnd::Finish() {
    std::vector<mapping::WrittenPose> written = state_->mapper.Finish();
    for (const mapping::WrittenPose &pose : written)
        state_->trajectory.Append(pose.stamp_ns, pose.T_world_base);
    return written;
}

const Trajectory &MultiRadarFrontEnd::trajectory() const {
    return state_->trajectory;
}
const odometry::PlanarTwistFilter &MultiRadarFrontEnd::twist_filter() const {
    return state_->filter;
}
std::size_t MultiRadarFrontEnd::radars() const {
    return state_->T_base_radars.size();
}

}  // namespace dorado::frontend
