// The steps of RadarMapper::Register around the registration: the priors on the two chains, the
// estimate (first scan, too few points, planar or 3-D), its fallback to the prior, the window
// smoother and the map update (mapper_state.hpp).
#include <chrono>
#include <string>
#include <utility>

#include "dorado/core/angles.hpp"
#include "dorado/core/time.hpp"
#include "mapper_state.hpp"
#include "planar_registration.hpp"
#include "pose_information.hpp"
#include "scan_points.hpp"

namespace dorado::mapping {

namespace {

using Clock = std::chrono::steady_clock;

WindowNoise WindowNoiseOf(const MapperConfig &config) {
    return {config.doppler_sigma_mps, config.kernel, config.kernel_scale};
}

// A planar registration as the mapper's estimate (the registered pose on the map's chain, the
// output fused from it).
ScanEstimate EstimateOf(const PlanarRegistration &reg) {
    ScanEstimate out;
    out.cause = reg.cause;
    out.detail = reg.detail;
    out.observability = reg.observability;
    out.prior_mahalanobis_squared = reg.prior_mahalanobis_squared;
    out.correspondences = reg.count;
    out.fitness_rms_m = reg.rms_m;
    out.alignment_ms = reg.alignment_ms;
    out.registration_ms = reg.registration_ms;
    out.refinement_ms = reg.refinement_ms;
    out.T_map_base = reg.T_map_base;
    out.T_world_base = reg.T_world_base;
    out.covariance = reg.covariance;
    out.registered = reg.registered;
    return out;
}

}  // namespace

RadarMapper::State::State(const MapperConfig &c, const Extrinsics &e, const VehicleGeometry &g)
    : config(c),
      extrinsics(e),
      map(c.map),
      movers(c.movers, c.map.voxel_size_m),
      noise(c.noise_calibration),
      threshold(c.initial_threshold_m, c.min_threshold_m, c.min_motion_m, c.max_range_m) {
    if (c.refinement == Refinement::kWindow) window.emplace(c.window, WindowNoiseOf(c), e, g);
}

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

MotionPrior RadarMapper::State::OnMapChain(const MotionPrior &prior) const {
    MotionPrior prior_map = prior;
    if (!has_pose) return prior_map;
    prior_map.T_world_base = T_map_base_last * T_world_base_last.inverse() * prior.T_world_base;
    // After fallbacks the previous pose is the prior's, not the map's: its uncertainty relative to
    // the map, carried along the motion, adds to this scan's (P = Ad(D^-1) U Ad(D^-1)^T + C).
    if (!unanchored_covariance.isZero()) {
        const Matrix6d Ad =
            AdjointSE3((T_world_base_last.inverse() * prior.T_world_base).inverse());
        prior_map.covariance += Ad * unanchored_covariance * Ad.transpose();
    }
    return prior_map;
}

// P^- = Ad(D^-1) P Ad(D^-1)^T + C_prior, D the prior's motion from the previous output pose.
MotionPrior RadarMapper::State::OutputPrior(const MotionPrior &prior) const {
    MotionPrior prior_output = prior;
    if (config.refinement == Refinement::kFilter && has_pose) {
        const Matrix6d Ad =
            AdjointSE3((T_world_base_last.inverse() * prior.T_world_base).inverse());
        prior_output.covariance = Ad * filter_covariance * Ad.transpose() + prior.covariance;
    }
    return prior_output;
}

ScanEstimate RadarMapper::State::Estimate(const Eigen::Matrix3Xd &source_base,
                                          const std::vector<DopplerObservation> &doppler,
                                          const MotionPrior &prior_map, const MotionPrior &prior,
                                          const MotionPrior &prior_output, const MapperInput &input,
                                          double threshold_m) {
    if (map.empty()) {  // the first scan starts the map at the prior, its origin
        ScanEstimate first;
        first.first_scan = true;
        first.T_map_base = prior_map.T_world_base;
        first.T_world_base = prior.T_world_base;
        return first;
    }
    const int source_points = static_cast<int>(source_base.cols());
    if (source_points < config.min_correspondences) {
        ScanEstimate too_few;
        too_few.cause = FallbackCause::kTooFewPoints;
        too_few.detail = std::to_string(source_points);
        return too_few;
    }
    if (planar) {  // a 2D radar: x, y and yaw (planar_registration.cpp)
        const ScanEstimate estimate =
            EstimateOf(RegisterPlanar(source_base, prior_map, prior, map, config, threshold_m));
        if (!estimate.fallback())
            threshold.Update(prior_map.T_world_base.inverse() * estimate.T_map_base);
        return estimate;
    }
    const GroundUp *ground = input.ground_base ? &*input.ground_base : nullptr;
    return RegisterToMap(source_base, doppler, prior_map, prior_output, input.dt_s, threshold_m,
                         ground);
}

ScanEstimate RadarMapper::State::FallBack(ScanEstimate estimate, const MotionPrior &prior,
                                          const MotionPrior &prior_map) {
    estimate.T_world_base = prior.T_world_base;
    estimate.covariance = ScaleBlocks(prior.covariance, noise.scales().prior);
    estimate.T_map_base = prior_map.T_world_base;
    ++fallbacks;
    return estimate;
}

// The window smoother's step: the scan's matches (none on a fallback), its static points' Doppler
// and the gyro rate join the window, initialised at the registered (or prior) pose and at the twist
// the prior implies. The motion prior itself is not a factor: the Doppler residuals, the kinematic
// model and the WNOA prior carry the information it was built from (the odometry's twist comes
// from the same Doppler points), so adding it would count them twice. Every scan enters the
// window; a fallback one without registration residuals.
ScanEstimate RadarMapper::State::SmoothWindow(ScanEstimate estimate,
                                              const std::vector<DopplerObservation> &doppler,
                                              const MotionPrior &prior, const MapperInput &input) {
    const auto t_window = Clock::now();
    WindowScan scan;
    scan.dt_s = input.dt_s;
    scan.T_world_base_initial = estimate.T_world_base;
    if (has_pose) {
        const Vector6d xi = LogSE3(T_world_base_last.inverse() * prior.T_world_base) / input.dt_s;
        scan.v_base_initial = xi.head<3>();
        scan.omega_base_initial = xi.tail<3>();
    }
    scan.matches = estimate.matches;
    if (config.use_doppler) scan.doppler = Thin(doppler, config.max_doppler_residuals);
    if (input.gyro_base_radps && input.gyro_base_radps->allFinite())
        scan.gyro_base_radps = *input.gyro_base_radps;
    estimate.T_world_base = window->Add(scan).T_world_base;
    estimate.refinement_ms += MillisecondsSince(t_window);
    // The window's marginal is not computed: the prior and the registration fused by their
    // information stand in for it (the window's older scans only tighten it).
    if (estimate.registered.valid)
        estimate.covariance =
            CovarianceFromInformation(CovarianceFromInformation(prior.covariance) +
                                      CovarianceFromInformation(estimate.registered.covariance));
    return estimate;
}

bool RadarMapper::State::IsKeyframe(const Eigen::Isometry3d &T_map_base) const {
    if (config.keyframe_distance_m <= 0.0 && config.keyframe_angle_deg <= 0.0) return true;
    const Eigen::Isometry3d delta = T_world_base_last_keyframe.inverse() * T_map_base;
    return delta.translation().norm() >= config.keyframe_distance_m ||
           RadToDeg(RotationAngle(delta.linear())) >= config.keyframe_angle_deg;
}

MapUpdate RadarMapper::State::UpdateMap(const Eigen::Matrix3Xd &p_base,
                                        const Eigen::Isometry3d &T_map_base, bool fallback) {
    const auto t_map = Clock::now();
    MapUpdate out;
    if ((!fallback || config.update_map_on_fallback) && (map.empty() || IsKeyframe(T_map_base))) {
        out.points_added_world = map.Update(T_map_base * p_base, T_map_base.translation());
        T_world_base_last_keyframe = T_map_base;
        map.BuildIndex();  // PCL's float copy of the map is part of the update's cost
        out.updated = true;
    }
    out.ms = MillisecondsSince(t_map);
    return out;
}

}  // namespace dorado::mapping
