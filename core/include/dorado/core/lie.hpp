#pragma once
/// @file lie.hpp
/// SO(3) and SE(3) exponential and logarithm maps in closed form (Rodrigues), with Taylor
/// expansions near zero. Tangent vectors of SE(3) are ordered [rho (translation part); phi
/// (rotation)].

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dorado {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Skew-symmetric matrix with Hat(a) * b == a.cross(b).
[[nodiscard]] Eigen::Matrix3d Hat(const Eigen::Vector3d &v);

/// Rotation matrix exp(Hat(phi)).
[[nodiscard]] Eigen::Matrix3d ExpSO3(const Eigen::Vector3d &phi);

/// Rotation vector phi with ExpSO3(phi) == R, |phi| in [0, pi].
[[nodiscard]] Eigen::Vector3d LogSO3(const Eigen::Matrix3d &R);

/// Left Jacobian of SO(3): J(phi) = sum_k Hat(phi)^k / (k+1)!.
[[nodiscard]] Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d &phi);

/// Inverse of LeftJacobianSO3.
[[nodiscard]] Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d &phi);

/// exp of the twist xi = [rho; phi]: rotation ExpSO3(phi), translation LeftJacobianSO3(phi) * rho.
[[nodiscard]] Eigen::Isometry3d ExpSE3(const Vector6d &xi);

/// Inverse of ExpSE3.
[[nodiscard]] Vector6d LogSE3(const Eigen::Isometry3d &T);

/// Pose interpolation: slerp of the rotation and linear interpolation of the translation,
/// alpha = 0 gives T_a, alpha = 1 gives T_b.
[[nodiscard]] Eigen::Isometry3d InterpolatePose(const Eigen::Isometry3d &T_a,
                                                const Eigen::Isometry3d &T_b, double alpha);

/// Rotation angle of R in radians, in [0, pi].
[[nodiscard]] double RotationAngle(const Eigen::Matrix3d &R);

/// R = Rz(yaw) Ry(pitch) Rx(roll) (ZYX Euler angles, radians): the one roll/pitch/yaw convention
/// of dorado (dataset YAML rotation_rpy_deg, simulator mounts, calibration output).
[[nodiscard]] Eigen::Matrix3d RotationFromRollPitchYaw(const Eigen::Vector3d &rpy_rad);

/// The inverse of RotationFromRollPitchYaw: [roll, pitch, yaw] in radians, pitch in [-pi/2, pi/2].
[[nodiscard]] Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d &R);

}  // namespace dorado
