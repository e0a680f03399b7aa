#pragma once
/// @file pose_smoother.hpp
/// The mapper's estimator: a fixed-lag smoother over the poses of the last scans. Its factors are
/// the motion prior between consecutive scans (the Doppler odometry's, the IMU's, ...), the
/// registration of each scan to the map (a robust 6-DoF pose measurement, by the registration's
/// own information), the road's up-vector where a ground plane was seen, and, for the oldest pose,
/// what the scans that already left the window said about it (their marginal). A pose leaves the
/// window smoothed, estimated from the scans on both sides of it: that is the pose written and the
/// one its scan enters the map at. Plain Eigen: a Gauss-Newton step on the window's
/// block-tridiagonal normal equations per iteration, a few hundred microseconds at most.
///
/// Every pose error is the right perturbation xi = [rho; phi] of T_world_base (T_true =
/// T ExpSE3(xi), in the base frame: MotionPrior's convention).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/measurements.hpp"

namespace dorado::mapping {

struct SmootherConfig {
    /// A pose is written once the newest scan is this much later than it [s] (0: every pose is
    /// written at once, a filter).
    double lag_s = 1.0;
    /// A registration farther than this squared Mahalanobis distance from the prediction (under
    /// both covariances) counts with its information scaled down until it is this far (the
    /// mapper's robust weighting; 25: beyond the 99.9 % of 6 degrees of freedom).
    double max_registration_chi2 = 25.0;
    int max_iterations = 3;  ///< Gauss-Newton iterations per scan

    /// Throws std::invalid_argument naming the first bad key.
    void Validate() const;
};

/// One scan's measurements for the smoother.
struct SmootherScan {
    int64_t stamp_ns = 0;
    double time_s = 0.0;  ///< on any clock that increases from scan to scan
    /// The motion prior: this scan's pose predicted from the previous one's,
    /// T_world_base = T_world_base_previous * motion, with the covariance of that motion (ignored
    /// for the first scan, whose pose is motion: the map's origin).
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    Matrix6d motion_covariance = Matrix6d::Identity();
    /// The registered pose and the registration's information about it, robust weight applied
    /// (may be singular: zero along what the map does not observe); none when the scan fell
    /// back to the prior.
    std::optional<Eigen::Isometry3d> T_world_base_registered;
    Matrix6d registration_information = Matrix6d::Zero();
    /// The road's up-vector seen in this scan (already gated against the prior).
    std::optional<GroundUp> ground_base;
};

/// A pose that left the window.
struct SmoothedPose {
    int64_t stamp_ns = 0;
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    /// The covariance of the motion from the previous smoothed pose to this one (xi convention);
    /// zero for the first scan.
    Matrix6d motion_covariance = Matrix6d::Zero();
};

class PoseSmoother {
  public:
    explicit PoseSmoother(const SmootherConfig &config);

    /// Adds the newest scan and re-estimates the window; returns the newest pose's estimate (the
    /// filtered pose: only the scans up to it have seen it).
    Eigen::Isometry3d Add(const SmootherScan &scan);
    /// The poses that left the window after the last Add (oldest first), smoothed.
    [[nodiscard]] std::vector<SmoothedPose> TakeSmoothed();
    /// Every pose still in the window, as smoothed as it will get (the end of the drive).
    [[nodiscard]] std::vector<SmoothedPose> Flush();

    [[nodiscard]] bool empty() const { return states_.empty(); }
    [[nodiscard]] const Eigen::Isometry3d &newest() const { return states_.back().T_world_base; }
    /// The marginal covariance of the newest pose given everything so far.
    [[nodiscard]] const Matrix6d &newest_covariance() const { return newest_covariance_; }
    [[nodiscard]] std::size_t size() const { return states_.size(); }

  private:
    struct State {
        SmootherScan scan;
        Eigen::Isometry3d T_world_base;
        Matrix6d registration_sqrt_information = Matrix6d::Zero();
    };
    void Solve();
    std::optional<SmoothedPose> PopOldest();

    SmootherConfig config_;
    std::deque<State> states_;
    /// What the scans that left the window say about the oldest pose: mean and sqrt information.
    Eigen::Isometry3d anchor_mean_ = Eigen::Isometry3d::Identity();
    Matrix6d anchor_sqrt_information_ = Matrix6d::Zero();
    /// The covariance of [xi_0; xi_1] (the two oldest poses) at the last solve.
    Eigen::Matrix<double, 12, 12> oldest_pair_covariance_ = Eigen::Matrix<double, 12, 12>::Zero();
    Matrix6d newest_covariance_ = Matrix6d::Zero();
    /// The motion covariance the next pose to leave will be written with.
    Matrix6d next_motion_covariance_ = Matrix6d::Zero();
    std::vector<SmoothedPose> smoothed_;
};

}  // namespace dorado::mapping
