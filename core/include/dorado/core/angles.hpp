#pragma once
/// @file angles.hpp
/// Degrees and radians: configs and reports speak degrees, the estimators radians.

namespace dorado {

inline constexpr double kPi = 3.14159265358979323846;

[[nodiscard]] constexpr double DegToRad(double degrees) {
    return degrees * (kPi / 180.0);
}
[[nodiscard]] constexpr double RadToDeg(double radians) {
    return radians * (180.0 / kPi);
}

}  // namespace dorado
