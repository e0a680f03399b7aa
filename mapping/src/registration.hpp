#pragma once
// Internal: the steps of RadarMapper::Register, one free function each, so that the mapper's loop
// reads like the pipeline. PCL and Ceres stay inside the .cpp files that implement them.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "dorado/mapping/local_map.hpp"
#include "dorado/mapping/measurements.hpp"
#include "dorado/mapping/motion_prior.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::mapping {

/// Voxel-grid downsampling (PCL VoxelGrid: one centroid per occupied voxel). downsample.cpp.
[[nodiscard]] Eigen::Matrix3Xd VoxelDownsample(const Eigen::Matrix3Xd &points, double voxel_m);

struct PclAlignment {
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    bool converged = false;
};

/// Scan-to-map registration with PCL (point-to-point ICP, point-to-plane ICP or GICP) from the
/// guess, with correspondences cut at threshold_m. registration.cpp.
[[nodiscard]] PclAlignment AlignWithPcl(const Eigen::Matrix3Xd &source_base,
                                        const Eigen::Isometry3d &T_world_base_guess,
                                        const LocalMap &map, const MapperConfig &config,
                                        double threshold_m);

struct Association {
    std::vector<Correspondence> matches;  ///< thinned to at most max_matches
    int count = 0;                        ///< all matches within the threshold
    double rms_m = 0.0;
    /// min over translation and rotation of lambda_min / lambda_max of the point-to-plane
    /// information of the kept matches (1 = isotropic, 0 = a direction is not observed, e.g. one
    /// wall).
    double observability = 0.0;
};

/// Nearest map point within threshold_m of each source point at T_world_base, with the map's
/// local covariance. At most max_matches are kept (evenly spaced). association.cpp.
[[nodiscard]] Association Associate(const Eigen::Matrix3Xd &source_base,
                                    const Eigen::Isometry3d &T_world_base, const LocalMap &map,
                                    const MapperConfig &config, double threshold_m,
                                    int max_matches);

/// What the refinement of one scan starts from, by name (the mapper fills each field).
struct RefinementInput {
    Eigen::Isometry3d T_world_base_initial = Eigen::Isometry3d::Identity();
    /// The prediction (the prior from the newest pose) and the newest pose (T_world_base_prev).
    const MotionPrior *prior = nullptr;
    const std::vector<Correspondence> *matches = nullptr;
    /// The Doppler residuals (empty when the prior carries the Doppler velocity already).
    const std::vector<DopplerObservation> *doppler = nullptr;
    Eigen::Isometry3d T_world_base_prev = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_base_radar = Eigen::Isometry3d::Identity();
    double dt_s = 0.0;  ///< the interval the Doppler residuals compare the pose's velocity over
    /// The road's up-vector seen in this scan (none: no ground residual): held against the
    /// absolute roll and pitch of the pose.
    const GroundUp *ground = nullptr;
};

struct RefinementOutput {
    Eigen::Isometry3d T_world_base;
    bool usable = false;
    int iterations = 0;
    RegisteredPose registered;  ///< the registered pose and the registration's covariance
    bool ground_used = false;   ///< the ground residual joined (passed the innovation gate)
};

/// The registered pose: registration + Doppler + prior residuals jointly (the registration's
/// residuals at their per-point weight, which locks the pose to the map), and the registration's
/// own covariance by registration_covariance (what the smoother weighs it by). With
/// input.ground, the pose's roll and pitch are also held to the road's up-vector
/// (ground_factor.hpp), robustly and when its innovation against the prior passes the
/// observation's gate. refinement.cpp.
[[nodiscard]] RefinementOutput RefinePose(const RefinementInput &input, const MapperConfig &config);

}  // namespace dorado::mapping
