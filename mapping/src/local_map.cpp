#include "dorado/mapping/local_map.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

#include "local_map_impl.hpp"

namespace dorado::mapping {

void LocalMapConfig::Validate() const {
    auto fail = [](const std::string &key, const std::string &what) {
        throw std::invalid_argument("mapper config: map." + key + " " + what);
    };
    if (!std::isfinite(voxel_size_m) || voxel_size_m <= 0.0) fail("voxel_size_m", "must be > 0");
    if (max_points_per_voxel < 1) fail("max_points_per_voxel", "must be >= 1");
    if (!(max_distance_m > 0.0)) fail("max_distance_m", "must be > 0");
}

VoxelKey LocalMap::Impl::KeyOf(const Eigen::Vector3d &p) const {
    const Eigen::Vector3d s = p / config.voxel_size_m;
    return {static_cast<int64_t>(std::floor(s.x())), static_cast<int64_t>(std::floor(s.y())),
            static_cast<int64_t>(std::floor(s.z()))};
}

void LocalMap::Impl::EnsureSearch() {
    if (!dirty) return;
    origin_world = last_position_world.array().round();
    points_world.clear();
    points_world.reserve(point_count);
    cloud->clear();
    cloud->reserve(point_count);
    for (const auto &[key, points] : voxels) {
        for (const auto &p : points) {
            points_world.push_back(p);
            const Eigen::Vector3f local = (p - origin_world).cast<float>();
            cloud->push_back(pcl::PointXYZ(local.x(), local.y(), local.z()));
        }
    }
    if (!cloud->empty()) tree->setInputCloud(cloud);
    covariances.assign(points_world.size(), Eigen::Matrix3d::Identity());
    normals.assign(points_world.size(), Eigen::Vector3d::UnitZ());
    covariance_ready.assign(points_world.size(), 0);
    dirty = false;
}

void LocalMap::Impl::SetCovarianceModel(int neighbours, double flatness) {
    if (neighbours == covariance_neighbours && flatness == plane_flatness) return;
    covariance_neighbours = neighbours;
    plane_flatness = flatness;
    std::fill(covariance_ready.begin(), covariance_ready.end(), 0);
}

const Eigen::Matrix3d &LocalMap::Impl::Covariance(int i) {
    if (covariance_ready[i]) return covariances[i];
    pcl::Indices indices;
    std::vector<float> distances;
    const int k = std::min<int>(covariance_neighbours, static_cast<int>(points_world.size()));
    tree->nearestKSearch((*cloud)[i], k, indices, distances);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto j : indices) mean += points_world[j];
    mean /= static_cast<double>(indices.size());
    Eigen::Matrix3d sample = Eigen::Matrix3d::Zero();
    for (const auto j : indices) {
        const Eigen::Vector3d d = points_world[j] - mean;
        sample += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(sample);
    const Eigen::Matrix3d V = eig.eigenvectors();  // columns sorted by increasing eigenvalue
    covariances[i] = V * Eigen::Vector3d(plane_flatness, 1.0, 1.0).asDiagonal() * V.transpose();
    normals[i] = V.col(0);
    covariance_ready[i] = 1;
    return covariances[i];
}

const Eigen::Vector3d &LocalMap::Impl::Normal(int i) {
    Covariance(i);
    return normals[i];
}

void LocalMap::Impl::ComputeAllCovariances() {
    EnsureSearch();
    for (int i = 0; i < static_cast<int>(points_world.size()); ++i) Covariance(i);
}

LocalMap::LocalMap(const LocalMapConfig &config) : impl_(std::make_unique<Impl>()) {
    config.Validate();
    impl_->config = config;
}
LocalMap::~LocalMap() = default;
LocalMap::LocalMap(LocalMap &&) noexcept = default;
LocalMap &LocalMap::operator=(LocalMap &&) noexcept = default;

void LocalMap::Update(const Eigen::Matrix3Xd &points_world, const Eigen::Vector3d &position_world) {
    Impl &m = *impl_;
    for (Eigen::Index i = 0; i < points_world.cols(); ++i) {
        const Eigen::Vector3d p = points_world.col(i);
        if (!p.allFinite()) continue;
        auto &cell = m.voxels[m.KeyOf(p)];
        if (static_cast<int>(cell.size()) >= m.config.max_points_per_voxel) continue;
        cell.push_back(p);
        ++m.point_count;
    }
    m.last_position_world = position_world;
    m.dirty = true;
    // An unbounded map (the whole-run output map) is never cropped: the crop walks every voxel.
    if (!std::isfinite(m.config.max_distance_m)) return;
    // Crop: a voxel is kept while its first point is within max_distance_m of the vehicle.
    const double max_d2 = m.config.max_distance_m * m.config.max_distance_m;
    for (auto it = m.voxels.begin(); it != m.voxels.end();) {
        if ((it->second.front() - position_world).squaredNorm() > max_d2) {
            m.point_count -= it->second.size();
            it = m.voxels.erase(it);
        } else {
            ++it;
        }
    }
}

Eigen::Matrix3Xd LocalMap::Points() const {
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(impl_->point_count));
    Eigen::Index c = 0;
    for (const auto &[key, points] : impl_->voxels)
        for (const auto &p : points) out.col(c++) = p;
    return out;
}

void LocalMap::BuildIndex() const {
    impl_->EnsureSearch();
}

std::size_t LocalMap::size() const {
    return impl_->point_count;
}
const LocalMapConfig &LocalMap::config() const {
    return impl_->config;
}

LocalMap::Neighbour LocalMap::Nearest(const Eigen::Vector3d &query_world) const {
    Impl &m = *impl_;
    m.EnsureSearch();
    if (m.cloud->empty()) return {};
    const Eigen::Vector3f q = (query_world - m.origin_world).cast<float>();
    pcl::Indices indices(1);
    std::vector<float> d2(1);
    m.tree->nearestKSearch(pcl::PointXYZ(q.x(), q.y(), q.z()), 1, indices, d2);
    return {indices[0], (m.points_world[indices[0]] - query_world).squaredNorm()};
}

}  // namespace dorado::mapping
