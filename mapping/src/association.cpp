// Data association at a given pose: nearest map point, its local distribution, and how well the
// matches constrain the pose.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "local_map_impl.hpp"
#include "registration.hpp"
#include "whitening.hpp"

namespace dorado::mapping {

namespace {

double EigenvalueRatio(const Eigen::Matrix3d &H) {
    const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(H).eigenvalues();
    return lambda(2) > 0.0 ? std::max(0.0, lambda(0)) / lambda(2) : 0.0;
}

}  // namespace

Association Associate(const Eigen::Matrix3Xd &source_base, const Eigen::Isometry3d &T_world_base,
                      const LocalMap &local_map, const MapperConfig &config, double threshold_m,
                      int max_matches) {
    LocalMap::Impl &map = local_map.impl();
    map.SetCovarianceModel(config.covariance_neighbours, config.plane_flatness);
    Association out;
    if (map.point_count == 0 || source_base.cols() == 0) return out;

    // Every source point is tested (the counts and the observability need them all); the residuals
    // handed to Ceres are then thinned evenly.
    std::vector<std::pair<Eigen::Index, int>> found;
    found.reserve(static_cast<std::size_t>(source_base.cols()));
    double sum_sq = 0.0;
    for (Eigen::Index i = 0; i < source_base.cols(); ++i) {
        const Eigen::Vector3d p_world = T_world_base * source_base.col(i);
        const LocalMap::Neighbour nn = map.Nearest(p_world, threshold_m);  // within the threshold
        if (nn.index < 0) continue;
        found.emplace_back(i, nn.index);
        sum_sq += nn.distance_squared;
    }
    if (found.empty()) return out;
    out.count = static_cast<int>(found.size());
    out.rms_m = std::sqrt(sum_sq / static_cast<double>(found.size()));

    // The kept matches: their local shapes (a k-NN fit each, the costly part) whiten the residuals
    // and measure how well the geometry constrains the pose. An even thinning keeps the scan's
    // spatial spread, so the eigenvalue ratio is that of all matches up to sampling.
    const std::size_t keep =
        std::min<std::size_t>(found.size(), static_cast<std::size_t>(max_matches));
    out.matches.reserve(keep);
    const double sigma_sq = config.point_sigma_m * config.point_sigma_m;
    Eigen::Matrix3d H_translation = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d H_rotation = Eigen::Matrix3d::Zero();
    for (std::size_t k = 0; k < keep; ++k) {
        const auto [i, j] = found[k * found.size() / keep];
        const Eigen::Matrix3d C = sigma_sq * map.Covariance(j);
        out.matches.push_back(
            {source_base.col(i), map.points_world[j], InverseCholeskyFactor<3>(C)});
        // Point-to-plane Jacobian w.r.t. a world translation and a rotation about the vehicle:
        // d r / d t = n, d r / d theta = (R p) x n.
        const Eigen::Vector3d &n = map.Normal(j);
        const Eigen::Vector3d lever = (T_world_base.linear() * source_base.col(i)).cross(n);
        H_translation += n * n.transpose();
        H_rotation += lever * lever.transpose();
    }
    out.observability = std::min(EigenvalueRatio(H_translation), EigenvalueRatio(H_rotation));
    return out;
}

}  // namespace dorado::mapping
