#pragma once
// Internal: RadarMapper's state between scans and the steps of its per-scan loop
// (radar_mapper.cpp), each defined next to its helpers: the prediction, the estimate and its
// fallback, the smoother's step and the map update in mapper_steps.cpp; the 3-D registration to
// the map and its refinement in map_registration.cpp.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/adaptive_threshold.hpp"
#include "dorado/mapping/pose_smoother.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "registration.hpp"

namespace dorado::mapping {

/// What steps 2-3 of Register made of one scan: the checks and their numbers (cause kNone:
/// registered) and the registered pose.
struct ScanEstimate {
    bool first_scan = false;  ///< the map was empty: the prior starts it
    FallbackCause cause = FallbackCause::kNone;
    std::string detail;
    double observability = 0.0;
    int correspondences = 0;
    double fitness_rms_m = 0.0;
    double alignment_ms = 0.0, registration_ms = 0.0, refinement_ms = 0.0;
    RegisteredPose registered;
    /// The registration alone (PCL's alignment from the prediction), before the refinement pulls
    /// it toward the prediction: what the registration's distance from the prediction is measured
    /// on.
    Eigen::Isometry3d T_world_base_aligned = Eigen::Isometry3d::Identity();
    int doppler_residuals = 0;
    [[nodiscard]] bool fallback() const { return cause != FallbackCause::kNone; }
};

/// A scan in the smoother's window: what its written pose carries besides the pose, and its
/// points, which enter the map when the pose leaves the window.
struct PendingScan {
    WrittenPose written;
    Eigen::Matrix3Xd p_base;
    bool fallback = false;
    bool in_map = false;  ///< the first scan's points enter the map at once (the map's origin)
};

struct RadarMapper::State {
    MapperConfig config;
    Extrinsics extrinsics;
    LocalMap map;
    MoverMemory movers;
    PoseSmoother smoother;
    std::deque<PendingScan> pending;  ///< the scans in the smoother's window, oldest first
    double time_s = 0.0;  ///< the sum of the scans' dt_s (the smoother's and movers' clock)
    AdaptiveThreshold threshold;
    bool has_pose = false;
    bool finished = false;
    /// The newest scan's pose as last estimated (the front end's next prior starts there).
    Eigen::Isometry3d T_world_base_last = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_world_base_last_keyframe = Eigen::Isometry3d::Identity();
    int fallbacks = 0;
    bool planar = false;  ///< a 2D radar: registration in the plane

    State(const MapperConfig &c, const Extrinsics &e);

    // mapper_steps.cpp
    /// The prior's motion from the newest pose, with the newest pose's own uncertainty carried
    /// along it (P = Ad(D^-1) P_newest Ad(D^-1)^T + C): where registration starts and what it is
    /// checked against.
    [[nodiscard]] MotionPrior Predict(const MotionPrior &prior) const;
    /// Steps 2-3: the first scan, too few points, the planar or the 3-D registration.
    [[nodiscard]] ScanEstimate Estimate(const Eigen::Matrix3Xd &source_base,
                                        const std::vector<DopplerObservation> &doppler,
                                        const MotionPrior &prediction, const MapperInput &input,
                                        double threshold_m);
    /// Step 4: the scan into the smoother (the registration weighted by its distance from the
    /// prediction), the poses that leave it written and their scans' points into the map.
    [[nodiscard]] std::vector<WrittenPose> Smooth(PendingScan scan, const MotionPrior &prior,
                                                  const MotionPrior &prediction,
                                                  const ScanEstimate &estimate,
                                                  const GroundUp *ground,
                                                  RegistrationResult &result);
    /// The written poses' scans into the map (keyframes only, when configured).
    [[nodiscard]] std::vector<WrittenPose> Write(const std::vector<SmoothedPose> &smoothed,
                                                 double &map_update_ms);
    [[nodiscard]] bool IsKeyframe(const Eigen::Isometry3d &T_world_base) const;
    /// Cells emptied by movers: the points a pending scan already put in the map there (the first
    /// scan's) leave its report too, so that an output map built from the written poses stays the
    /// mapper's.
    void DropFromPending(const std::vector<VoxelKey> &cells);

    // map_registration.cpp
    /// Scan-to-map registration from the prediction (PCL), its checks, then the refinement of
    /// a trusted one (registration, Doppler and prediction residuals, Ceres).
    [[nodiscard]] ScanEstimate RegisterToMap(const Eigen::Matrix3Xd &source_base,
                                             const std::vector<DopplerObservation> &doppler,
                                             const MotionPrior &prediction, double dt_s,
                                             double threshold_m, const GroundUp *ground);
};

/// A 2D radar's prior: its motion since T_world_base_last projected onto the plane.
[[nodiscard]] MotionPrior OnThePlane(const MotionPrior &prior,
                                     const Eigen::Isometry3d &T_world_base_last);

}  // namespace dorado::mapping
