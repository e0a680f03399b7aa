// Steps 2-3 of RadarMapper::Register in 3-D: scan-to-map registration from the prior (PCL), the
// checks that decide whether it is trusted, and the Doppler-aware refinement of a trusted one.
#include <ceres/loss_function.h>

#include <chrono>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "dorado/core/time.hpp"
#include "mapper_state.hpp"
#include "pose_information.hpp"
#include "robust_loss.hpp"
#include "scan_points.hpp"

namespace dorado::mapping {

// What Refine computed: the registered pose on the map's chain, the output pose and its
// covariance, the registration's estimate (valid only when the refinement succeeded) and the last
// association.
struct Refined {
    Eigen::Isometry3d T_map_base = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    Matrix6d covariance = Matrix6d::Zero();
    std::optional<Matrix6d> filter_covariance;  ///< refinement filter: the posterior P
    RegisteredPose registered;
    Association association;
    int doppler_residuals = 0;
    bool ground_used = false;
};

namespace {

using Clock = std::chrono::steady_clock;

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
                                   const Eigen::Isometry3d &T_world_base_aligned,
                                   const GroundUp *ground) const {
    const bool filter = config.refinement == Refinement::kFilter;
    const bool ceres = RefinesWithCeres(config.refinement);
    Refined out;
    out.T_map_base = T_world_base_aligned;
    out.T_world_base = ceres ? prior.T_world_base : T_world_base_aligned;
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
            out.association = Associate(source_base, out.T_map_base, map, config, threshold_m,
                                        config.max_registration_residuals);
        if (out.association.count < config.min_correspondences) break;
        RefinementInput input;
        input.T_world_base_initial = out.T_map_base;
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
            out.T_map_base = refined.registered.T_world_base;
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

ScanEstimate RadarMapper::State::RegisterToMap(const Eigen::Matrix3Xd &source_base,
                                               const std::vector<DopplerObservation> &doppler,
                                               const MotionPrior &prior_map,
                                               const MotionPrior &prior, double dt_s,
                                               double threshold_m, const GroundUp *ground) {
    ScanEstimate out;
    const auto t_reg = Clock::now();
    const PclAlignment aligned =
        AlignWithPcl(source_base, prior_map.T_world_base, map, config, threshold_m);
    out.alignment_ms = MillisecondsSince(t_reg);
    Association association = Associate(source_base, aligned.T_world_base, map, config, threshold_m,
                                        config.max_registration_residuals);
    out.prior_mahalanobis_squared =
        PriorMahalanobisSquared(WidenedPrior(prior_map, config), aligned.T_world_base);
    out.registration_ms = MillisecondsSince(t_reg);
    std::tie(out.cause, out.detail) =
        CheckRegistration(aligned, association, out.prior_mahalanobis_squared, config);
    out.observability = association.observability;
    out.correspondences = association.count;
    out.fitness_rms_m = association.rms_m;
    if (out.fallback()) return out;

    // Covariance matching: PCL's pose (the registration alone, started at the prior) against the
    // prior, each with its model's covariance; then both weighed by the scales learnt so far.
    if (noise.enabled()) {
        const auto loss = MakeLoss(config.kernel, config.kernel_scale);
        const RegisteredPose alone =
            RegistrationCovariance(aligned.T_world_base, association.matches, loss.get(), config);
        if (alone.valid && alone.weak_directions == 0)
            noise.Add(LogSE3(prior_map.T_world_base.inverse() * aligned.T_world_base),
                      prior_map.covariance, alone.covariance);
    }
    const NoiseScales &scales = noise.scales();
    MotionPrior prior_map_scaled = prior_map, prior_scaled = prior;
    prior_map_scaled.covariance = ScaleBlocks(prior_map.covariance, scales.prior);
    prior_scaled.covariance = ScaleBlocks(prior.covariance, scales.prior);

    const auto t_refine = Clock::now();
    const Refined refined = Refine(source_base, doppler, prior_map_scaled, prior_scaled, dt_s,
                                   threshold_m, association, aligned.T_world_base, ground);
    out.refinement_ms = MillisecondsSince(t_refine);
    // kiss-icp: the threshold adapts to how far registration corrected the prior.
    threshold.Update(prior_map.T_world_base.inverse() * refined.T_map_base);

    out.T_map_base = refined.T_map_base;
    out.T_world_base = refined.T_world_base;
    out.covariance = refined.covariance;
    out.registered = refined.registered;
    out.filter_covariance = refined.filter_covariance;
    out.correspondences = refined.association.count;
    out.fitness_rms_m = refined.association.rms_m;
    out.doppler_residuals = refined.doppler_residuals;
    out.ground_used = refined.ground_used;
    out.matches = std::move(association.matches);
    return out;
}

}  // namespace dorado::mapping
