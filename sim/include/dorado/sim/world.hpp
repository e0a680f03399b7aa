#pragma once
/// @file world.hpp
/// The static world a radar sees: point reflectors (tree trunks and canopies, poles, rocks,
/// bushes, walls, building facades, parked cars) with a radar cross-section, and the opaque boxes
/// that hide what is behind them. Both are binned in a 2D grid so a scan only looks at the cells
/// within its range.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dorado/sim/sequence_config.hpp"
#include "dorado/sim/terrain.hpp"

namespace dorado::sim {

/// A point reflector. A zero normal means it reflects the same in every direction; otherwise its
/// cross-section falls with the incidence angle on the surface it belongs to.
struct Reflector {
    Eigen::Vector3f position_world;
    Eigen::Vector3f normal_world;
    float rcs_dbsm;
};

/// An opaque box (rotated about Z) that blocks the line of sight.
struct Occluder {
    Eigen::Vector3d center_world;
    Eigen::Vector3d half_extent_m;
    double yaw_rad = 0.0;
    /// The 8 corners in the world frame.
    [[nodiscard]] std::array<Eigen::Vector3d, 8> Corners() const;
};

/// Items binned in square cells of the XY plane (compressed rows: cell -> item indices).
class CellGrid {
  public:
    CellGrid() = default;
    CellGrid(const Eigen::Vector2d &origin, double cell_m, int nx, int ny);
    void Build(const std::vector<Eigen::Vector2d> &item_xy);
    /// Calls visit(index) for every item in the cells that touch the disc (center, radius).
    template <typename Visit>
    void ForEachNear(const Eigen::Vector2d &center, double radius, Visit &&visit) const {
        const int x0 = std::max(0, CellX(center.x() - radius));
        const int x1 = std::min(nx_ - 1, CellX(center.x() + radius));
        const int y0 = std::max(0, CellY(center.y() - radius));
        const int y1 = std::min(ny_ - 1, CellY(center.y() + radius));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                const auto c = static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_) +
                               static_cast<std::size_t>(x);
                for (uint32_t k = offsets_[c]; k < offsets_[c + 1]; ++k) visit(items_[k]);
            }
        }
    }
    [[nodiscard]] int CellX(double x) const {
        return static_cast<int>(std::floor((x - origin_.x()) / cell_m_));
    }
    [[nodiscard]] int CellY(double y) const {
        return static_cast<int>(std::floor((y - origin_.y()) / cell_m_));
    }

  private:
    Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
    double cell_m_ = 1.0;
    int nx_ = 0, ny_ = 0;
    std::vector<uint32_t> offsets_{0};
    std::vector<uint32_t> items_;
};

class StaticWorld {
  public:
    /// Places structure at the configured densities in a corridor around the route (seeded).
    StaticWorld(const WorldConfig &config, const Terrain &terrain,
                const std::vector<Eigen::Vector2d> &route_xy, uint64_t seed);

    [[nodiscard]] const std::vector<Reflector> &reflectors() const { return reflectors_; }
    [[nodiscard]] const std::vector<Occluder> &occluders() const { return occluders_; }
    [[nodiscard]] const CellGrid &reflector_grid() const { return reflector_grid_; }
    [[nodiscard]] const CellGrid &occluder_grid() const { return occluder_grid_; }
    /// Largest half diagonal of an occluder (to widen grid queries) [m].
    [[nodiscard]] double max_occluder_radius_m() const { return max_occluder_radius_m_; }

  private:
    std::vector<Reflector> reflectors_;
    std::vector<Occluder> occluders_;
    CellGrid reflector_grid_;
    CellGrid occluder_grid_;
    double max_occluder_radius_m_ = 0.0;
};

}  // namespace dorado::sim
