// Steps 2-3 of RadarMapper::Register in 3-D: scan-to-map registration from the prediction (PCL),
// the checks that decide whether there is anything to register, and the Doppler-aware refinement
// of the registered pose (Ceres).
#include <chrono>
#include <string>
#include <tuple>
#include <utility>

#include "dorado/core/time.hpp"
#include "mapper_state.hpp"
#include "scan_points.hpp"

namespace dorado::mapping {

namespace {

using Clock = std::chrono::steady_clock;

// Why there is nothing to register (kNone when there is), with the numbers: convergence,
// support, fitness and observability, in that order.
std::pair<FallbackCause, std::string> CheckRegistration(const PclAlignment &aligned,
                                                        const Association &association,
                                                        const MapperConfig &config) {
    if (!aligned.converged) return {FallbackCause::kNotConverged, ""};
    if (association.count < config.min_correspondences)
        return {FallbackCause::kTooFewCorrespondences, std::to_string(association.count)};
    if (association.rms_m > config.max_rms_m)
        return {FallbackCause::kBadFitness, "rms " + std::to_string(association.rms_m) + " m"};
    if (association.observability < config.min_observability)
        return {FallbackCause::kDegenerate,
                "observability " + std::to_string(association.observability)};
    return {FallbackCause::kNone, ""};
}

}  // namespace

ScanEstimate RadarMapper::State::RegisterToMap(const Eigen::Matrix3Xd &source_base,
                                               const std::vector<DopplerObservation> &doppler,
                                               const MotionPrior &prediction, double dt_s,
                                               double threshold_m, const GroundUp *ground) {
    ScanEstimate out;
    const auto t_reg = Clock::now();
    const PclAlignment aligned =
        AlignWithPcl(source_base, prediction.T_world_base, map, config, threshold_m);
    out.alignment_ms = MillisecondsSince(t_reg);
    const Association association = Associate(source_base, aligned.T_world_base, map, config,
                                              threshold_m, config.max_registration_residuals);
    out.registration_ms = MillisecondsSince(t_reg);
    std::tie(out.cause, out.detail) = CheckRegistration(aligned, association, config);
    out.observability = association.observability;
    out.correspondences = association.count;
    out.fitness_rms_m = association.rms_m;
    if (out.fallback()) return out;

    // The Doppler residuals join only when the prior was not built from the same Doppler
    // velocity (counted once).
    const auto t_refine = Clock::now();
    const std::vector<DopplerObservation> doppler_residuals =
        config.use_doppler && !NeedsDoppler(prediction.kind)
            ? Thin(doppler, config.max_doppler_residuals)
            : std::vector<DopplerObservation>{};
    RefinementInput input;
    input.T_world_base_initial = aligned.T_world_base;
    input.prior = &prediction;
    input.matches = &association.matches;
    input.doppler = &doppler_residuals;
    input.T_world_base_prev = T_world_base_last;
    input.T_base_radar = extrinsics.T_base_radar;
    input.dt_s = dt_s;
    input.ground = ground;
    const RefinementOutput refined = RefinePose(input, config);
    out.refinement_ms = MillisecondsSince(t_refine);
    out.doppler_residuals = static_cast<int>(doppler_residuals.size());
    if (!refined.usable) {
        out.cause = FallbackCause::kUnrefined;
        return out;
    }
    out.registered = refined.registered;
    out.T_world_base_aligned = aligned.T_world_base;
    return out;
}

}  // namespace dorado::mapping
