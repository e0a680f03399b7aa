#include "reference_path.hpp"

#include <cstdio>
#include <exception>

#include "dorado/io/dataset.hpp"

namespace dorado::apps {

std::vector<Eigen::Vector3d> AlignedReferencePath(const Trajectory &reference,
                                                  const Trajectory &estimate) {
    if (reference.empty() || estimate.empty()) return {};
    // T_estworld_refworld from the first estimate pose the reference covers.
    std::optional<Eigen::Isometry3d> T_estworld_refworld;
    for (const StampedPose &pose : estimate.poses()) {
        if (const auto T_refworld_base = reference.Interpolate(pose.stamp_ns)) {
            T_estworld_refworld = pose.T_world_body * T_refworld_base->inverse();
            break;
        }
    }
    if (!T_estworld_refworld) return {};
    const int64_t first = estimate.poses().front().stamp_ns;
    const int64_t last = estimate.poses().back().stamp_ns;
    std::vector<Eigen::Vector3d> path;
    for (const StampedPose &pose : reference.poses()) {
        if (pose.stamp_ns < first || pose.stamp_ns > last) continue;
        path.push_back(*T_estworld_refworld * pose.T_world_body.translation());
    }
    return path;
}

std::vector<Eigen::Vector3d> ReferencePath(const io::DatasetConfig &dataset,
                                           const Trajectory &estimate) {
    try {
        const std::optional<Trajectory> reference = io::LoadGroundTruth(dataset);
        return reference ? AlignedReferencePath(*reference, estimate)
                         : std::vector<Eigen::Vector3d>{};
    } catch (const std::exception &e) {
        std::fprintf(stderr, "warning: map.png without the reference trajectory: %s\n", e.what());
        return {};
    }
}

}  // namespace dorado::apps
