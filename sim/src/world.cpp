#include "dorado/sim/world.hpp"

#include <random>

namespace dorado::sim {

namespace {

using Rng = std::mt19937_64;

double Uniform(Rng &rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

/// Appends reflectors and occluders for one object; every builder stands the object on the ground.
class Builder {
  public:
    Builder(const Terrain &terrain, Rng &rng, std::vector<Reflector> &reflectors,
            std::vector<Occluder> &occluders)
        : terrain_(terrain), rng_(rng), reflectors_(reflectors), occluders_(occluders) {}

    void Reflect(const Eigen::Vector3d &p, double rcs_dbsm,
                 const Eigen::Vector3d &normal = Eigen::Vector3d::Zero()) {
        reflectors_.push_back(
            {p.cast<float>(), normal.cast<float>(), static_cast<float>(rcs_dbsm)});
    }
    void Block(const Eigen::Vector3d &center, const Eigen::Vector3d &half, double yaw) {
        occluders_.push_back({center, half, yaw});
    }
    /// A uniform random point in [-1, 1]^3.
    Eigen::Vector3d Cube() {
        return {Uniform(rng_, -1, 1), Uniform(rng_, -1, 1), Uniform(rng_, -1, 1)};
    }
    double Ground(const Eigen::Vector2d &xy) const { return terrain_.SmoothHeight(xy.x(), xy.y()); }

    void Tree(const Eigen::Vector2d &xy) {
        const double z0 = Ground(xy);
        const double radius = Uniform(rng_, 0.08, 0.35);
        const double height = Uniform(rng_, 4.0, 14.0);
        const double trunk_top = std::min(3.0, 0.45 * height);
        const int n_trunk = 3 + static_cast<int>(radius * 15.0);
        for (int i = 0; i < n_trunk; ++i) {
            const double a = Uniform(rng_, 0.0, 2 * M_PI);
            Reflect({xy.x() + radius * std::cos(a), xy.y() + radius * std::sin(a),
                     z0 + Uniform(rng_, 0.2, trunk_top)},
                    Uniform(rng_, -3.0, 7.0) + 10.0 * std::log10(radius / 0.2));
        }
        const int n_canopy = 8 + static_cast<int>(2.0 * height);
        const double canopy_radius = 0.25 * height;
        for (int i = 0; i < n_canopy; ++i) {
            const Eigen::Vector3d u = Cube();
            if (u.squaredNorm() > 1.0) continue;
            Reflect({xy.x() + canopy_radius * u.x(), xy.y() + canopy_radius * u.y(),
                     z0 + 0.65 * height + 0.3 * height * u.z()},
                    Uniform(rng_, -18.0, -6.0));
        }
        Block({xy.x(), xy.y(), z0 + 0.25 * height}, {radius, radius, 0.25 * height}, 0.0);
    }

    void Pole(const Eigen::Vector2d &xy) {
        const double z0 = Ground(xy);
        const double height = Uniform(rng_, 4.0, 9.0);
        for (const double h : {0.3, 1.0, 2.0, 0.9 * height}) {
            Reflect({xy.x(), xy.y(), z0 + h}, Uniform(rng_, 2.0, 10.0));
        }
        Block({xy.x(), xy.y(), z0 + 0.5 * height}, {0.1, 0.1, 0.5 * height}, 0.0);
    }

    void Rock(const Eigen::Vector2d &xy) {
        const double z0 = Ground(xy);
        const double radius = Uniform(rng_, 0.3, 1.0);
        const int n = 3 + static_cast<int>(radius * 4.0);
        for (int i = 0; i < n; ++i) {
            const double a = Uniform(rng_, 0.0, 2 * M_PI);
            const double e = Uniform(rng_, 0.0, 1.2);
            Reflect({xy.x() + radius * std::cos(a) * std::cos(e),
                     xy.y() + radius * std::sin(a) * std::cos(e), z0 + 0.6 * radius * std::sin(e)},
                    Uniform(rng_, -5.0, 7.0));
        }
        Block({xy.x(), xy.y(), z0 + 0.3 * radius}, {0.8 * radius, 0.8 * radius, 0.3 * radius}, 0.0);
    }

    void Bush(const Eigen::Vector2d &xy) {
        const double z0 = Ground(xy);
        const double radius = Uniform(rng_, 0.5, 1.5);
        const double height = Uniform(rng_, 0.5, 1.8);
        const int n = 5 + static_cast<int>(radius * 8.0);
        for (int i = 0; i < n; ++i) {
            const Eigen::Vector3d u = Cube();
            Reflect({xy.x() + radius * u.x(), xy.y() + radius * u.y(),
                     z0 + 0.5 * height * (1.0 + u.z())},
                    Uniform(rng_, -20.0, -8.0));
        }
    }

    /// A vertical plane from a to b (ground-level XY), reflectors every ~spacing, with strong
    /// edges; occluded in 3 m pieces so that the angular boxes stay tight.
    void Facade(const Eigen::Vector2d &a, const Eigen::Vector2d &b, double z0, double height,
                double spacing) {
        const Eigen::Vector2d along = b - a;
        const double length = along.norm();
        const Eigen::Vector2d dir = along / length;
        const Eigen::Vector3d normal(-dir.y(), dir.x(), 0.0);
        const int nu = std::max(1, static_cast<int>(length / spacing));
        const int nv = std::max(1, static_cast<int>(height / spacing));
        for (int i = 0; i <= nu; ++i) {
            for (int j = 0; j <= nv; ++j) {
                const double u = std::clamp((i + Uniform(rng_, -0.4, 0.4)) / nu, 0.0, 1.0);
                const double v = std::clamp((j + Uniform(rng_, -0.4, 0.4)) / nv, 0.0, 1.0);
                const Eigen::Vector2d xy = a + u * along;
                const bool edge = i == 0 || i == nu;
                Reflect({xy.x(), xy.y(), z0 + v * height},
                        edge ? Uniform(rng_, 6.0, 14.0) : Uniform(rng_, -12.0, -2.0),
                        edge ? Eigen::Vector3d::Zero() : normal);
            }
        }
        const int pieces = std::max(1, static_cast<int>(std::ceil(length / 3.0)));
        const double yaw = std::atan2(dir.y(), dir.x());
        for (int k = 0; k < pieces; ++k) {
            const Eigen::Vector2d c = a + (k + 0.5) / pieces * along;
            Block({c.x(), c.y(), z0 + 0.5 * height}, {0.5 * length / pieces, 0.12, 0.5 * height},
                  yaw);
        }
    }

    void Wall(const Eigen::Vector2d &xy) {
        const double length = Uniform(rng_, 5.0, 30.0);
        const double yaw = Uniform(rng_, 0.0, M_PI);
        const Eigen::Vector2d half = 0.5 * length * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
        const double z0 = std::min(Ground(xy - half), Ground(xy + half));
        Facade(xy - half, xy + half, z0, Uniform(rng_, 1.0, 3.0), 0.5);
    }

    void Building(const Eigen::Vector2d &xy) {
        const double w = Uniform(rng_, 8.0, 25.0), d = Uniform(rng_, 8.0, 25.0);
        const double height = Uniform(rng_, 4.0, 15.0);
        const double yaw = Uniform(rng_, 0.0, M_PI);
        const Eigen::Rotation2Dd R(yaw);
        std::array<Eigen::Vector2d, 4> corners;
        const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
        double z0 = 1e9;
        for (int i = 0; i < 4; ++i) {
            corners[i] = xy + R * Eigen::Vector2d(0.5 * w * sx[i], 0.5 * d * sy[i]);
            z0 = std::min(z0, Ground(corners[i]));
        }
        for (int i = 0; i < 4; ++i) Facade(corners[i], corners[(i + 1) % 4], z0, height, 0.7);
    }

    /// Weak reflectors in the grass of one cell (they may lie on the route: it is driven over).
    void Vegetation(const Eigen::Vector2d &lo, double size, double per_m2) {
        std::poisson_distribution<int> count(per_m2 * size * size);
        for (int n = count(rng_); n > 0; --n) {
            const Eigen::Vector2d xy =
                lo + size * Eigen::Vector2d(Uniform(rng_, 0, 1), Uniform(rng_, 0, 1));
            Reflect({xy.x(), xy.y(), terrain_.Height(xy.x(), xy.y()) + Uniform(rng_, 0.05, 0.6)},
                    Uniform(rng_, -26.0, -6.0));
        }
    }

    void ParkedCar(const Eigen::Vector2d &xy) {
        const double z0 = Ground(xy);
        const double yaw = Uniform(rng_, 0.0, 2 * M_PI);
        const Eigen::Vector3d half(2.25, 0.9, 0.75);
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        const Eigen::Vector3d center(xy.x(), xy.y(), z0 + half.z());
        for (int i = 0; i < 30; ++i) {
            Eigen::Vector3d u = Cube();
            Eigen::Index axis = 0;
            u.cwiseAbs().maxCoeff(&axis);
            u[axis] = u[axis] > 0 ? 1.0 : -1.0;  // on the surface of the box
            Reflect(center + R * half.cwiseProduct(u), Uniform(rng_, -6.0, 8.0));
        }
        Block(center, half, yaw);
    }

  private:
    const Terrain &terrain_;
    Rng &rng_;
    std::vector<Reflector> &reflectors_;
    std::vector<Occluder> &occluders_;
};

}  // namespace

std::array<Eigen::Vector3d, 8> Occluder::Corners() const {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    std::array<Eigen::Vector3d, 8> corners;
    for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d s((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
        corners[static_cast<std::size_t>(i)] = center_world + R * half_extent_m.cwiseProduct(s);
    }
    return corners;
}

CellGrid::CellGrid(const Eigen::Vector2d &origin, double cell_m, int nx, int ny)
    : origin_(origin), cell_m_(cell_m), nx_(nx), ny_(ny) {}

void CellGrid::Build(const std::vector<Eigen::Vector2d> &item_xy) {
    const auto n_cells = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
    std::vector<uint32_t> cell_of(item_xy.size());
    offsets_.assign(n_cells + 1, 0);
    for (std::size_t i = 0; i < item_xy.size(); ++i) {
        const int x = std::clamp(CellX(item_xy[i].x()), 0, nx_ - 1);
        const int y = std::clamp(CellY(item_xy[i].y()), 0, ny_ - 1);
        cell_of[i] = static_cast<uint32_t>(y * nx_ + x);
        ++offsets_[cell_of[i] + 1];
    }
    for (std::size_t c = 0; c < n_cells; ++c) offsets_[c + 1] += offsets_[c];
    items_.resize(item_xy.size());
    std::vector<uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (std::size_t i = 0; i < item_xy.size(); ++i)
        items_[fill[cell_of[i]]++] = static_cast<uint32_t>(i);
}

StaticWorld::StaticWorld(const WorldConfig &config, const Terrain &terrain,
                         const std::vector<Eigen::Vector2d> &route_xy, uint64_t seed) {
    Rng rng(seed ^ 0x5157a71cull);
    // The route densified to ~1 m, binned, to keep the route itself clear of obstacles.
    std::vector<Eigen::Vector2d> route;
    for (std::size_t i = 0; i + 1 < route_xy.size(); ++i) {
        const int n = 1 + static_cast<int>((route_xy[i + 1] - route_xy[i]).norm());
        for (int k = 0; k < n; ++k)
            route.push_back(route_xy[i] + (route_xy[i + 1] - route_xy[i]) * k / n);
    }
    route.push_back(route_xy.back());
    Eigen::Vector2d lo = route.front(), hi = route.front();
    for (const auto &p : route) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const double margin = config.corridor_half_width_m + 30.0;
    lo.array() -= margin;
    hi.array() += margin;
    constexpr double kCell = 8.0;
    const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / kCell));
    const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / kCell));
    CellGrid route_grid(lo, kCell, nx, ny);
    route_grid.Build(route);

    // Cells within the corridor get structure.
    std::vector<char> in_corridor(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0);
    const int reach = static_cast<int>(std::ceil(config.corridor_half_width_m / kCell));
    for (std::size_t i = 0; i < route.size(); i += 4) {
        const int cx = route_grid.CellX(route[i].x()), cy = route_grid.CellY(route[i].y());
        for (int y = std::max(0, cy - reach); y <= std::min(ny - 1, cy + reach); ++y) {
            for (int x = std::max(0, cx - reach); x <= std::min(nx - 1, cx + reach); ++x) {
                if (std::hypot(x - cx, y - cy) <= reach)
                    in_corridor[static_cast<std::size_t>(y * nx + x)] = 1;
            }
        }
    }
    auto clear_of_route = [&](const Eigen::Vector2d &xy, double radius) {
        bool clear = true;
        const double limit = config.clearance_m + radius;
        route_grid.ForEachNear(xy, limit, [&](uint32_t i) {
            if ((route[i] - xy).norm() < limit) clear = false;
        });
        return clear;
    };

    Builder build(terrain, rng, reflectors_, occluders_);
    struct Kind {
        double per_1000m2;
        double radius_m;
        void (Builder::*make)(const Eigen::Vector2d &);
    };
    const Kind kinds[] = {{config.trees_per_1000m2, 0.5, &Builder::Tree},
                          {config.poles_per_1000m2, 0.2, &Builder::Pole},
                          {config.rocks_per_1000m2, 1.0, &Builder::Rock},
                          {config.bushes_per_1000m2, 1.5, &Builder::Bush},
                          {config.walls_per_1000m2, 15.0, &Builder::Wall},
                          {config.buildings_per_1000m2, 18.0, &Builder::Building},
                          {config.parked_cars_per_1000m2, 2.5, &Builder::ParkedCar}};
    const double cell_area_1000m2 = kCell * kCell / 1000.0;
    for (int y = 0; y < ny; ++y) {
        for (int x = 0; x < nx; ++x) {
            if (!in_corridor[static_cast<std::size_t>(y * nx + x)]) continue;
            build.Vegetation(lo + kCell * Eigen::Vector2d(x, y), kCell, config.vegetation_per_m2);
            for (const auto &kind : kinds) {
                std::poisson_distribution<int> count(kind.per_1000m2 * cell_area_1000m2);
                for (int n = count(rng); n > 0; --n) {
                    const Eigen::Vector2d xy = lo + kCell * Eigen::Vector2d(x + Uniform(rng, 0, 1),
                                                                            y + Uniform(rng, 0, 1));
                    if (clear_of_route(xy, kind.radius_m)) (build.*kind.make)(xy);
                }
            }
        }
    }

    std::vector<Eigen::Vector2d> xy;
    xy.reserve(reflectors_.size());
    for (const auto &r : reflectors_) xy.emplace_back(r.position_world.x(), r.position_world.y());
    reflector_grid_ = CellGrid(lo, kCell, nx, ny);
    reflector_grid_.Build(xy);
    xy.clear();
    for (const auto &o : occluders_) {
        xy.push_back(o.center_world.head<2>());
        max_occluder_radius_m_ = std::max(max_occluder_radius_m_, o.half_extent_m.head<2>().norm());
    }
    occluder_grid_ = CellGrid(lo, kCell, nx, ny);
    occluder_grid_.Build(xy);
}

}  // namespace dorado::sim
