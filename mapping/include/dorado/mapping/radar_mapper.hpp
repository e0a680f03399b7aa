#pragma once
/// @file radar_mapper.hpp
/// Radar scan-to-map registration with a motion prior (paper section IV-C), made Doppler-aware and
/// smoothed: for each scan, downsample, register against the local map with PCL from the
/// prediction, refine the registered pose with Ceres (registration, Doppler and prior residuals),
/// then one estimator, a fixed-lag smoother (pose_smoother.hpp), weighs the motion prior, the
/// registration (robustly, by its information) and the ground over the last second of scans. A
/// pose leaves the smoother smoothed: it is the pose written and the one its scan enters the map
/// at (one chain).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/radar_scan.hpp"
#include "dorado/mapping/local_map.hpp"
#include "dorado/mapping/measurements.hpp"
#include "dorado/mapping/motion_prior.hpp"
#include "dorado/mapping/movers.hpp"
#include "dorado/mapping/pose_smoother.hpp"

namespace dorado::mapping {

enum class RegistrationMethod { kPointToPoint, kPointToPlane, kGicp };
/// How the registration's information about the pose is counted when it is fused with the prior
/// (configs/mapper.yaml, registration_covariance):
///   kIndependent: every point residual an independent measurement of the per-point noise model
///                 (sum of J^T W J): hundreds of correlated residuals, over-counted;
///   kResidualScale: the same, scaled by the residuals' own variance per scan;
///   kClustered: the cluster-robust (sandwich) covariance H^-1 (sum_c g_c g_c^T) H^-1 with the
///               residuals grouped by the map cell they fall in (registration_cluster_m): residuals
///               of one cell share their surface's error and count as one.
/// Each adds the floor diag(registration_floor_sigma_translation_m^2, ..._rotation_rad^2).
enum class RegistrationCovarianceModel { kIndependent, kResidualScale, kClustered };

/// Every default is explained in configs/mapper.yaml.
struct MapperConfig {
    // Which points of a scan are used.
    double min_range_m = 1.0;
    double max_range_m = 100.0;
    double scan_voxel_m = 1.0;    ///< voxel of the downsampled scan that is registered
    int max_source_points = 800;  ///< then evenly thinned to at most this many

    LocalMapConfig map;
    /// What else stays out of the map besides the mask's moving points (movers.hpp).
    MoverConfig movers;
    /// Add a scan to the map only when the vehicle moved this far / turned this much since the
    /// last map update (0 and 0: every scan).
    double keyframe_distance_m = 1.0;
    double keyframe_angle_deg = 5.0;
    bool update_map_on_fallback = true;

    // PCL registration.
    RegistrationMethod method = RegistrationMethod::kPointToPoint;
    int max_iterations = 10;
    double initial_threshold_m = 2.0;
    double min_threshold_m = 0.5;
    double min_motion_m = 0.1;
    int covariance_neighbours = 20;  ///< k of the local covariances (plane, GICP)

    // Ceres refinement of the registered pose.
    RobustKernel kernel = RobustKernel::kCauchy;
    double kernel_scale = 1.0;    ///< in whitened units (sigmas)
    double point_sigma_m = 0.3;   ///< radar point position noise
    double plane_flatness = 0.1;  ///< GICP-style eigenvalue of a map neighbourhood's normal axis
    double doppler_sigma_mps = 0.15;
    bool use_doppler = true;
    int max_registration_residuals = 250;
    int max_doppler_residuals = 150;
    int refine_max_iterations = 5;
    /// How the registration's information is counted against the prior (see the enum).
    RegistrationCovarianceModel registration_covariance = RegistrationCovarianceModel::kClustered;
    double registration_cluster_m = 4.0;  ///< cell of the clustered model's groups

    /// The estimator: the fixed-lag smoother over the prior, the registrations and the ground.
    SmootherConfig smoother;

    // When there is nothing to register and the pose is the prior's.
    int min_correspondences = 40;
    double max_rms_m = 1.5;
    /// The registration's own noise that no scan's residuals show (the map's error, shared by all
    /// of a scan's matches): added to the registration's covariance, per axis (1 sigma).
    double registration_floor_sigma_translation_m = 0.03;
    double registration_floor_sigma_rotation_rad = 0.003;
    /// Degeneracy-aware registration (Zhang et al. ICRA 2016, X-ICP), refinement ceres: a direction
    /// of the registration's per-point information (its translation and rotation blocks, each
    /// eigen-decomposed) whose eigenvalue is below this fraction of its block's largest is weak:
    /// the registered pose keeps the prior's value along it and the registration adds no
    /// information there (the prior carries the pose); across the others the map does. 0: off.
    double registration_weak_ratio = 0.0;
    double min_observability = 0.004;

    /// Throws std::invalid_argument naming the first bad key.
    void Validate() const;
};

/// Why a scan has no registration (its pose is the prior's, smoothed), in the order the checks
/// run; the numbers that decided it are in RegistrationResult::fallback_detail. A registration
/// that disagrees with the prior is not one: it is down-weighted (registration_weight).
enum class FallbackCause {
    kNone,          ///< registered
    kTooFewPoints,  ///< "too few points": the downsampled scan is smaller than min_correspondences
    kNotConverged,  ///< "registration did not converge"
    kTooFewCorrespondences,  ///< "too few correspondences" within the threshold
    kBadFitness,             ///< "bad fitness": their RMS distance above max_rms_m
    kDegenerate,             ///< "degenerate geometry": observability below min_observability
    kUnrefined,              ///< "refinement failed": Ceres found no usable registered pose
};
/// Every cause, in the order above.
inline constexpr FallbackCause kAllFallbackCauses[] = {
    FallbackCause::kNone,         FallbackCause::kTooFewPoints,
    FallbackCause::kNotConverged, FallbackCause::kTooFewCorrespondences,
    FallbackCause::kBadFitness,   FallbackCause::kDegenerate,
    FallbackCause::kUnrefined};

/// Milliseconds spent in each stage of Register.
struct StageTimes {
    double preprocess_ms = 0.0;    ///< range gate, mask, base frame, voxel downsample
    double registration_ms = 0.0;  ///< PCL alignment + data association + checks
    double alignment_ms = 0.0;     ///< of which the PCL alignment alone
    double refinement_ms = 0.0;    ///< Ceres
    double map_update_ms = 0.0;    ///< voxel map update + PCL's float copy of the map
    double total_ms = 0.0;
};

/// The registered pose and the registration's covariance (registration_covariance, the xi
/// convention below): registration, Doppler and prior residuals jointly (Ceres), the smoother's
/// measurement of the scan's pose.
struct RegisteredPose {
    bool valid = false;  ///< false on the first scan, on a fallback, or a singular information
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    Matrix6d covariance = Matrix6d::Zero();
    double residual_scale = 0.0;  ///< whitened residual RMS (1 = the noise model)
    int clusters = 0;             ///< independent groups of residuals (clustered model)
    /// Directions the registration does not observe (registration_weak_ratio), and the projector
    /// onto the ones it does (identity when none is weak); `information` is the registration's
    /// information about the pose, zero along the weak directions (covariance: its inverse,
    /// regularised).
    int weak_directions = 0;
    Matrix6d strong_projector = Matrix6d::Identity();
    Matrix6d information = Matrix6d::Zero();
};

/// A scan's pose as written: smoothed by the scans on both sides of it, the pose its points
/// entered the map at. Poses are written in scan order, about smoother.lag_s after their scan.
struct WrittenPose {
    int64_t stamp_ns = 0;
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    /// The covariance of the motion from the previous written pose (xi convention below); zero
    /// for the first scan.
    Matrix6d covariance = Matrix6d::Zero();
    /// The smoother's inputs for this scan, as they were: the motion prior (from the previous
    /// scan's newest estimate) and the registered pose (not valid on a fallback).
    MotionPrior prior;
    RegisteredPose registered;
    bool first_scan = false;
    double registration_weight = 0.0;  ///< after the robust loss (0: no registration)
    bool map_updated = false;          ///< a keyframe: its points entered the map
    /// The points it added to the mapper's map, world frame: the union over a run is the map as
    /// it was (map.pcd), cropping aside.
    Eigen::Matrix3Xd map_points_added_world;
};

/// What Register made of the newest scan.
struct RegistrationResult {
    /// The newest scan's pose: filtered (the smoother's estimate from the scans up to this one),
    /// the start of the next scan's prior. The written, smoothed poses are in `written`.
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    /// Its marginal covariance given the map, as the right perturbation xi = [rho; phi] in the
    /// base frame (T_true = T_world_base ExpSE3(xi), MotionPrior's convention).
    Matrix6d covariance = Matrix6d::Zero();
    RegisteredPose registered;  ///< the registration's estimate the smoother weighs
    /// The registration's alignment from the prediction (PCL), before its refinement: what
    /// prior_mahalanobis_squared measures.
    Eigen::Isometry3d T_world_base_aligned = Eigen::Isometry3d::Identity();
    bool first_scan = false;  ///< the map was empty: the pose is the prior and starts the map
    /// Nothing to register (kNone: registered): the pose is the prior's, smoothed.
    FallbackCause fallback_cause = FallbackCause::kNone;
    std::string fallback_detail;  ///< the numbers behind the cause, e.g. "rms 1.7 m" (for reports)
    [[nodiscard]] bool fallback() const { return fallback_cause != FallbackCause::kNone; }
    int source_points = 0;       ///< downsampled points registered
    int correspondences = 0;     ///< within the threshold at the final pose
    double fitness_rms_m = 0.0;  ///< RMS distance of those correspondences
    double observability = 0.0;  ///< min eigenvalue ratio of the point-to-plane information
    /// The alignment against the prediction: squared Mahalanobis distance under the prediction's
    /// and the registration's covariances (6 on average when both are honest).
    double prior_mahalanobis_squared = 0.0;
    /// The registration's weight in the smoother: 1 within smoother.max_registration_chi2 of the
    /// prediction; beyond, its information is scaled by this until it is that far (0 without a
    /// registration).
    double registration_weight = 0.0;
    double threshold_m = 0.0;  ///< correspondence threshold used
    int doppler_residuals = 0;
    /// The scan's ground (MapperInput::ground_base) joined the smoother (3-D, consistent with
    /// the prediction).
    bool ground_used = false;
    /// The map points dropped from cells seen moving in this scan.
    int map_points_dropped = 0;
    /// The map cells (map.voxel_size_m) emptied because something moved there: an output map
    /// that accumulates the written points drops its points in them too (before adding this
    /// call's `written` points).
    std::vector<VoxelKey> map_cells_dropped;
    /// Per scan point: true when the mask called it static but the mover rules kept it out (near
    /// a moving point, or in a cell where something moved recently: movers.hpp).
    Eigen::Array<bool, Eigen::Dynamic, 1> mover_dropped;
    [[nodiscard]] int mover_points_dropped() const {
        return static_cast<int>(mover_dropped.count());
    }
    /// The poses that left the smoother with this scan (oldest first; none while it fills).
    std::vector<WrittenPose> written;
    std::size_t local_map_points = 0;  ///< after this scan's update (bounded by the crop radius)
    StageTimes times;
};

/// A per-point flag, same length as the scan.
using PointMask = Eigen::Array<bool, Eigen::Dynamic, 1>;

/// One scan's inputs besides its points.
struct MapperInput {
    MotionPrior prior;
    /// Time since the previous registered scan [s] (the interval over which the Doppler
    /// residuals compare the pose's velocity); ignored on the first scan.
    double dt_s = 0.0;
    /// true = static: only these points are registered, used as Doppler residuals and added to
    /// the map. Empty: every point.
    PointMask static_mask;
    /// true = seen moving (the Doppler mask's outliers): kept out with their neighbours and
    /// remembered in the map (movers.hpp). Empty: none.
    PointMask moving_mask;
    /// The road's up-vector seen in this scan: holds the poses' roll and pitch in the smoother
    /// (3-D; not in planar mode, where they are held at the prior's).
    std::optional<GroundUp> ground_base;
};

class RadarMapper {
  public:
    RadarMapper(const MapperConfig &config, const Extrinsics &extrinsics);
    ~RadarMapper();
    RadarMapper(RadarMapper &&) noexcept;
    RadarMapper &operator=(RadarMapper &&) noexcept;

    /// Registers one scan (radar frame) with its inputs (MapperInput: the prior, dt, the masks,
    /// the gyro rate and the ground). Throws std::invalid_argument on a mask of the wrong size, a
    /// non-finite dt or prior.
    RegistrationResult Register(const RadarScan &scan_radar, const MapperInput &input);

    [[nodiscard]] const LocalMap &local_map() const;
    [[nodiscard]] const MapperConfig &config() const;
    /// Scans that fell back to the prior so far.
    [[nodiscard]] int fallbacks() const;
    /// The end of the drive: every pose still in the smoother, written (in scan order, each
    /// scan's points into the map as in Register). Register throws std::logic_error after it.
    std::vector<WrittenPose> Finish();

    /// A 2D radar (the odometry's planar mode): from now on every scan registers in the plane,
    /// x, y and yaw, with z, roll and pitch held at the prior's (planar_registration.hpp).
    void SetPlanar();
    [[nodiscard]] bool planar() const;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

[[nodiscard]] const char *ToString(RegistrationMethod method);
/// "" (kNone), "too few points", "registration did not converge", ... (as in the enum).
[[nodiscard]] const char *ToString(FallbackCause cause);
[[nodiscard]] const char *ToString(RobustKernel kernel);
/// Parse "point_to_point" | "point_to_plane" | "gicp"; throws std::invalid_argument.
[[nodiscard]] RegistrationMethod ParseRegistrationMethod(const std::string &name);
/// Parse "none" | "huber" | "cauchy" | "tukey"; throws std::invalid_argument.
[[nodiscard]] RobustKernel ParseRobustKernel(const std::string &name);
/// "independent" | "residual_scale" | "clustered".
[[nodiscard]] const char *ToString(RegistrationCovarianceModel model);
/// The inverse of ToString(RegistrationCovarianceModel); throws std::invalid_argument.
[[nodiscard]] RegistrationCovarianceModel ParseRegistrationCovarianceModel(const std::string &name);

}  // namespace dorado::mapping
