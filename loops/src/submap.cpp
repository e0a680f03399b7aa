// Keyframe submaps in their anchors' frames (submap.hpp).
#include "dorado/loops/submap.hpp"

#include <cmath>
#include <stdexcept>

#include "dorado/core/require.hpp"

namespace dorado::loops {

void SubmapConfig::Validate() const {
    Require(length_m > 0.0 && std::isfinite(length_m), "loop_closure.submap_length_m",
            "must be > 0");
    Require(turn_deg > 0.0 && std::isfinite(turn_deg), "loop_closure.submap_turn_deg",
            "must be > 0");
    Require(voxel_m > 0.0 && std::isfinite(voxel_m), "loop_closure.submap_voxel_m", "must be > 0");
}

Matrix6d ComposeCovariance(const Matrix6d &cov_ab, const Eigen::Isometry3d &T_bc,
                           const Matrix6d &cov_bc) {
    // T_ab Exp(xi_ab) T_bc Exp(xi_bc) = T_ab T_bc Exp(Ad(T_bc^-1) xi_ab) Exp(xi_bc), with
    // Ad(T^-1) = [R^T, -R^T Hat(t); 0, R^T] for xi = [rho; phi].
    const Eigen::Matrix3d R_t = T_bc.rotation().transpose();
    Matrix6d adjoint_inverse = Matrix6d::Zero();
    adjoint_inverse.topLeftCorner<3, 3>() = R_t;
    adjoint_inverse.topRightCorner<3, 3>() = -R_t * Hat(T_bc.translation());
    adjoint_inverse.bottomRightCorner<3, 3>() = R_t;
    return adjoint_inverse * cov_ab * adjoint_inverse.transpose() + cov_bc;
}

SubmapBuilder::SubmapBuilder(const SubmapConfig &config) : config_(config) {
    config_.Validate();
}

bool SubmapBuilder::StartsNewSubmap(const Eigen::Isometry3d &T_world_base, double path_m) const {
    if (!open_) return true;
    const Eigen::Matrix3d R_anchor_base =
        open_->T_world_anchor.rotation().transpose() * T_world_base.rotation();
    const double turn_deg = RotationAngle(R_anchor_base) * 180.0 / M_PI;
    return path_m - open_->path_start_m() >= config_.length_m || turn_deg >= config_.turn_deg;
}

void SubmapBuilder::AddPoints(const Eigen::Matrix3Xd &points_world) {
    const Eigen::Isometry3d T_anchor_world = open_->T_world_anchor.inverse();
    for (Eigen::Index i = 0; i < points_world.cols(); ++i) {
        const Eigen::Vector3d p_anchor = T_anchor_world * points_world.col(i);
        if (!p_anchor.allFinite()) continue;
        if (open_voxels_.insert(mapping::VoxelKeyOf(p_anchor, config_.voxel_m)).second)
            open_points_.push_back(p_anchor.cast<float>());
    }
}

std::optional<Submap> SubmapBuilder::Add(const mapping::WrittenPose &pose) {
    if (started_) path_m_ += (pose.T_world_base.translation() - T_world_last_.translation()).norm();
    std::optional<Submap> closed;
    if (StartsNewSubmap(pose.T_world_base, path_m_)) {
        if (open_) {
            const Eigen::Isometry3d T_last_base = T_world_last_.inverse() * pose.T_world_base;
            AnchorMotion motion;
            motion.T_anchor_next = open_->T_world_anchor.inverse() * pose.T_world_base;
            motion.covariance =
                ComposeCovariance(covariance_anchor_last_, T_last_base, pose.covariance);
            open_->to_next = motion;
            closed = Finish();
        }
        open_ = Submap{};
        open_->id = next_id_++;
        open_->T_world_anchor = pose.T_world_base;
        covariance_anchor_last_.setZero();
    } else {
        const Eigen::Isometry3d T_last_base = T_world_last_.inverse() * pose.T_world_base;
        covariance_anchor_last_ =
            ComposeCovariance(covariance_anchor_last_, T_last_base, pose.covariance);
    }
    open_->scans.push_back(
        {pose.stamp_ns, open_->T_world_anchor.inverse() * pose.T_world_base, path_m_});
    AddPoints(pose.map_points_added_world);
    T_world_last_ = pose.T_world_base;
    started_ = true;
    return closed;
}

std::optional<Submap> SubmapBuilder::Finish() {
    if (!open_) return std::nullopt;
    Submap done = std::move(*open_);
    open_.reset();
    done.points_anchor.resize(3, static_cast<Eigen::Index>(open_points_.size()));
    for (std::size_t i = 0; i < open_points_.size(); ++i)
        done.points_anchor.col(static_cast<Eigen::Index>(i)) = open_points_[i];
    open_points_.clear();
    open_points_.shrink_to_fit();
    open_voxels_.clear();
    return done;
}

}  // namespace dorado::loops
