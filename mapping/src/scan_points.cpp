// The points of a scan the mapper uses (scan_points.hpp).
#include "scan_points.hpp"

#include <cmath>

namespace dorado::mapping {

namespace {

bool InRange(const Eigen::Vector3d &p_radar, const MapperConfig &config) {
    const double range = p_radar.norm();
    return std::isfinite(range) && range >= config.min_range_m && range <= config.max_range_m;
}

}  // namespace

ScanPoints SelectScanPoints(const RadarScan &scan, const MapperInput &input,
                            const Eigen::Isometry3d &T_world_base,
                            const Eigen::Isometry3d &T_base_radar, const MapperConfig &config,
                            MoverMemory &movers, double time_s) {
    ScanPoints out;
    out.mover_dropped = PointMask::Constant(scan.size(), false);
    const bool masked = input.static_mask.size() > 0;
    const bool moving = input.moving_mask.size() > 0;
    std::vector<Eigen::Index> candidates;
    candidates.reserve(static_cast<std::size_t>(scan.size()));
    out.moving_base.resize(3, moving ? input.moving_mask.count() : 0);
    Eigen::Index m = 0;
    for (Eigen::Index i = 0; i < scan.size(); ++i) {
        if (moving && input.moving_mask(i)) {
            if (scan.xyz_radar.col(i).allFinite())
                out.moving_base.col(m++) = T_base_radar * scan.xyz_radar.col(i);
            continue;
        }
        if (masked && !input.static_mask(i)) continue;
        if (InRange(scan.xyz_radar.col(i), config)) candidates.push_back(i);
    }
    out.moving_base.conservativeResize(3, m);
    // Evidence of a mover: the clustered ones (a ghost or a noisy return is alone).
    out.moving_base = Clustered(out.moving_base, config.movers.neighbour_radius_m,
                                config.movers.min_cluster_points);
    out.moving_cells = movers.Observe(T_world_base * out.moving_base, time_s);

    Eigen::Matrix3Xd candidates_base(3, static_cast<Eigen::Index>(candidates.size()));
    for (std::size_t k = 0; k < candidates.size(); ++k)
        candidates_base.col(static_cast<Eigen::Index>(k)) =
            T_base_radar * scan.xyz_radar.col(candidates[k]);  // radar frame in, base frame out
    const std::vector<bool> near =
        NearAny(candidates_base, out.moving_base, config.movers.neighbour_radius_m);
    out.p_base.resize(3, candidates_base.cols());
    Eigen::Index n = 0;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
        const Eigen::Vector3d p_base = candidates_base.col(static_cast<Eigen::Index>(k));
        const Eigen::Index i = candidates[k];
        if (near[k] || movers.Moving(T_world_base * p_base)) {
            out.mover_dropped(i) = true;
            continue;
        }
        out.p_base.col(n++) = p_base;
        const Eigen::Vector3d p_radar = scan.xyz_radar.col(i);
        if (std::isfinite(scan.doppler_mps(i)))
            out.doppler.push_back({p_radar / p_radar.norm(), scan.doppler_mps(i)});
    }
    out.p_base.conservativeResize(3, n);
    return out;
}

std::vector<DopplerObservation> Thin(const std::vector<DopplerObservation> &all, int max_count) {
    if (static_cast<int>(all.size()) <= max_count) return all;
    std::vector<DopplerObservation> out;
    out.reserve(static_cast<std::size_t>(max_count));
    for (int k = 0; k < max_count; ++k) out.push_back(all[k * all.size() / max_count]);
    return out;
}

Eigen::Matrix3Xd ThinColumns(const Eigen::Matrix3Xd &points, int max_count) {
    if (points.cols() <= max_count) return points;
    Eigen::Matrix3Xd out(3, max_count);
    for (int k = 0; k < max_count; ++k) out.col(k) = points.col(k * points.cols() / max_count);
    return out;
}

}  // namespace dorado::mapping
