#include "dorado/mapping/movers.hpp"

#include <cmath>

#include "dorado/core/require.hpp"

namespace dorado::mapping {

void MoverConfig::Validate() const {
    Require(std::isfinite(neighbour_radius_m) && neighbour_radius_m >= 0.0 &&
                neighbour_radius_m <= 10.0,
            "mapper.movers.neighbour_radius_m", "must be in [0, 10]");
    Require(std::isfinite(memory_s) && memory_s >= 0.0 && memory_s <= 600.0,
            "mapper.movers.memory_s", "must be in [0, 600]");
    Require(std::isfinite(min_radial_speed_mps) && min_radial_speed_mps >= 0.0,
            "mapper.movers.min_radial_speed_mps", "must be >= 0");
    Require(min_cluster_points >= 1 && min_cluster_points <= 100,
            "mapper.movers.min_cluster_points", "must be in [1, 100]");
}

Eigen::Matrix3Xd Clustered(const Eigen::Matrix3Xd &moving, double radius_m, int min_points) {
    if (!(radius_m > 0.0) || min_points <= 1) return moving;
    const double r2 = radius_m * radius_m;
    Eigen::Matrix3Xd out(3, moving.cols());
    Eigen::Index n = 0;
    for (Eigen::Index i = 0; i < moving.cols(); ++i)
        if (((moving.colwise() - moving.col(i)).colwise().squaredNorm().array() <= r2).count() >=
            min_points)
            out.col(n++) = moving.col(i);
    out.conservativeResize(3, n);
    return out;
}

std::vector<bool> NearAny(const Eigen::Matrix3Xd &points, const Eigen::Matrix3Xd &moving,
                          double radius_m) {
    std::vector<bool> near(static_cast<std::size_t>(points.cols()), false);
    if (!(radius_m > 0.0) || moving.cols() == 0) return near;
    const double r2 = radius_m * radius_m;
    for (Eigen::Index i = 0; i < points.cols(); ++i)
        near[static_cast<std::size_t>(i)] =
            ((moving.colwise() - points.col(i)).colwise().squaredNorm().array() <= r2).any();
    return near;
}

MoverMemory::MoverMemory(const MoverConfig &config, double cell_m)
    : config_(config), cell_m_(cell_m) {
    config_.Validate();
}

std::vector<VoxelKey> MoverMemory::Observe(const Eigen::Matrix3Xd &moving_world, double time_s) {
    std::vector<VoxelKey> marked;
    if (!(config_.memory_s > 0.0)) return marked;
    for (auto it = last_seen_s_.begin(); it != last_seen_s_.end();)
        it = time_s - it->second > config_.memory_s ? last_seen_s_.erase(it) : std::next(it);
    marked.reserve(static_cast<std::size_t>(moving_world.cols()));
    for (Eigen::Index i = 0; i < moving_world.cols(); ++i) {
        if (!moving_world.col(i).allFinite()) continue;
        const VoxelKey key = VoxelKeyOf(moving_world.col(i), cell_m_);
        last_seen_s_[key] = time_s;
        marked.push_back(key);
    }
    return marked;
}

bool MoverMemory::Moving(const Eigen::Vector3d &p_world) const {
    return !last_seen_s_.empty() && last_seen_s_.count(VoxelKeyOf(p_world, cell_m_)) > 0;
}

std::size_t MoverMemory::size() const {
    return last_seen_s_.size();
}

}  // namespace dorado::mapping
