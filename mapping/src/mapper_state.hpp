#pragma once
// Internal: RadarMapper's state between scans and the steps of its per-scan loop
// (radar_mapper.cpp), each defined next to its helpers: the priors on the two chains, the
// estimate and its fallback, the window and the map update in mapper_steps.cpp; the 3-D
// registration to the map and its refinement in map_registration.cpp.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/adaptive_threshold.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "registration.hpp"

namespace dorado::mapping {

/// What steps 2-3 of Register made of one scan: the checks and their numbers (cause kNone:
/// trusted), and the poses on both chains with the output's covariance.
struct ScanEstimate {
    bool first_scan = false;  ///< the map was empty: the prior starts it
    FallbackCause cause = FallbackCause::kNone;
    std::string detail;
    double observability = 0.0;
    double prior_mahalanobis_squared = 0.0;
    int correspondences = 0;
    double fitness_rms_m = 0.0;
    double alignment_ms = 0.0, registration_ms = 0.0, refinement_ms = 0.0;
    /// The pose the map is built from (the map's chain) and the output pose with its covariance.
    Eigen::Isometry3d T_map_base = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    Matrix6d covariance = Matrix6d::Zero();
    RegisteredPose registered;
    std::optional<Matrix6d> filter_covariance;  ///< refinement filter: the posterior P
    int doppler_residuals = 0;
    bool ground_used = false;
    /// The registration's matches at PCL's pose, for the window smoother (none on a fallback).
    std::vector<Correspondence> matches;

    [[nodiscard]] bool fallback() const { return cause != FallbackCause::kNone; }
};

/// What step 4 of Register did to the map.
struct MapUpdate {
    bool updated = false;
    Eigen::Matrix3Xd points_added_world;
    double ms = 0.0;
};

struct Refined;  // map_registration.cpp

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
    /// The map chain's last pose relative to the map: zero after a registered scan, the prior's
    /// covariance compounded over the fallbacks since.
    Matrix6d unanchored_covariance = Matrix6d::Zero();
    std::optional<WindowSmoother> window;  ///< refinement = kWindow
    bool planar = false;                   ///< a 2D radar: registration in the plane
    /// refinement = kFilter: the covariance of T_world_base_last relative to the map (zero at the
    /// first scan, the map's origin).
    Matrix6d filter_covariance = Matrix6d::Zero();

    State(const MapperConfig &c, const Extrinsics &e, const VehicleGeometry &g);

    // mapper_steps.cpp
    /// The prior's motion from the output chain's previous pose, from the map chain's instead.
    [[nodiscard]] MotionPrior OnMapChain(const MotionPrior &prior) const;
    /// The output chain's prior; refinement filter: with the filter's prediction of its
    /// covariance relative to the map chain.
    [[nodiscard]] MotionPrior OutputPrior(const MotionPrior &prior) const;
    /// Steps 2-3: the first scan, too few points, the planar or the 3-D registration.
    [[nodiscard]] ScanEstimate Estimate(const Eigen::Matrix3Xd &source_base,
                                        const std::vector<DopplerObservation> &doppler,
                                        const MotionPrior &prior_map, const MotionPrior &prior,
                                        const MotionPrior &prior_output, const MapperInput &input,
                                        double threshold_m);
    /// A registration not trusted: the pose is the prior (counted in `fallbacks`).
    [[nodiscard]] ScanEstimate FallBack(ScanEstimate estimate, const MotionPrior &prior,
                                        const MotionPrior &prior_map);
    /// refinement window: the estimate with the window's newest pose.
    [[nodiscard]] ScanEstimate SmoothWindow(ScanEstimate estimate,
                                            const std::vector<DopplerObservation> &doppler,
                                            const MotionPrior &prior, const MapperInput &input);
    /// Step 4: the scan's points into the map at T_map_base (keyframes only, when configured).
    [[nodiscard]] MapUpdate UpdateMap(const Eigen::Matrix3Xd &p_base,
                                      const Eigen::Isometry3d &T_map_base, bool fallback);
    [[nodiscard]] bool IsKeyframe(const Eigen::Isometry3d &T_map_base) const;

    // map_registration.cpp
    /// Scan-to-map registration from the prior (PCL), its checks, then the refinement of a
    /// trusted one.
    [[nodiscard]] ScanEstimate RegisterToMap(const Eigen::Matrix3Xd &source_base,
                                             const std::vector<DopplerObservation> &doppler,
                                             const MotionPrior &prior_map, const MotionPrior &prior,
                                             double dt_s, double threshold_m,
                                             const GroundUp *ground);
    [[nodiscard]] Refined Refine(const Eigen::Matrix3Xd &source_base,
                                 const std::vector<DopplerObservation> &doppler_all,
                                 const MotionPrior &prior_map, const MotionPrior &prior,
                                 double dt_s, double threshold_m, const Association &association,
                                 const Eigen::Isometry3d &T_world_base_aligned,
                                 const GroundUp *ground) const;
};

/// A 2D radar's prior: its motion since T_world_base_last projected onto the plane.
[[nodiscard]] MotionPrior OnThePlane(const MotionPrior &prior,
                                     const Eigen::Isometry3d &T_world_base_last);

}  // namespace dorado::mapping
