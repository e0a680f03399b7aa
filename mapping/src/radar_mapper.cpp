#include "dorado/mapping/radar_mapper.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "dorado/core/time.hpp"
#include "mapper_state.hpp"
#include "registration.hpp"
#include "scan_points.hpp"

namespace dorado::mapping {

namespace {

using Clock = std::chrono::steady_clock;

// Throws std::invalid_argument on a mask of the wrong size, a non-finite dt or prior.
void CheckInput(const RadarScan &scan_radar, const MapperInput &input, bool has_pose) {
    for (const auto &[name, mask] :
         {std::pair{"mask", &input.static_mask}, std::pair{"moving mask", &input.moving_mask}})
        if (mask->size() != 0 && mask->size() != scan_radar.size())
            throw std::invalid_argument(std::string("RadarMapper::Register: ") + name + " has " +
                                        std::to_string(mask->size()) + " entries, scan has " +
                                        std::to_string(scan_radar.size()) + " points");
    if (has_pose && !(std::isfinite(input.dt_s) && input.dt_s > 0.0))
        throw std::invalid_argument("RadarMapper::Register: dt must be finite and > 0");
    if (!input.prior.T_world_base.matrix().allFinite() || !input.prior.covariance.allFinite())
        throw std::invalid_argument("RadarMapper::Register: the prior is not finite");
}

// The scan's result from its estimate (the registration's numbers and the output pose).
RegistrationResult ResultOf(ScanEstimate estimate) {
    RegistrationResult result;
    result.T_world_base = estimate.T_world_base;
    result.covariance = estimate.covariance;
    result.registered = std::move(estimate.registered);
    result.first_scan = estimate.first_scan;
    result.fallback_cause = estimate.cause;
    result.fallback_detail = std::move(estimate.detail);
    result.correspondences = estimate.correspondences;
    result.fitness_rms_m = estimate.fitness_rms_m;
    result.observability = estimate.observability;
    result.prior_mahalanobis_squared = estimate.prior_mahalanobis_squared;
    result.doppler_residuals = estimate.doppler_residuals;
    result.ground_used = estimate.ground_used;
    result.times.alignment_ms = estimate.alignment_ms;
    result.times.registration_ms = estimate.registration_ms;
    result.times.refinement_ms = estimate.refinement_ms;
    return result;
}

}  // namespace

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

RegistrationResult RadarMapper::Register(const RadarScan &scan_radar, const MapperInput &input) {
    State &s = *state_;
    const MapperConfig &config = s.config;
    CheckInput(scan_radar, input, s.has_pose);
    // The prior on the output's chain (a 2D radar's in the plane), the same motion on the map's.
    const MotionPrior prior =
        s.planar && s.has_pose ? OnThePlane(input.prior, s.T_world_base_last) : input.prior;
    const MotionPrior prior_map = s.OnMapChain(prior);
    const auto t_start = Clock::now();
    const double threshold_m = s.threshold.Threshold();
    if (s.has_pose) s.time_s += input.dt_s;

    // 1. Points: range gate, dynamic mask and movers, base frame, voxel downsampling. The map
    //    drops what it held where something moves now.
    ScanPoints points = SelectScanPoints(scan_radar, input, prior_map.T_world_base,
                                         s.extrinsics.T_base_radar, config, s.movers, s.time_s);
    const int map_points_dropped = static_cast<int>(s.map.Remove(points.moving_cells));
    const Eigen::Matrix3Xd source_base =
        ThinColumns(VoxelDownsample(points.p_base, config.scan_voxel_m), config.max_source_points);
    const double preprocess_ms = MillisecondsSince(t_start);

    // 2-3. Registration and refinement, or the prior; the window smoother; one chain or two.
    const MotionPrior prior_output = s.OutputPrior(prior);
    ScanEstimate estimate =
        s.Estimate(source_base, points.doppler, prior_map, prior, prior_output, input, threshold_m);
    if (estimate.fallback()) estimate = s.FallBack(std::move(estimate), prior, prior_map);
    if (estimate.fallback())
        s.unanchored_covariance = prior_map.covariance;
    else
        s.unanchored_covariance.setZero();
    const NoiseScales noise_scales = s.noise.scales();
    if (s.window) estimate = s.SmoothWindow(std::move(estimate), points.doppler, prior, input);
    const bool filter = config.refinement == Refinement::kFilter;
    if (!RefinesWithCeres(config.refinement) || (filter && config.filter_builds_map))
        estimate.T_map_base = estimate.T_world_base;
    if (filter)  // P^- kept on a fallback or a failed update; zero at the map's origin
        s.filter_covariance = estimate.filter_covariance.value_or(prior_output.covariance);
    if (filter && estimate.first_scan) s.filter_covariance.setZero();

    // 4. Map update (keyframes only, when configured).
    MapUpdate update = s.UpdateMap(points.p_base, estimate.T_map_base, estimate.fallback());
    s.T_world_base_last = estimate.T_world_base;
    s.T_map_base_last = estimate.T_map_base;
    s.has_pose = true;

    RegistrationResult result = ResultOf(std::move(estimate));
    result.threshold_m = threshold_m;
    result.source_points = static_cast<int>(source_base.cols());
    result.mover_dropped = std::move(points.mover_dropped);
    result.map_points_dropped = map_points_dropped;
    if (map_points_dropped > 0) result.map_cells_dropped = std::move(points.moving_cells);
    result.noise_scales = noise_scales;
    if (filter) result.filter_covariance = s.filter_covariance;
    result.map_updated = update.updated;
    result.map_points_added_world = std::move(update.points_added_world);
    result.local_map_points = s.map.size();
    result.times.preprocess_ms = preprocess_ms;
    result.times.map_update_ms = update.ms;
    result.times.total_ms = MillisecondsSince(t_start);
    return result;
}

}  // namespace dorado::mapping
