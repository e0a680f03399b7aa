#include "dorado/mapping/local_map.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "dorado/core/require.hpp"
#include "local_map_impl.hpp"

namespace dorado::mapping {

namespace {

// Distance from a query at fraction f in [0, 1) of its voxel (along one axis) to the voxel d steps
// away, in voxel units.
double Gap(int32_t d, double f) {
    if (d == 0) return 0.0;
    return d > 0 ? static_cast<double>(d) - f : static_cast<double>(-d) - 1.0 + f;
}

// 0, -1, 1, -2, 2, ...: the query's own voxel first, so the best distance prunes early.
int32_t Offset(int32_t n) {
    return (n % 2 == 1) ? -(n + 1) / 2 : n / 2;
}

}  // namespace

void LocalMapConfig::Validate() const {
    Require(std::isfinite(voxel_size_m) && voxel_size_m > 0.0, "mapper.map.voxel_size_m",
            "must be > 0");
    Require(max_points_per_voxel >= 1 && max_points_per_voxel <= 1000,
            "mapper.map.max_points_per_voxel", "must be in [1, 1000]");
    Require(max_distance_m > 0.0, "mapper.map.max_distance_m", "must be > 0");
}

VoxelKey LocalMap::Impl::KeyOf(const Eigen::Vector3d &p) const {
    return VoxelKeyOf(p, config.voxel_size_m);
}

bool LocalMap::Impl::Insert(const Eigen::Vector3d &p) {
    const int32_t capacity = config.max_points_per_voxel;
    const VoxelKey key = KeyOf(p);
    auto [it, created] = voxels.try_emplace(key);
    Voxel &voxel = it.value();
    if (created) {
        if (!free_blocks.empty()) {
            voxel.first = free_blocks.back();
            free_blocks.pop_back();
        } else {
            voxel.first = static_cast<int32_t>(points_world.size());
            const std::size_t size = points_world.size() + static_cast<std::size_t>(capacity);
            points_world.resize(size, Eigen::Vector3d::Zero());
            if (shapes_used) ResizeShapes();
        }
    }
    if (voxel.count >= capacity) return false;
    const int32_t slot = voxel.first + voxel.count++;
    points_world[slot] = p;
    ++point_count;
    if (shapes_used) {
        fitted_at[slot] = 0;
        MarkChanged(key);
    }
    return true;
}

void LocalMap::Impl::UseShapes() {
    if (shapes_used) return;
    shapes_used = true;
    ResizeShapes();
}

void LocalMap::Impl::ResizeShapes() {
    covariances.resize(points_world.size(), Eigen::Matrix3d::Identity());
    normals.resize(points_world.size(), Eigen::Vector3d::Zero());
    fitted_at.resize(points_world.size(), 0);
    fitted_rings.resize(points_world.size(), 0);
}

namespace {

int32_t FloorDiv(int32_t a, int32_t b) {
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

VoxelKey BlockOf(const VoxelKey &voxel) {
    return {FloorDiv(voxel.x, kBlockVoxels), FloorDiv(voxel.y, kBlockVoxels),
            FloorDiv(voxel.z, kBlockVoxels)};
}

}  // namespace

int LocalMap::Impl::MaxShapeRings() const {
    return static_cast<int>(
        std::min<double>(kMaxShapeRings, std::ceil(kShapeReachM / config.voxel_size_m)));
}

void LocalMap::Impl::MarkChanged(const VoxelKey &key) {
    blocks[BlockOf(key)] = update_stamp;
}

bool LocalMap::Impl::ShapeIsCurrent(int32_t i) const {
    const uint32_t fitted = fitted_at[i];
    if (fitted == 0) return false;
    const VoxelKey key = KeyOf(points_world[i]);
    const int32_t r = fitted_rings[i];
    const VoxelKey lo = BlockOf({key.x - r, key.y - r, key.z - r});
    const VoxelKey hi = BlockOf({key.x + r, key.y + r, key.z + r});
    for (int32_t bx = lo.x; bx <= hi.x; ++bx)
        for (int32_t by = lo.y; by <= hi.y; ++by)
            for (int32_t bz = lo.z; bz <= hi.z; ++bz) {
                const auto it = blocks.find({bx, by, bz});
                if (it != blocks.end() && it->second > fitted) return false;
            }
    return true;
}

void LocalMap::Impl::Crop(const Eigen::Vector3d &position_world) {
    const double max_d2 = config.max_distance_m * config.max_distance_m;
    for (auto it = voxels.begin(); it != voxels.end();) {
        if ((points_world[it->second.first] - position_world).squaredNorm() > max_d2) {
            point_count -= static_cast<std::size_t>(it->second.count);
            free_blocks.push_back(it->second.first);
            if (shapes_used) MarkChanged(it->first);
            it = voxels.erase(it);
        } else {
            ++it;
        }
    }
    // Change stamps of blocks that no kept point's neighbourhood can reach are no longer needed
    // (a kept voxel's first point is inside the radius, its other points a voxel diagonal out).
    const double block_m = kBlockVoxels * config.voxel_size_m;
    const double reach = config.max_distance_m +
                         std::sqrt(3.0) * (block_m + (MaxShapeRings() + 1) * config.voxel_size_m);
    for (auto it = blocks.begin(); it != blocks.end();) {
        const Eigen::Vector3d centre =
            (Eigen::Vector3d(static_cast<double>(it->first.x), static_cast<double>(it->first.y),
                             static_cast<double>(it->first.z)) +
             Eigen::Vector3d::Constant(0.5)) *
            block_m;
        it = (centre - position_world).norm() > reach ? blocks.erase(it) : std::next(it);
    }
}

LocalMap::Neighbour LocalMap::Impl::Nearest(const Eigen::Vector3d &query_world,
                                            double max_distance_m) const {
    Neighbour best;
    if (!(max_distance_m > 0.0) || !std::isfinite(max_distance_m)) return best;
    const double v = config.voxel_size_m;
    const Eigen::Vector3d s = query_world / v;
    const VoxelKey key{VoxelIndex(s.x()), VoxelIndex(s.y()), VoxelIndex(s.z())};
    const Eigen::Vector3d f = s - Eigen::Vector3d(key.x, key.y, key.z);
    // A voxel is visited only when its box is closer than the best point so far (squared
    // distances in metres), so the answer is exact within max_distance_m.
    const double reach = std::min(max_distance_m / v, static_cast<double>(kMaxSearchRings));
    double best_d2 = reach * reach * v * v;
    const auto rings = static_cast<int32_t>(std::ceil(reach));
    for (int32_t nx = 0; nx <= 2 * rings; ++nx) {
        const int32_t dx = Offset(nx);
        const double gx = Gap(dx, f.x()) * v;
        const double gx2 = gx * gx;
        if (gx2 >= best_d2) continue;
        for (int32_t ny = 0; ny <= 2 * rings; ++ny) {
            const int32_t dy = Offset(ny);
            const double gy = Gap(dy, f.y()) * v;
            const double gxy2 = gx2 + gy * gy;
            if (gxy2 >= best_d2) continue;
            for (int32_t nz = 0; nz <= 2 * rings; ++nz) {
                const int32_t dz = Offset(nz);
                const double gz = Gap(dz, f.z()) * v;
                if (gxy2 + gz * gz >= best_d2) continue;
                const auto it = voxels.find({key.x + dx, key.y + dy, key.z + dz});
                if (it == voxels.end()) continue;
                const Voxel &voxel = it->second;
                for (int32_t slot = voxel.first; slot < voxel.first + voxel.count; ++slot) {
                    const double d2 = (points_world[slot] - query_world).squaredNorm();
                    if (d2 < best_d2) {
                        best_d2 = d2;
                        best.index = slot;
                    }
                }
            }
        }
    }
    if (best.index >= 0) best.distance_squared = best_d2;
    return best;
}

int LocalMap::Impl::NearestInNeighbourhood(int32_t i, int k) const {
    const Eigen::Vector3d &p = points_world[i];
    const VoxelKey key = KeyOf(p);
    const auto wanted = static_cast<std::size_t>(k);
    scratch.clear();
    const int max_rings = MaxShapeRings();
    int rings = 0;
    for (;; ++rings) {
        // The shell of voxels exactly `rings` away (Chebyshev) from p's, in the order of the full
        // cube's loops: inside the cube's x and y faces only its two z faces are on the shell.
        for (int32_t dx = -rings; dx <= rings; ++dx)
            for (int32_t dy = -rings; dy <= rings; ++dy) {
                const bool side = std::abs(dx) == rings || std::abs(dy) == rings;
                const int32_t step = side || rings == 0 ? 1 : 2 * rings;
                for (int32_t dz = -rings; dz <= rings; dz += step) {
                    const auto it = voxels.find({key.x + dx, key.y + dy, key.z + dz});
                    if (it == voxels.end()) continue;
                    const Voxel &v = it->second;
                    for (int32_t s = v.first; s < v.first + v.count; ++s)
                        scratch.emplace_back((points_world[s] - p).squaredNorm(), s);
                }
            }
        if (rings >= max_rings) break;
        if (scratch.size() < wanted) continue;
        // Every point closer than `rings` voxels has been seen: done when the k-th is that close.
        std::nth_element(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(k - 1),
                         scratch.end());
        const double reach = rings * config.voxel_size_m;
        if (scratch[wanted - 1].first <= reach * reach) break;
    }
    const std::size_t keep = std::min(scratch.size(), wanted);
    std::nth_element(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(keep),
                     scratch.end());
    scratch.resize(keep);
    return rings;
}

void LocalMap::Impl::EnsureCloud() {
    if (!cloud_dirty) return;
    origin_world = last_position_world.array().round();
    cloud->resize(points_world.size());
    for (std::size_t s = 0; s < points_world.size(); ++s) {
        const Eigen::Vector3f local = (points_world[s] - origin_world).cast<float>();
        (*cloud)[s] = pcl::PointXYZ(local.x(), local.y(), local.z());
    }
    cloud_dirty = false;
}

void LocalMap::Impl::SetCovarianceModel(int neighbours, double flatness) {
    if (neighbours == covariance_neighbours && flatness == plane_flatness) return;
    covariance_neighbours = neighbours;
    plane_flatness = flatness;
    std::fill(fitted_at.begin(), fitted_at.end(), 0);
}

const Eigen::Matrix3d &LocalMap::Impl::Covariance(int32_t i) {
    UseShapes();
    if (ShapeIsCurrent(i)) return covariances[i];
    fitted_rings[i] = static_cast<uint8_t>(NearestInNeighbourhood(i, covariance_neighbours));
    fitted_at[i] = std::max<uint32_t>(update_stamp, 1);
    if (scratch.size() < 3) {  // no surface around it: round, and no direction to observe
        covariances[i] = Eigen::Matrix3d::Identity();
        normals[i] = Eigen::Vector3d::Zero();
        return covariances[i];
    }
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto &[d2, j] : scratch) mean += points_world[j];
    mean /= static_cast<double>(scratch.size());
    Eigen::Matrix3d sample = Eigen::Matrix3d::Zero();
    for (const auto &[d2, j] : scratch) {
        const Eigen::Vector3d d = points_world[j] - mean;
        sample += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(sample);
    const Eigen::Matrix3d V = eig.eigenvectors();  // columns sorted by increasing eigenvalue
    covariances[i] = V * Eigen::Vector3d(plane_flatness, 1.0, 1.0).asDiagonal() * V.transpose();
    normals[i] = V.col(0);
    return covariances[i];
}

const Eigen::Vector3d &LocalMap::Impl::Normal(int32_t i) {
    Covariance(i);
    return normals[i];
}

void LocalMap::Impl::ComputeAllCovariances() {
    UseShapes();
    ForEachSlot([this](int32_t s) { Covariance(s); });
}

LocalMap::LocalMap(const LocalMapConfig &config) : impl_(std::make_unique<Impl>()) {
    config.Validate();
    impl_->config = config;
}
LocalMap::~LocalMap() = default;
LocalMap::LocalMap(LocalMap &&) noexcept = default;
LocalMap &LocalMap::operator=(LocalMap &&) noexcept = default;

Eigen::Matrix3Xd LocalMap::Update(const Eigen::Matrix3Xd &points_world,
                                  const Eigen::Vector3d &position_world) {
    Impl &m = *impl_;
    ++m.update_stamp;
    Eigen::Matrix3Xd added(3, points_world.cols());
    Eigen::Index n = 0;
    for (Eigen::Index i = 0; i < points_world.cols(); ++i) {
        const Eigen::Vector3d p = points_world.col(i);
        if (p.allFinite() && m.Insert(p)) added.col(n++) = p;
    }
    m.last_position_world = position_world;
    m.cloud_dirty = true;
    // An unbounded map (max_distance_m infinite) is never cropped: the crop walks every voxel.
    if (std::isfinite(m.config.max_distance_m)) m.Crop(position_world);
    // A voxel is kept or dropped whole: an added point is in the map iff its voxel still is.
    Eigen::Index kept = 0;
    for (Eigen::Index i = 0; i < n; ++i)
        if (m.voxels.find(m.KeyOf(added.col(i))) != m.voxels.end())
            added.col(kept++) = added.col(i);
    added.conservativeResize(3, kept);
    return added;
}

std::size_t LocalMap::Remove(const std::vector<VoxelKey> &keys) {
    Impl &m = *impl_;
    std::size_t dropped = 0;
    for (const VoxelKey &key : keys) {
        const auto it = m.voxels.find(key);
        if (it == m.voxels.end()) continue;
        dropped += static_cast<std::size_t>(it->second.count);
        m.point_count -= static_cast<std::size_t>(it->second.count);
        m.free_blocks.push_back(it->second.first);
        m.voxels.erase(it);
        if (m.shapes_used) {
            ++m.update_stamp;  // the shapes that reached this voxel are stale
            m.MarkChanged(key);
        }
    }
    if (dropped > 0) m.cloud_dirty = true;
    return dropped;
}

Eigen::Matrix3Xd LocalMap::Points() const {
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(impl_->point_count));
    Eigen::Index c = 0;
    impl_->ForEachSlot([&](int32_t s) { out.col(c++) = impl_->points_world[s]; });
    return out;
}

void LocalMap::BuildIndex() const {
    impl_->EnsureCloud();
}

std::size_t LocalMap::size() const {
    return impl_->point_count;
}
std::size_t LocalMap::voxel_count() const {
    return impl_->voxels.size();
}
std::size_t LocalMap::capacity() const {
    return impl_->points_world.size();
}
const LocalMapConfig &LocalMap::config() const {
    return impl_->config;
}

LocalMap::Neighbour LocalMap::Nearest(const Eigen::Vector3d &query_world,
                                      double max_distance_m) const {
    return impl_->Nearest(query_world, max_distance_m);
}

}  // namespace dorado::mapping
