#include "dorado/mapping/voxel_cloud.hpp"

#include <tsl/robin_set.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "dorado/mapping/voxel_key.hpp"

namespace dorado::mapping {

struct VoxelCloud::Impl {
    double voxel_m = 0.3;
    bool has_origin = false;
    Eigen::Vector3d origin_world = Eigen::Vector3d::Zero();  ///< the first point kept
    tsl::robin_set<VoxelKey, VoxelKeyHash> occupied;
    std::vector<Eigen::Vector3f> offsets;  ///< point - origin_world
};

VoxelCloud::VoxelCloud(double voxel_m) : impl_(std::make_unique<Impl>()) {
    if (!(voxel_m > 0.0) || !std::isfinite(voxel_m))
        throw std::invalid_argument("VoxelCloud: voxel size must be > 0 (got " +
                                    std::to_string(voxel_m) + ")");
    impl_->voxel_m = voxel_m;
}
VoxelCloud::~VoxelCloud() = default;
VoxelCloud::VoxelCloud(VoxelCloud &&) noexcept = default;
VoxelCloud &VoxelCloud::operator=(VoxelCloud &&) noexcept = default;

void VoxelCloud::Add(const Eigen::Matrix3Xd &points_world) {
    Impl &m = *impl_;
    for (Eigen::Index i = 0; i < points_world.cols(); ++i) {
        const Eigen::Vector3d p = points_world.col(i);
        if (!p.allFinite()) continue;
        if (!m.occupied.insert(VoxelKeyOf(p, m.voxel_m)).second) continue;
        if (!m.has_origin) {
            m.origin_world = p;
            m.has_origin = true;
        }
        m.offsets.push_back((p - m.origin_world).cast<float>());
    }
}

std::size_t VoxelCloud::size() const {
    return impl_->offsets.size();
}

Eigen::Matrix3Xd VoxelCloud::Points() const {
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(impl_->offsets.size()));
    for (std::size_t i = 0; i < impl_->offsets.size(); ++i)
        out.col(static_cast<Eigen::Index>(i)) =
            impl_->offsets[i].cast<double>() + impl_->origin_world;
    return out;
}

}  // namespace dorado::mapping
