#pragma once
/// @file angles.hpp
/// Degrees and radians: configs and reports speak degrees, the estimators radians. The one place
/// that converts them (no inline `* M_PI / 180`).

#include <Eigen/Core>

namespace dorado {

inline constexpr double kPi = 3.14159265358979323846;

[[nodiscard]] constexpr double DegToRad(double degrees) {
    return degrees * (kPi / 180.0);
}
[[nodiscard]] constexpr double RadToDeg(double radians) {
    return radians * (180.0 / kPi);
}
/// Per component (roll, pitch, yaw triples, rotation vectors).
[[nodiscard]] inline Eigen::Vector3d DegToRad(const Eigen::Vector3d &degrees) {
    return degrees * (kPi / 180.0);
}
[[nodiscard]] inline Eigen::Vector3d RadToDeg(const Eigen::Vector3d &radians) {
    return radians * (180.0 / kPi);
}

}  // namespace dorado
