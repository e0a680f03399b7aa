#include "dorado/mapping/radar_mapper.hpp"

#include <ceres/loss_function.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/mapping/adaptive_threshold.hpp"
#include "planar_registration.hpp"
#include "pose_information.hpp"
#include "registration.hpp"
#include "robust_loss.hpp"

namespace dorado::mapping {

namespace {

using Clock = std::chrono::steady_clock;

// The points of a scan the mapper uses: in the range gate, finite, static by the mask, and not
// near anything seen moving (movers.hpp).
struct ScanPoints {
    Eigen::Matrix3Xd p_base;  ///< all used points, base frame (for the map)
    std::vector<DopplerObservation> doppler;
    Eigen::Matrix3Xd moving_base;  ///< the points seen moving (clustered), base frame
    PointMask mover_dropped;       ///< per scan point: kept out by the mover rules
};

bool InRange(const Eigen::Vector3d &p_radar, const MapperConfig &config) {
    const double range = p_radar.norm();
    return std::isfinite(range) && range >= config.min_range_m && range <= config.max_range_m;
}

// T_world_base (the prior on the map's chain) places the points in the mover memory's cells;
// this scan's moving points are marked before the others are looked up.
ScanPoints SelectScanPoints(const RadarScan &scan, const MapperInput &input,
                            const Eigen::Isometry3d &T_world_base,
                            const Eigen::Isometry3d &T_base_radar, const MapperConfig &config,
                            MoverMemory &movers, double time_s,
                            std::vector<VoxelKey> &moving_cells) {
    ScanPoints out;
    out.mover_dropped = PointMask::Constant(scan.size(), false);
    const bool masked = input.static_mask.size() > 0;
    const bool moving = input.moving_mask.size() > 0;
    std::vector<Eigen::Index> candidates;
    candidates.reserve(static_cast<std::size_t>(scan.size()));
    out.moving_base.resize(3, moving ? input.moving_mask.count() : 0);
    Eigen::Index m = 0;
    for (Eigen::Index i = 0; i < scan.size(); ++i) {
        if (moving && input.moving_mask(i)) {
            if (scan.xyz_radar.col(i).allFinite())
                out.moving_base.col(m++) = T_base_radar * scan.xyz_radar.col(i);
            continue;
        }
        if (masked && !input.static_mask(i)) continue;
        if (InRange(scan.xyz_radar.col(i), config)) candidates.push_back(i);
    }
    out.moving_base.conservativeResize(3, m);
    // Evidence of a mover: the clustered ones (a ghost or a noisy return is alone).
    out.moving_base = Clustered(out.moving_base, config.movers.neighbour_radius_m,
                                config.movers.min_cluster_points);
    moving_cells = movers.Observe(T_world_base * out.moving_base, time_s);

    Eigen::Matrix3Xd candidates_base(3, static_cast<Eigen::Index>(candidates.size()));
    for (std::size_t k = 0; k < candidates.size(); ++k)
        candidates_base.col(static_cast<Eigen::Index>(k)) =
            T_base_radar * scan.xyz_radar.col(candidates[k]);  // radar frame in, base frame out
    const std::vector<bool> near =
        NearAny(candidates_base, out.moving_base, config.movers.neighbour_radius_m);
    out.p_base.resize(3, candidates_base.cols());
    Eigen::Index n = 0;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
        const Eigen::Vector3d p_base = candidates_base.col(static_cast<Eigen::Index>(k));
        const Eigen::Index i = candidates[k];
        if (near[k] || movers.Moving(T_world_base * p_base)) {
            out.mover_dropped(i) = true;
            continue;
        }
        out.p_base.col(n++) = p_base;
        const Eigen::Vector3d p_radar = scan.xyz_radar.col(i);
        if (std::isfinite(scan.doppler_mps(i)))
            out.doppler.push_back({p_radar / p_radar.norm(), scan.doppler_mps(i)});
    }
    out.p_base.conservativeResize(3, n);
    return out;
}

// Evenly thinned copy (the Doppler residuals: a few hundred constrain 3 velocity components well).
std::vector<DopplerObservation> Thin(const std::vector<DopplerObservation> &all, int max_count) {
    if (static_cast<int>(all.size()) <= max_count) return all;
    std::vector<DopplerObservation> out;
    out.reserve(static_cast<std::size_t>(max_count));
    for (int k = 0; k < max_count; ++k) out.push_back(all[k * all.size() / max_count]);
    return out;
}

// Evenly spaced columns, at most max_count: radar scans are too sparse for a voxel grid alone to
// bound the registration cost.
Eigen::Matrix3Xd ThinColumns(const Eigen::Matrix3Xd &points, int max_count) {
    if (points.cols() <= max_count) return points;
    Eigen::Matrix3Xd out(3, max_count);
    for (int k = 0; k < max_count; ++k) out.col(k) = points.col(k * points.cols() / max_count);
    return out;
}

WindowNoise WindowNoiseOf(const MapperConfig &config) {
    return {config.doppler_sigma_mps, config.kernel, config.kernel_scale};
}

// What Refine computed: the registered pose on the map's chain, the output pose and its
// covariance, the registration's estimate (valid only when the refinement succeeded) and the last
// association.
struct Refined {
    Eigen::Isometry3d T_map = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    Matrix6d covariance = Matrix6d::Zero();
    std::optional<Matrix6d> filter_covariance;  ///< refinement filter: the posterior P
    RegisteredPose registered;
    Association association;
    int doppler_residuals = 0;
    bool ground_used = false;
};

// What RegisterToMap computed: the checks (cause kNone: trusted) and their numbers, then the
// refinement of a trusted registration.
struct MapRegistration {
    FallbackCause cause = FallbackCause::kNone;
    std::string detail;
    Association association;  ///< at PCL's pose (the window smoother's matches)
    double prior_mahalanobis_squared = 0.0;
    Refined refined;  ///< when trusted
    double alignment_ms = 0.0, registration_ms = 0.0, refinement_ms = 0.0;
};

}  // namespace

struct RadarMapper::State {
    MapperConfig config;
    Extrinsics extrinsics;
    LocalMap map;
    MoverMemory movers;
    NoiseCalibration noise;
    double time_s = 0.0;  ///< the sum of the scans' dt_s (the mover memory's clock)
    AdaptiveThreshold threshold;
    bool has_pose = false;
    /// Two chains of poses (refinement ceres, and filter without filter_builds_map): the output
    /// (the prior's chain, pulled toward the map by the registration's honest weight) and the
    /// map's (the registered poses, locked to the map by the registration's residuals, which the
    /// map is built from). One chain otherwise.
    Eigen::Isometry3d T_world_base_last = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_map_base_last = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_world_base_last_keyframe = Eigen::Isometry3d::Identity();
    int fallbacks = 0;
    std::optional<WindowSmoother> window;  ///< refinement = kWindow
    bool planar = false;                   ///< a 2D radar: registration in the plane
    /// refinement = kFilter: the covariance of T_world_base_last relative to the map (zero at the
    /// first scan, the map's origin).
    Matrix6d filter_covariance = Matrix6d::Zero();

    State(const MapperConfig &c, const Extrinsics &e, const VehicleGeometry &g)
        : config(c),
          extrinsics(e),
          map(c.map),
          movers(c.movers, c.map.voxel_size_m),
          noise(c.noise_calibration),
          threshold(c.initial_threshold_m, c.min_threshold_m, c.min_motion_m, c.max_range_m) {
        if (c.refinement == Refinement::kWindow) window.emplace(c.window, WindowNoiseOf(c), e, g);
    }

    bool IsKeyframe(const Eigen::Isometry3d &T) const {
        if (config.keyframe_distance_m <= 0.0 && config.keyframe_angle_deg <= 0.0) return true;
        const Eigen::Isometry3d delta = T_world_base_last_keyframe.inverse() * T;
        return delta.translation().norm() >= config.keyframe_distance_m ||
               RotationAngle(delta.linear()) * 180.0 / M_PI >= config.keyframe_angle_deg;
    }

    [[nodiscard]] MapRegistration RegisterToMap(const Eigen::Matrix3Xd &source_base,
                                                const std::vector<DopplerObservation> &doppler,
                                                const MotionPrior &prior_map,
                                                const MotionPrior &prior, double dt_s,
                                                double threshold_m, const GroundUp *ground);
    [[nodiscard]] Refined Refine(const Eigen::Matrix3Xd &source_base,
                                 const std::vector<DopplerObservation> &doppler_all,
                                 const MotionPrior &prior_map, const MotionPrior &prior,
                                 double dt_s, double threshold_m, const Association &association,
                                 const Eigen::Isometry3d &T_aligned, const GroundUp *ground) const;
    [[nodiscard]] Eigen::Isometry3d SmoothWindow(const std::vector<DopplerObservation> &doppler,
                                                 const std::vector<Correspondence> &matches,
                                                 const MotionPrior &prior, double dt_s,
                                                 const Eigen::Vector3d *gyro_base_radps,
                                                 const Eigen::Isometry3d &T_world_base_initial);
};

RadarMapper::RadarMapper(const MapperConfig &config, const Extrinsics &extrinsics,
                         const VehicleGeometry &geometry) {
    config.Validate();
    state_ = std::make_unique<State>(config, extrinsics, geometry);
}
RadarMapper::~RadarMapper() = default;
RadarMapper::RadarMapper(RadarMapper &&) noexcept = default;
RadarMapper &RadarMapper::operator=(RadarMapper &&) noexcept = default;

const LocalMap &RadarMapper::local_map() const {
    return state_->map;
}
const MapperConfig &RadarMapper::config() const {
    return state_->config;
}
int RadarMapper::fallbacks() const {
    return state_->fallbacks;
}
void RadarMapper::SetPlanar() {
    if (state_->window || state_->config.refinement == Refinement::kFilter)
        throw std::invalid_argument(
            std::string("refinement ") + ToString(state_->config.refinement) +
            ": not for a 2D radar (planar mode registers x, y and yaw); use refinement ceres or "
            "none");
    state_->planar = true;
}
bool RadarMapper::planar() const {
    return state_->planar;
}

const char *ToString(FallbackCause cause) {
    switch (cause) {
        case FallbackCause::kNone:
            return "";
        case FallbackCause::kTooFewPoints:
            return "too few points";
        case FallbackCause::kNotConverged:
            return "registration did not converge";
        case FallbackCause::kTooFewCorrespondences:
            return "too few correspondences";
        case FallbackCause::kBadFitness:
            return "bad fitness";
        case FallbackCause::kDegenerate:
            return "degenerate geometry";
        case FallbackCause::kJump:
            return "jump outside the prior";
    }
    return "?";
}

namespace {

// A 2D radar's map lives in the plane: the prior's motion since the previous pose projected onto
// it (x, y and the rotation about the base's z axis), z, roll and pitch held. A 3-D gyro's roll and
// pitch rates (a car's body roll, sensor noise) would otherwise be integrated into every pose.
MotionPrior OnThePlane(const MotionPrior &prior, const Eigen::Isometry3d &T_world_base_last) {
    const Eigen::Isometry3d D_last_prior = T_world_base_last.inverse() * prior.T_world_base;
    Eigen::Isometry3d D_planar = Eigen::Isometry3d::Identity();
    D_planar.linear() =
        Eigen::AngleAxisd(RollPitchYaw(D_last_prior.linear()).z(), Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
    D_planar.translation() << D_last_prior.translation().x(), D_last_prior.translation().y(), 0.0;
    MotionPrior planar = prior;
    planar.T_world_base = T_world_base_last * D_planar;
    return planar;
}

// The jump test's prior: the prior's uncertainty plus the registration's own noise.
MotionPrior WidenedPrior(const MotionPrior &prior, const MapperConfig &config) {
    MotionPrior widened = prior;
    widened.covariance.diagonal() +=
        (Vector6d() << Eigen::Vector3d::Constant(config.registration_sigma_translation_m),
         Eigen::Vector3d::Constant(config.registration_sigma_rotation_rad))
            .finished()
            .cwiseAbs2();
    return widened;
}

// Why a registration is not trusted (kNone when it is), with the numbers: convergence, support,
// fitness, observability and the jump test, in that order.
std::pair<FallbackCause, std::string> CheckRegistration(const PclAlignment &aligned,
                                                        const Association &association,
                                                        double prior_mahalanobis_squared,
                                                        const MapperConfig &config) {
    if (!aligned.converged) return {FallbackCause::kNotConverged, ""};
    if (association.count < config.min_correspondences)
        return {FallbackCause::kTooFewCorrespondences, std::to_string(association.count)};
    if (association.rms_m > config.max_rms_m)
        return {FallbackCause::kBadFitness, "rms " + std::to_string(association.rms_m) + " m"};
    if (association.observability < config.min_observability)
        return {FallbackCause::kDegenerate,
                "observability " + std::to_string(association.observability)};
    if (prior_mahalanobis_squared > config.max_prior_mahalanobis_squared)
        return {FallbackCause::kJump, "Mahalanobis^2 " + std::to_string(prior_mahalanobis_squared)};
    return {FallbackCause::kNone, ""};
}

}  // namespace

// Doppler-aware refinement (Ceres), re-associating refine_outer_iterations times from the
// registered pose: with ceres, the registered pose and the output fused from it (RefinePose); with
// none and window, the registration alone gives the covariance (the output stays PCL's pose). The
// Doppler residuals join only when the prior was not built from the same Doppler velocity (counted
// once). A refinement that fails leaves the pose where it was and `registered` not valid.
Refined RadarMapper::State::Refine(const Eigen::Matrix3Xd &source_base,
                                   const std::vector<DopplerObservation> &doppler_all,
                                   const MotionPrior &prior_map, const MotionPrior &prior,
                                   double dt_s, double threshold_m, const Association &association,
                                   const Eigen::Isometry3d &T_aligned,
                                   const GroundUp *ground) const {
    const bool filter = config.refinement == Refinement::kFilter;
    const bool ceres = RefinesWithCeres(config.refinement);
    Refined out;
    out.T_map = T_aligned;
    out.T_world_base = ceres ? prior.T_world_base : T_aligned;
    // Until a refinement fuses: the motion prior's covariance (with `filter`, `prior` carries the
    // filter's P^-, relative to the map, not the scan's motion).
    out.covariance = prior_map.covariance;
    out.association = association;
    const std::vector<DopplerObservation> doppler =
        (config.use_doppler && has_pose && !NeedsDoppler(prior.kind))
            ? Thin(doppler_all, config.max_doppler_residuals)
            : std::vector<DopplerObservation>{};
    const std::vector<DopplerObservation> doppler_registration =
        (config.use_doppler && has_pose && config.doppler_in_registration)
            ? Thin(doppler_all, config.max_doppler_residuals)
            : doppler;
    out.doppler_residuals = static_cast<int>(doppler_registration.size());
    for (int outer = 0; outer < config.refine_outer_iterations; ++outer) {
        if (outer > 0)
            out.association = Associate(source_base, out.T_map, map, config, threshold_m,
                                        config.max_registration_residuals);
        if (out.association.count < config.min_correspondences) break;
        RefinementInput input;
        input.T_world_base_initial = out.T_map;
        input.prior = &prior_map;
        input.matches = &out.association.matches;
        input.doppler = &doppler;
        input.doppler_registration = &doppler_registration;
        input.T_world_base_prev = T_map_base_last;
        input.T_base_radar = extrinsics.T_base_radar;
        input.dt_s = dt_s;
        input.prior_output = &prior;
        input.T_world_base_prev_output = T_world_base_last;
        input.ground = ceres ? ground : nullptr;
        input.registration_scale = noise.scales().registration;
        const RefinementOutput refined =
            ceres ? RefinePose(input, config) : RegisterAlone(input, config);
        if (!refined.usable) break;
        out.registered = refined.registered;
        out.ground_used = refined.ground_used;
        if (ceres) {
            out.T_map = refined.registered.T_world_base;
            out.T_world_base = refined.T_world_base;
            out.covariance = refined.covariance;
            if (filter) {  // prior carries the filter's prediction P^-, prior_map the one step's
                out.filter_covariance = refined.covariance;
                out.covariance = FilterMotionCovariance(prior.covariance, prior_map.covariance,
                                                        refined.covariance);
            }
        } else {  // none: PCL's pose; the window smoother's covariance is set after it
            out.covariance = refined.registered.covariance;
        }
    }
    return out;
}

// The window smoother's step: the scan's matches (none on a fallback), its static points' Doppler
// and the gyro rate join the window, initialised at the registered (or prior) pose and at the twist
// the prior implies. The motion prior itself is not a factor: the Doppler residuals, the kinematic
// model and the WNOA prior carry the information it was built from (the odometry's twist comes
// from the same Doppler points), so adding it would count them twice. Returns the newest pose.
Eigen::Isometry3d RadarMapper::State::SmoothWindow(const std::vector<DopplerObservation> &doppler,
                                                   const std::vector<Correspondence> &matches,
                                                   const MotionPrior &prior, double dt_s,
                                                   const Eigen::Vector3d *gyro_base_radps,
                                                   const Eigen::Isometry3d &T_world_base_initial) {
    WindowScan scan;
    scan.dt_s = dt_s;
    scan.T_world_base_initial = T_world_base_initial;
    if (has_pose) {
        const Vector6d xi = LogSE3(T_world_base_last.inverse() * prior.T_world_base) / dt_s;
        scan.v_base_initial = xi.head<3>();
        scan.omega_base_initial = xi.tail<3>();
    }
    scan.matches = matches;
    if (config.use_doppler) scan.doppler = Thin(doppler, config.max_doppler_residuals);
    if (gyro_base_radps != nullptr && gyro_base_radps->allFinite())
        scan.gyro_base_radps = *gyro_base_radps;
    return window->Add(scan).T_world_base;
}

// Scan-to-map registration from the prior (PCL), its checks, then the refinement of a trusted one.
MapRegistration RadarMapper::State::RegisterToMap(const Eigen::Matrix3Xd &source_base,
                                                  const std::vector<DopplerObservation> &doppler,
                                                  const MotionPrior &prior_map,
                                                  const MotionPrior &prior, double dt_s,
                                                  double threshold_m, const GroundUp *ground) {
    MapRegistration out;
    const auto t_reg = Clock::now();
    const PclAlignment aligned =
        AlignWithPcl(source_base, prior_map.T_world_base, map, config, threshold_m);
    out.alignment_ms = MillisecondsSince(t_reg);
    out.association = Associate(source_base, aligned.T_world_base, map, config, threshold_m,
                                config.max_registration_residuals);
    out.prior_mahalanobis_squared =
        PriorMahalanobisSquared(WidenedPrior(prior_map, config), aligned.T_world_base);
    out.registration_ms = MillisecondsSince(t_reg);
    std::tie(out.cause, out.detail) =
        CheckRegistration(aligned, out.association, out.prior_mahalanobis_squared, config);
    if (out.cause != FallbackCause::kNone) return out;

    // Covariance matching: PCL's pose (the registration alone, started at the prior) against the
    // prior, each with its model's covariance; then both weighed by the scales learnt so far.
    if (noise.enabled()) {
        const auto loss = MakeLoss(config.kernel, config.kernel_scale);
        const RegisteredPose alone = RegistrationCovariance(
            aligned.T_world_base, out.association.matches, loss.get(), config);
        if (alone.valid && alone.weak_directions == 0)
            noise.Add(LogSE3(prior_map.T_world_base.inverse() * aligned.T_world_base),
                      prior_map.covariance, alone.covariance);
    }
    const NoiseScales &scales = noise.scales();
    MotionPrior prior_map_scaled = prior_map, prior_scaled = prior;
    prior_map_scaled.covariance = ScaleBlocks(prior_map.covariance, scales.prior);
    prior_scaled.covariance = ScaleBlocks(prior.covariance, scales.prior);

    const auto t_refine = Clock::now();
    out.refined = Refine(source_base, doppler, prior_map_scaled, prior_scaled, dt_s, threshold_m,
                         out.association, aligned.T_world_base, ground);
    out.refinement_ms = MillisecondsSince(t_refine);
    // kiss-icp: the threshold adapts to how far registration corrected the prior.
    threshold.Update(prior_map.T_world_base.inverse() * out.refined.T_map);
    return out;
}

RegistrationResult RadarMapper::Register(const RadarScan &scan_radar, const MotionPrior &prior,
                                         double dt_s, const PointMask *static_mask,
                                         const Eigen::Vector3d *gyro_base_radps,
                                         const GroundUp *ground_base) {
    MapperInput input;
    input.prior = prior;
    input.dt_s = dt_s;
    if (static_mask != nullptr) input.static_mask = *static_mask;
    if (gyro_base_radps != nullptr) input.gyro_base_radps = *gyro_base_radps;
    if (ground_base != nullptr) input.ground_base = *ground_base;
    return Register(scan_radar, input);
}

RegistrationResult RadarMapper::Register(const RadarScan &scan_radar, const MapperInput &input) {
    State &s = *state_;
    const MapperConfig &config = s.config;
    const double dt_s = input.dt_s;
    const GroundUp *ground_base = input.ground_base ? &*input.ground_base : nullptr;
    const Eigen::Vector3d *gyro_base_radps =
        input.gyro_base_radps ? &*input.gyro_base_radps : nullptr;
    for (const auto &[name, mask] :
         {std::pair{"mask", &input.static_mask}, std::pair{"moving mask", &input.moving_mask}})
        if (mask->size() != 0 && mask->size() != scan_radar.size())
            throw std::invalid_argument(std::string("RadarMapper::Register: ") + name + " has " +
                                        std::to_string(mask->size()) + " entries, scan has " +
                                        std::to_string(scan_radar.size()) + " points");
    if (s.has_pose && !(std::isfinite(dt_s) && dt_s > 0.0))
        throw std::invalid_argument("RadarMapper::Register: dt must be finite and > 0");
    if (!input.prior.T_world_base.matrix().allFinite() || !input.prior.covariance.allFinite())
        throw std::invalid_argument("RadarMapper::Register: the prior is not finite");
    const MotionPrior prior =
        s.planar && s.has_pose ? OnThePlane(input.prior, s.T_world_base_last) : input.prior;

    const auto t_start = Clock::now();
    RegistrationResult result;
    result.T_world_base = prior.T_world_base;
    result.covariance = prior.covariance;  // until a refinement fuses the registration into it
    result.threshold_m = s.threshold.Threshold();
    if (s.has_pose) s.time_s += dt_s;

    // 1. Points: range gate, dynamic mask and movers, base frame, voxel downsampling. The map
    //    drops what it held where something moves now.
    // The prior moved onto the map's chain: the same motion from the map's previous pose.
    MotionPrior prior_map = prior;
    if (s.has_pose)
        prior_map.T_world_base =
            s.T_map_base_last * s.T_world_base_last.inverse() * prior.T_world_base;
    std::vector<VoxelKey> moving_cells;
    const ScanPoints points =
        SelectScanPoints(scan_radar, input, prior_map.T_world_base, s.extrinsics.T_base_radar,
                         config, s.movers, s.time_s, moving_cells);
    result.mover_dropped = points.mover_dropped;
    result.map_points_dropped = static_cast<int>(s.map.Remove(moving_cells));
    if (result.map_points_dropped > 0) result.map_cells_dropped = std::move(moving_cells);
    const Eigen::Matrix3Xd source_base =
        ThinColumns(VoxelDownsample(points.p_base, config.scan_voxel_m), config.max_source_points);
    result.source_points = static_cast<int>(source_base.cols());
    result.times.preprocess_ms = MillisecondsSince(t_start);

    // 2-3. Registration and refinement, or the prior.
    const bool filter = config.refinement == Refinement::kFilter;
    // The output chain's prior (refinement filter: with the filter's prediction of its covariance
    // relative to the map chain, P^- = Ad(D^-1) P Ad(D^-1)^T + C_prior).
    MotionPrior prior_output = prior;
    if (filter && s.has_pose) {
        const Matrix6d Ad =
            AdjointSE3((s.T_world_base_last.inverse() * prior.T_world_base).inverse());
        prior_output.covariance = Ad * s.filter_covariance * Ad.transpose() + prior.covariance;
    }
    Matrix6d filter_covariance = prior_output.covariance;  // kept on a fallback or a failed update
    Eigen::Isometry3d T_map = prior_map.T_world_base;
    std::vector<Correspondence> window_matches;
    if (s.map.empty()) {
        result.first_scan = true;  // the first scan starts the map at the prior, its origin
        result.covariance.setZero();
    } else if (result.source_points < config.min_correspondences) {
        result.fallback_cause = FallbackCause::kTooFewPoints;
        result.fallback_detail = std::to_string(result.source_points);
    } else if (s.planar) {  // a 2D radar: x, y and yaw (planar_registration.cpp)
        const PlanarRegistration reg =
            RegisterPlanar(source_base, prior_map, prior, s.map, config, result.threshold_m);
        result.fallback_cause = reg.cause;
        result.fallback_detail = reg.detail;
        result.observability = reg.observability;
        result.prior_mahalanobis_squared = reg.prior_mahalanobis_squared;
        result.correspondences = reg.count;
        result.fitness_rms_m = reg.rms_m;
        result.times.alignment_ms = reg.alignment_ms;
        result.times.registration_ms = reg.registration_ms;
        result.times.refinement_ms = reg.refinement_ms;
        if (!result.fallback()) {
            T_map = reg.T_map;
            result.T_world_base = reg.T_world_base;
            result.covariance = reg.covariance;
            result.registered = reg.registered;
            s.threshold.Update(prior_map.T_world_base.inverse() * reg.T_map);
        }
    } else {
        const MapRegistration reg =
            s.RegisterToMap(source_base, points.doppler, prior_map, prior_output, dt_s,
                            result.threshold_m, ground_base);
        result.fallback_cause = reg.cause;
        result.fallback_detail = reg.detail;
        result.observability = reg.association.observability;
        result.prior_mahalanobis_squared = reg.prior_mahalanobis_squared;
        result.correspondences = reg.association.count;
        result.fitness_rms_m = reg.association.rms_m;
        result.times.alignment_ms = reg.alignment_ms;
        result.times.registration_ms = reg.registration_ms;
        result.times.refinement_ms = reg.refinement_ms;
        if (!result.fallback()) {
            const Refined &refined = reg.refined;
            T_map = refined.T_map;
            result.T_world_base = refined.T_world_base;
            result.covariance = refined.covariance;
            result.registered = refined.registered;
            if (refined.filter_covariance) filter_covariance = *refined.filter_covariance;
            result.correspondences = refined.association.count;
            result.fitness_rms_m = refined.association.rms_m;
            result.doppler_residuals = refined.doppler_residuals;
            result.ground_used = refined.ground_used;
            if (s.window) window_matches = reg.association.matches;
        }
    }
    if (result.fallback()) {
        result.T_world_base = prior.T_world_base;
        result.covariance = ScaleBlocks(prior.covariance, s.noise.scales().prior);
        T_map = prior_map.T_world_base;
        ++s.fallbacks;
    }
    result.noise_scales = s.noise.scales();
    if (s.window) {  // every scan enters the window; a fallback one without registration residuals
        const auto t_window = Clock::now();
        result.T_world_base = s.SmoothWindow(points.doppler, window_matches, prior, dt_s,
                                             gyro_base_radps, result.T_world_base);
        result.times.refinement_ms += MillisecondsSince(t_window);
        // The window's marginal is not computed: the prior and the registration fused by their
        // information stand in for it (the window's older scans only tighten it).
        if (result.registered.valid)
            result.covariance =
                CovarianceFromInformation(CovarianceFromInformation(prior.covariance) +
                                          CovarianceFromInformation(result.registered.covariance));
    }
    if (!RefinesWithCeres(config.refinement) || (filter && config.filter_builds_map))
        T_map = result.T_world_base;  // one chain
    if (filter) {
        s.filter_covariance = result.first_scan ? Matrix6d::Zero() : filter_covariance;
        result.filter_covariance = s.filter_covariance;
    }

    // 4. Map update (keyframes only, when configured).
    const auto t_map = Clock::now();
    if ((!result.fallback() || config.update_map_on_fallback) &&
        (s.map.empty() || s.IsKeyframe(T_map))) {
        result.map_points_added_world = s.map.Update(T_map * points.p_base, T_map.translation());
        s.T_world_base_last_keyframe = T_map;
        s.map.BuildIndex();  // PCL's float copy of the map is part of the update's cost
        result.map_updated = true;
    }
    result.times.map_update_ms = MillisecondsSince(t_map);
    result.local_map_points = s.map.size();

    s.T_world_base_last = result.T_world_base;
    s.T_map_base_last = T_map;
    s.has_pose = true;
    result.times.total_ms = MillisecondsSince(t_start);
    return result;
}

}  // namespace dorado::mapping
