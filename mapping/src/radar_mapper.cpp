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

}  // namespace

RadarMapper::RadarMapper(const MapperConfig &config, const Extrinsics &extrinsics) {
    config.Validate();
    state_ = std::make_unique<State>(config, extrinsics);
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
        case FallbackCause::kUnrefined:
            return "refinement failed";
    }
    return "?";
}

RegistrationResult RadarMapper::Register(const RadarScan &scan_radar, const MapperInput &input) {
    State &s = *state_;
    if (s.finished) throw std::logic_error("RadarMapper::Register: called after Finish");
    const MapperConfig &config = s.config;
    CheckInput(scan_radar, input, s.has_pose);
    // The prior (a 2D radar's in the plane) and the prediction it makes from the newest pose.
    const MotionPrior prior =
        s.planar && s.has_pose ? OnThePlane(input.prior, s.T_world_base_last) : input.prior;
    const MotionPrior prediction = s.Predict(prior);
    const auto t_start = Clock::now();
    const double threshold_m = s.threshold.Threshold();
    if (s.has_pose) s.time_s += input.dt_s;

    // 1. Points: range gate, dynamic mask and movers, base frame, voxel downsampling. The map
    //    drops what it held where something moves now.
    ScanPoints points = SelectScanPoints(scan_radar, input, prediction.T_world_base,
                                         s.extrinsics.T_base_radar, config, s.movers, s.time_s);
    RegistrationResult result;
    result.map_points_dropped = static_cast<int>(s.map.Remove(points.moving_cells));
    if (result.map_points_dropped > 0) {
        s.DropFromPending(points.moving_cells);
        result.map_cells_dropped = std::move(points.moving_cells);
    }
    const Eigen::Matrix3Xd source_base =
        ThinColumns(VoxelDownsample(points.p_base, config.scan_voxel_m), config.max_source_points);
    result.times.preprocess_ms = MillisecondsSince(t_start);

    // 2-3. Registration to the map and its refinement (or nothing to register).
    const GroundUp *ground = input.ground_base && !s.planar ? &*input.ground_base : nullptr;
    const ScanEstimate estimate =
        s.Estimate(source_base, points.doppler, prediction, input, threshold_m);
    result.first_scan = estimate.first_scan;
    result.fallback_cause = estimate.cause;
    result.fallback_detail = estimate.detail;
    result.source_points = static_cast<int>(source_base.cols());
    result.correspondences = estimate.correspondences;
    result.fitness_rms_m = estimate.fitness_rms_m;
    result.observability = estimate.observability;
    result.threshold_m = threshold_m;
    result.doppler_residuals = estimate.doppler_residuals;
    result.registered = estimate.registered;
    result.T_world_base_aligned = estimate.T_world_base_aligned;
    result.mover_dropped = std::move(points.mover_dropped);
    result.times.alignment_ms = estimate.alignment_ms;
    result.times.registration_ms = estimate.registration_ms;
    if (estimate.fallback()) ++s.fallbacks;

    // 4. The smoother: the newest pose, and the poses that leave it written with their points
    //    in the map.
    PendingScan pending;
    pending.written.stamp_ns = scan_radar.stamp_ns;
    pending.p_base = std::move(points.p_base);
    const auto t_smooth = Clock::now();
    result.written = s.Smooth(std::move(pending), prior, prediction, estimate, ground, result);
    result.times.refinement_ms = estimate.refinement_ms + MillisecondsSince(t_smooth) -
                                 result.times.map_update_ms;
    result.local_map_points = s.map.size();
    result.times.total_ms = MillisecondsSince(t_start);
    return result;
}

std::vector<WrittenPose> RadarMapper::Finish() {
    State &s = *state_;
    s.finished = true;
    double map_update_ms = 0.0;
    return s.Write(s.smoother.Flush(), map_update_ms);
}

}  // namespace dorado::mapping
