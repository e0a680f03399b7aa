#pragma once
// Internal to dorado_odometry: the ground fit's candidate points as structure-of-arrays and the
// RANSAC count of the points near a plane z = h + a x + b y (ground_plane.cpp).

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

namespace dorado::odometry::internal {

/// The ground candidates (base frame) as contiguous columns, padded to whole vectors of kLanes
/// with points that no plane holds (z = +inf). Refilled per scan into the same buffers.
struct PlanePoints {
    static constexpr std::size_t kLanes = 4;
    std::vector<double> x, y, z;
    std::size_t size = 0;  ///< real points; the columns hold size rounded up to kLanes

    /// Room for n points and their padding.
    void Reserve(std::size_t n) {
        x.reserve(n + kLanes), y.reserve(n + kLanes), z.reserve(n + kLanes);
    }
    void Add(double px, double py, double pz) {
        x.push_back(px), y.push_back(py), z.push_back(pz), ++size;
    }
    /// Pads the columns to whole vectors; call once after the last Add.
    void Pad();
};

/// The distance of (x, y, z) to the plane theta = [h, a, b] along its normal, rounded as
/// (z - ((h + a x) + b y)) / sqrt(1 + (a^2 + b^2)) with `norm` = that square root.
[[nodiscard]] inline double PlaneDistance(const Eigen::Vector3d &theta, double norm, double x,
                                          double y, double z) {
    return (z - ((theta[0] + theta[1] * x) + theta[2] * y)) / norm;
}

/// sqrt(1 + a^2 + b^2) of the plane theta = [h, a, b], rounded as PlaneDistance expects.
[[nodiscard]] inline double PlaneNormalNorm(const Eigen::Vector3d &theta) {
    return std::sqrt(1.0 + (theta[1] * theta[1] + theta[2] * theta[2]));
}

/// The number of points with |PlaneDistance| < threshold: the same count, point for point, as a
/// scalar loop over PlaneDistance (4-wide, no FMA, the same roundings).
[[nodiscard]] int CountPlaneInliers(const PlanePoints &points, const Eigen::Vector3d &theta,
                                    double threshold);

}  // namespace dorado::odometry::internal
