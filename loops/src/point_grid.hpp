#pragma once
// Internal: nearest neighbours in a voxel hash (kiss-icp's way): a query looks in the 27 cells
// around its own, which is exact for every search radius up to the cell's size. Built once per
// registration; no kd-tree library (FLANN's per-query parallel region costs more than the search).
#include <Eigen/Core>
#include <algorithm>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dorado/mapping/voxel_key.hpp"

namespace dorado::loops {

class PointGrid {
  public:
    PointGrid(const std::vector<Eigen::Vector3d> &points, double cell_m)
        : points_(points), cell_m_(cell_m) {
        cells_.reserve(points.size());
        for (std::size_t i = 0; i < points.size(); ++i)
            cells_[mapping::VoxelKeyOf(points[i], cell_m_)].push_back(static_cast<int>(i));
    }

    // The nearest point within max_m (<= the cell size) of q: its index, or -1.
    [[nodiscard]] int Nearest(const Eigen::Vector3d &q, double max_m) const {
        int best = -1;
        double best_d2 = max_m * max_m;
        Visit(q, [&](int i) {
            const double d2 = (points_[i] - q).squaredNorm();
            if (d2 <= best_d2) {
                best_d2 = d2;
                best = i;
            }
        });
        return best;
    }

    // The k nearest points within the cell size of q (fewer when there are not so many).
    [[nodiscard]] std::vector<int> KNearest(const Eigen::Vector3d &q, std::size_t k) const {
        std::vector<std::pair<double, int>> found;
        const double max_d2 = cell_m_ * cell_m_;
        Visit(q, [&](int i) {
            const double d2 = (points_[i] - q).squaredNorm();
            if (d2 <= max_d2) found.emplace_back(d2, i);
        });
        const std::size_t n = std::min(k, found.size());
        std::partial_sort(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(n),
                          found.end());
        std::vector<int> nearest(n);
        for (std::size_t j = 0; j < n; ++j) nearest[j] = found[j].second;
        return nearest;
    }

    [[nodiscard]] const Eigen::Vector3d &point(int i) const { return points_[i]; }

  private:
    template <typename F>
    void Visit(const Eigen::Vector3d &q, F &&f) const {
        const mapping::VoxelKey c = mapping::VoxelKeyOf(q, cell_m_);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto it = cells_.find({c.x + dx, c.y + dy, c.z + dz});
                    if (it == cells_.end()) continue;
                    for (int i : it->second) f(i);
                }
    }

    const std::vector<Eigen::Vector3d> &points_;
    double cell_m_;
    std::unordered_map<mapping::VoxelKey, std::vector<int>, mapping::VoxelKeyHash> cells_;
};

}  // namespace dorado::loops
