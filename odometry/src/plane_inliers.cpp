// The ground RANSAC's inlier count over structure-of-arrays candidates (plane_inliers.hpp):
// 4-wide branch-free vectors (an AVX2 clone and an SSE2 default, simd4.hpp) with the scalar
// PlaneDistance's operations in its order, so that every point is counted as the scalar loop
// would count it.
#include "plane_inliers.hpp"

#include <limits>

#include "simd4.hpp"

namespace dorado::odometry::internal {

using simd::Broadcast;
using simd::Load;
using simd::Mask4;
using simd::Sum;
using simd::Vec4;
static_assert(PlanePoints::kLanes == simd::kLanes, "one vector per group of points");

void PlanePoints::Pad() {
    while (x.size() % kLanes != 0) {
        x.push_back(0.0);
        y.push_back(0.0);
        z.push_back(std::numeric_limits<double>::infinity());  // infinitely far from any plane
    }
}

namespace {

DORADO_SIMD_CLONES int CountInVectors(std::size_t n, const double *x, const double *y,
                                      const double *z, double h, double a, double b, double norm,
                                      double threshold) {
    const Vec4 vh = Broadcast(h), va = Broadcast(a), vb = Broadcast(b), vn = Broadcast(norm);
    const Vec4 upper = Broadcast(threshold), lower = Broadcast(-threshold);
    Mask4 count = {0, 0, 0, 0};
    for (std::size_t i = 0; i < n; i += simd::kLanes) {
        const Vec4 d = (Load(z + i) - ((vh + va * Load(x + i)) + vb * Load(y + i))) / vn;
        count -= (d < upper) & (d > lower);  // |d| < threshold; true is -1
    }
    return static_cast<int>(Sum(count));
}

}  // namespace

int CountPlaneInliers(const PlanePoints &points, const Eigen::Vector3d &theta, double threshold) {
    return CountInVectors(points.x.size(), points.x.data(), points.y.data(), points.z.data(),
                          theta[0], theta[1], theta[2], PlaneNormalNorm(theta), threshold);
}

}  // namespace dorado::odometry::internal
