#pragma once
/// @file loop_verification.hpp
/// A loop candidate verified by registration: the query submap's points registered onto the
/// candidate's (both in their anchors' frames) from the place match's guess, by a Gauss-Newton
/// ICP with GICP-style neighbourhood covariances (a soft point-to-plane distance), started at the
/// height the points agree on (the odometry's height drifts by metres over a lap), then judged by
/// overlap, correspondences, fit and the observability of the horizontal directions (what the
/// matched planes and lines fix: a corridor leaves the direction along it open). Its
/// information about the relative pose is the registration's, counted once per map cell (points of
/// one cell share their surface's error) and scaled by the residuals' own variance.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dorado/core/lie.hpp"

namespace dorado::loops {

struct VerificationConfig {
    int max_iterations = 30;
    double initial_threshold_m = 3.0;  ///< correspondence distance of the first iterations ...
    double final_threshold_m = 1.0;    ///< ... shrinking to this one
    double point_sigma_m = 0.3;        ///< a point's position noise (the neighbourhoods' scale)
    double plane_flatness = 0.1;       ///< GICP eigenvalue of a neighbourhood's normal axis
    double cluster_m = 8.0;            ///< residuals of one such cell count as one measurement
    double min_overlap = 0.35;  ///< query points with a candidate point within final_threshold_m
    int min_correspondences = 150;
    double max_rms_m = 0.7;  ///< RMS distance of the correspondences
    /// Smallest eigenvalue / largest over (x, y, yaw * the points' RMS radius) of the information
    /// of the matched structure (a plane fixes its normal, a line the directions across it).
    double min_observability = 0.05;
    /// Added to the registration's covariance (1 sigma): the submaps' own error.
    double floor_sigma_translation_m = 0.15;
    double floor_sigma_rotation_rad = 0.003;
    void Validate() const;
};

/// Why a registration is not a loop (kNone: it is one), in the order the checks run.
enum class VerificationFailure {
    kNone,
    kTooFewPoints,
    kNotConverged,
    kLowOverlap,
    kTooFewCorrespondences,
    kBadFitness,
    kDegenerate,
};

struct Verification {
    VerificationFailure failure = VerificationFailure::kTooFewPoints;
    /// The query anchor in the candidate anchor's frame (T_candidate_query).
    Eigen::Isometry3d T_candidate_query = Eigen::Isometry3d::Identity();
    int iterations = 0;
    int correspondences = 0;
    double overlap = 0.0;
    double rms_m = 0.0;
    double observability = 0.0;
    /// The information of T_candidate_query's error (right perturbation, [rho; phi]).
    Matrix6d information = Matrix6d::Zero();
    [[nodiscard]] bool accepted() const { return failure == VerificationFailure::kNone; }
};

/// Registers query onto candidate (anchor frames) from T_candidate_query_guess.
[[nodiscard]] Verification VerifyLoop(const Eigen::Matrix3Xf &candidate_points,
                                      const Eigen::Matrix3Xf &query_points,
                                      const Eigen::Isometry3d &T_candidate_query_guess,
                                      const VerificationConfig &config);

/// "" (kNone), "too few points", "not converged", "low overlap", "too few correspondences",
/// "bad fitness", "degenerate".
[[nodiscard]] const char *ToString(VerificationFailure failure);

}  // namespace dorado::loops
