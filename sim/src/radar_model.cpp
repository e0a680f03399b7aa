#include "dorado/sim/radar_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "dorado/core/angles.hpp"

namespace dorado::sim {

namespace {

using Rng = std::mt19937_64;

double Uniform(Rng &rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}
double Gaussian(Rng &rng) {
    return std::normal_distribution<double>(0.0, 1.0)(rng);
}

/// Azimuth (from X towards Y) and elevation (from the XY plane) of a radar-frame vector.
struct Polar {
    double range, azimuth, elevation;
};
Polar ToPolar(const Eigen::Vector3d &p) {
    const double r_xy = std::hypot(p.x(), p.y());
    return {p.norm(), std::atan2(p.y(), p.x()), std::atan2(p.z(), r_xy)};
}

/// Range to the nearest opaque surface per (azimuth, elevation) cell of the field of view: boxes
/// are rasterised by intersecting each cell's central ray with the box (slab test).
class DepthBuffer {
  public:
    DepthBuffer(double half_az, double half_el, const std::vector<Eigen::Vector3d> &directions)
        : half_az_(half_az),
          half_el_(half_el),
          n_az_(static_cast<int>(std::ceil(2 * half_az / kCellAz))),
          n_el_(static_cast<int>(std::ceil(2 * half_el / kCellEl))),
          directions_(directions),
          depth_(static_cast<std::size_t>(n_az_ * n_el_), std::numeric_limits<float>::infinity()) {}

    /// Central ray of every cell, row by row (elevation-major), in the radar frame.
    static std::vector<Eigen::Vector3d> CellDirections(double half_az, double half_el) {
        const int n_az = static_cast<int>(std::ceil(2 * half_az / kCellAz));
        const int n_el = static_cast<int>(std::ceil(2 * half_el / kCellEl));
        std::vector<Eigen::Vector3d> directions;
        for (int j = 0; j < n_el; ++j) {
            const double el = -half_el + (j + 0.5) * kCellEl;
            for (int i = 0; i < n_az; ++i) {
                const double az = -half_az + (i + 0.5) * kCellAz;
                directions.emplace_back(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                        std::sin(el));
            }
        }
        return directions;
    }

    /// box corners and frame given in the radar frame.
    void Add(const Occluder &box_world, const Eigen::Isometry3d &T_radar_world) {
        const auto corners = box_world.Corners();
        double az_lo = 1e9, az_hi = -1e9, el_lo = 1e9, el_hi = -1e9;
        for (const auto &c : corners) {
            const Polar p = ToPolar(T_radar_world * c);
            az_lo = std::min(az_lo, p.azimuth);
            az_hi = std::max(az_hi, p.azimuth);
            el_lo = std::min(el_lo, p.elevation);
            el_hi = std::max(el_hi, p.elevation);
        }
        if (az_hi - az_lo > M_PI) return;  // wraps behind the radar (or contains it)
        if (az_hi < -half_az_ || az_lo > half_az_ || el_hi < -half_el_ || el_lo > half_el_) return;
        // The box in its own frame: ray origin and direction per cell.
        const Eigen::Matrix3d R_box =
            Eigen::AngleAxisd(box_world.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        const Eigen::Isometry3d T_world_radar = T_radar_world.inverse();
        const Eigen::Matrix3d R_box_radar = R_box.transpose() * T_world_radar.linear();
        const Eigen::Vector3d origin_box =
            R_box.transpose() * (T_world_radar.translation() - box_world.center_world);
        const Eigen::Vector3d &half = box_world.half_extent_m;
        if ((origin_box.cwiseAbs() - half).maxCoeff() < 0.0) return;  // radar inside the box
        const int i0 = std::max(0, AzCell(az_lo)), i1 = std::min(n_az_ - 1, AzCell(az_hi));
        const int j0 = std::max(0, ElCell(el_lo)), j1 = std::min(n_el_ - 1, ElCell(el_hi));
        for (int j = j0; j <= j1; ++j) {
            for (int i = i0; i <= i1; ++i) {
                const Eigen::Vector3d d =
                    R_box_radar * directions_[static_cast<std::size_t>(j * n_az_ + i)];
                double t_near = 0.0, t_far = 1e9;
                for (int k = 0; k < 3 && t_near <= t_far; ++k) {
                    if (std::abs(d[k]) < 1e-12) {
                        if (std::abs(origin_box[k]) > half[k]) t_near = 2e9;
                        continue;
                    }
                    double ta = (-half[k] - origin_box[k]) / d[k],
                           tb = (half[k] - origin_box[k]) / d[k];
                    if (ta > tb) std::swap(ta, tb);
                    t_near = std::max(t_near, ta);
                    t_far = std::min(t_far, tb);
                }
                if (t_near > t_far) continue;
                float &cell = depth_[static_cast<std::size_t>(j * n_az_ + i)];
                cell = std::min(cell, static_cast<float>(t_near));
            }
        }
    }

    [[nodiscard]] double Depth(double az, double el) const {
        const int i = AzCell(az), j = ElCell(el);
        if (i < 0 || i >= n_az_ || j < 0 || j >= n_el_)
            return std::numeric_limits<double>::infinity();
        return depth_[static_cast<std::size_t>(j * n_az_ + i)];
    }

  private:
    static constexpr double kCellAz = DegToRad(0.5);
    static constexpr double kCellEl = DegToRad(1.0);
    [[nodiscard]] int AzCell(double az) const {
        return static_cast<int>(std::floor((az + half_az_) / kCellAz));
    }
    [[nodiscard]] int ElCell(double el) const {
        return static_cast<int>(std::floor((el + half_el_) / kCellEl));
    }
    double half_az_, half_el_;
    int n_az_, n_el_;
    const std::vector<Eigen::Vector3d> &directions_;
    std::vector<float> depth_;
};

/// The terrain's horizon seen from the radar, per azimuth sector: the highest elevation angle
/// (world frame) of the ground up to each horizontal distance. Hills hide what is behind them.
class TerrainHorizon {
  public:
    TerrainHorizon(const Terrain &terrain, const Eigen::Isometry3d &T_world_radar, double half_az,
                   double max_range)
        : origin_(T_world_radar.translation()),
          half_az_(half_az),
          n_az_(static_cast<int>(std::ceil(2 * half_az / kCellAz))),
          n_steps_(static_cast<int>(max_range / kStep) + 1),
          horizon_(static_cast<std::size_t>(n_az_ * n_steps_)) {
        for (int i = 0; i < n_az_; ++i) {
            const double az = -half_az + (i + 0.5) * kCellAz;
            const Eigen::Vector3d d =
                T_world_radar.linear() * Eigen::Vector3d(std::cos(az), std::sin(az), 0.0);
            const Eigen::Vector2d h = d.head<2>().normalized();
            double highest = -M_PI / 2;
            for (int k = 0; k < n_steps_; ++k) {
                const double s = (k + 1) * kStep;
                const Eigen::Vector2d xy = origin_.head<2>() + s * h;
                highest = std::max(
                    highest, std::atan2(terrain.SmoothHeight(xy.x(), xy.y()) - origin_.z(), s));
                horizon_[static_cast<std::size_t>(i * n_steps_ + k)] = static_cast<float>(highest);
            }
        }
    }

    /// True when ground nearer than p_world (by more than a step) rises above the line of sight.
    [[nodiscard]] bool Hidden(double radar_azimuth, const Eigen::Vector3d &p_world) const {
        const int i = static_cast<int>(std::floor((radar_azimuth + half_az_) / kCellAz));
        if (i < 0 || i >= n_az_) return false;
        const Eigen::Vector3d v = p_world - origin_;
        const double s = v.head<2>().norm();
        const int k = static_cast<int>(s / kStep) - 2;
        if (k < 0) return false;
        const double elevation = std::atan2(v.z(), s);
        return elevation <
               horizon_[static_cast<std::size_t>(i * n_steps_ + std::min(k, n_steps_ - 1))] - 0.002;
    }

  private:
    static constexpr double kCellAz = DegToRad(2.0);
    static constexpr double kStep = 2.0;
    Eigen::Vector3d origin_;
    double half_az_;
    int n_az_, n_steps_;
    std::vector<float> horizon_;
};

/// A reflector the radar could see, before detection.
struct Candidate {
    Eigen::Vector3d p_world;
    Eigen::Vector3d v_world;
    double rcs_dbsm;
    PointSource source;
};

/// A detection before it is written into the scan.
struct Detection {
    double range, azimuth, elevation, doppler, snr_db;
    PointSource source;
};

}  // namespace

RadarModel::RadarModel(const RadarConfig &config, const Terrain &terrain, const StaticWorld &world,
                       const MovingObjects &moving)
    : config_(config),
      terrain_(terrain),
      world_(world),
      moving_(moving),
      cell_directions_(DepthBuffer::CellDirections(DegToRad(0.5 * config.azimuth_fov_deg),
                                                   DegToRad(0.5 * config.elevation_fov_deg))) {}

SimulatedScan RadarModel::Measure(double t, const Eigen::Isometry3d &T_world_radar,
                                  const Eigen::Vector3d &v_world_radar, Rng &rng) const {
    const RadarConfig &c = config_;
    const double half_az = DegToRad(0.5 * c.azimuth_fov_deg),
                 half_el = DegToRad(0.5 * c.elevation_fov_deg);
    const Eigen::Isometry3d T_radar_world = T_world_radar.inverse();
    const Eigen::Vector3d origin = T_world_radar.translation();
    const Eigen::Vector2d origin_xy = origin.head<2>();

    // Occlusion: static boxes near the radar and the moving objects' boxes.
    std::vector<MovingReflector> moving;
    std::vector<Occluder> moving_boxes;
    moving_.Snapshot(t, origin, c.max_range_m, moving, moving_boxes);
    DepthBuffer depth(half_az, half_el, cell_directions_);
    world_.occluder_grid().ForEachNear(
        origin_xy, c.max_range_m + world_.max_occluder_radius_m(),
        [&](uint32_t i) { depth.Add(world_.occluders()[i], T_radar_world); });
    for (const auto &box : moving_boxes) depth.Add(box, T_radar_world);
    const TerrainHorizon horizon(terrain_, T_world_radar, half_az, c.max_range_m);

    std::vector<Candidate> candidates;
    candidates.reserve(8192);
    // Cheap cone test before any trigonometry (the field of view is narrower than 180 deg).
    const double max_range2 = c.max_range_m * c.max_range_m;
    const double tan_az = half_az < M_PI / 2 - 1e-3 ? std::tan(half_az) : 1e9;
    const double tan_el = std::tan(half_el);
    const Eigen::Matrix3f R_radar_world = T_radar_world.linear().cast<float>();
    const Eigen::Vector3f origin_f = origin.cast<float>();
    world_.reflector_grid().ForEachNear(origin_xy, c.max_range_m, [&](uint32_t i) {
        const Reflector &r = world_.reflectors()[i];
        const Eigen::Vector3f p = R_radar_world * (r.position_world - origin_f);
        if (p.squaredNorm() > max_range2 || p.x() <= 0.0f) return;
        if (std::abs(p.y()) > tan_az * p.x() + 0.5f) return;
        if (std::abs(p.z()) > tan_el * std::hypot(p.x(), p.y()) + 0.5f) return;
        double rcs = r.rcs_dbsm;
        if (!r.normal_world.isZero()) {
            // Flat surfaces return mostly near normal incidence.
            const Eigen::Vector3d d = (r.position_world.cast<double>() - origin).normalized();
            const double cos_i = std::abs(d.dot(r.normal_world.cast<double>()));
            rcs += 10.0 * std::log10(0.03 + 0.97 * cos_i * cos_i);
        }
        candidates.push_back(
            {r.position_world.cast<double>(), Eigen::Vector3d::Zero(), rcs, PointSource::kStatic});
    });
    for (const auto &m : moving) {
        candidates.push_back(
            {m.position_world, m.velocity_world, m.rcs_dbsm, PointSource::kMoving});
    }
    // Ground patches at short range, uniform in azimuth and distance (so denser near the radar,
    // where the ground is seen), each standing for its share of the area; backscatter
    // ~ sigma0 * sin(grazing).
    const double s_min = 0.5, s_max = c.ground_max_range_m;
    const int n_ground = std::poisson_distribution<int>(c.ground_returns_per_scan)(rng);
    for (int k = 0; k < n_ground; ++k) {
        const double az = Uniform(rng, -half_az, half_az);
        const double s = Uniform(rng, s_min, s_max);
        const double patch_area = 2.0 * half_az * s * (s_max - s_min) / n_ground;
        const Eigen::Vector2d h =
            (T_world_radar.linear() * Eigen::Vector3d(std::cos(az), std::sin(az), 0.0))
                .head<2>()
                .normalized();
        const Eigen::Vector2d xy = origin_xy + s * h;
        const Eigen::Vector3d g(xy.x(), xy.y(), terrain_.Height(xy.x(), xy.y()));
        const double sin_grazing = -(g - origin).normalized().dot(terrain_.Normal(xy.x(), xy.y()));
        if (sin_grazing <= 1e-3) continue;  // the back of a slope
        const double rcs = c.ground_sigma0_db + 10.0 * std::log10(patch_area * sin_grazing);
        candidates.push_back({g, Eigen::Vector3d::Zero(), rcs, PointSource::kGround});
    }

    const auto doppler_of = [&](const Eigen::Vector3d &p_world, const Eigen::Vector3d &v_world) {
        // eq. (1): radial velocity, positive when the point recedes from the radar.
        return (p_world - origin).normalized().dot(v_world - v_world_radar);
    };
    const auto in_fov = [&](const Polar &p) {
        return p.range >= c.min_range_m && p.range <= c.max_range_m &&
               std::abs(p.azimuth) <= half_az && std::abs(p.elevation) <= half_el;
    };
    const auto snr_of = [&](double rcs, const Polar &p) {
        const double gain_db =
            -3.0 * (std::pow(p.azimuth / half_az, 2) + std::pow(p.elevation / half_el, 2));
        return c.snr_at_1m_0dbsm_db + rcs - 40.0 * std::log10(p.range) + gain_db;
    };
    const auto fading_db = [&] { return 10.0 * std::log10(-std::log(Uniform(rng, 1e-12, 1.0))); };

    std::vector<Detection> detections;
    detections.reserve(candidates.size() / 2);
    for (const auto &cand : candidates) {
        const Polar p = ToPolar(T_radar_world * cand.p_world);
        if (!in_fov(p)) continue;
        const bool blocked = p.range > depth.Depth(p.azimuth, p.elevation) + 0.4 ||
                             horizon.Hidden(p.azimuth, cand.p_world);
        if (blocked && Uniform(rng, 0.0, 1.0) >= c.occlusion_leak) continue;
        const double snr = snr_of(cand.rcs_dbsm, p) + fading_db() - (blocked ? 10.0 : 0.0);
        if (snr < c.detection_threshold_db) continue;
        const double doppler = doppler_of(cand.p_world, cand.v_world);
        detections.push_back({p.range, p.azimuth, p.elevation, doppler, snr, cand.source});
        if (cand.source == PointSource::kGround || snr < c.detection_threshold_db + 15.0) continue;
        // Strong returns make ghosts.
        if (Uniform(rng, 0, 1) < c.ghost_probability) {  // angular ambiguity: wrong direction
            const double shift = DegToRad((rng() % 2 ? 1.0 : -1.0) * Uniform(rng, 8.0, 25.0));
            detections.push_back({p.range, p.azimuth + shift,
                                  p.elevation + DegToRad(2.0) * Gaussian(rng), doppler,
                                  snr - Uniform(rng, 10.0, 20.0), PointSource::kGhost});
        }
        if (Uniform(rng, 0, 1) < c.double_bounce_probability) {  // radar-target-radar-target
            detections.push_back({2.0 * p.range, p.azimuth, p.elevation, 2.0 * doppler,
                                  snr - Uniform(rng, 12.0, 20.0), PointSource::kGhost});
        }
        if (Uniform(rng, 0, 1) < c.ground_multipath_probability) {  // mirror image in the ground
            const Eigen::Vector3d n = terrain_.Normal(cand.p_world.x(), cand.p_world.y());
            const Eigen::Vector3d foot(cand.p_world.x(), cand.p_world.y(),
                                       terrain_.SmoothHeight(cand.p_world.x(), cand.p_world.y()));
            const Eigen::Vector3d image = cand.p_world - 2.0 * (cand.p_world - foot).dot(n) * n;
            const Eigen::Vector3d v_image = cand.v_world - 2.0 * cand.v_world.dot(n) * n;
            const Polar q = ToPolar(T_radar_world * image);
            // The bistatic path: half direct, half via the ground.
            detections.push_back({0.5 * (p.range + q.range), q.azimuth, q.elevation,
                                  0.5 * (doppler + doppler_of(image, v_image)),
                                  snr - Uniform(rng, 6.0, 15.0), PointSource::kGhost});
        }
    }
    // Clutter: false alarms anywhere, with any Doppler.
    const double v_spread = std::max(3.0, 2.0 * v_world_radar.norm());
    for (int k = std::poisson_distribution<int>(c.clutter_per_scan)(rng); k > 0; --k) {
        detections.push_back(
            {Uniform(rng, c.min_range_m, c.max_range_m), Uniform(rng, -half_az, half_az),
             Uniform(rng, -half_el, half_el), Uniform(rng, -v_spread, v_spread),
             c.detection_threshold_db + std::exponential_distribution<double>(0.3)(rng),
             PointSource::kClutter});
    }
    // Ghosts outside the field of view or too weak are not seen.
    detections.erase(std::remove_if(detections.begin(), detections.end(),
                                    [&](const Detection &d) {
                                        return !in_fov({d.range, d.azimuth, d.elevation}) ||
                                               d.snr_db < c.detection_threshold_db;
                                    }),
                     detections.end());
    // The sensor reports at most max_points detections: the strongest.
    if (detections.size() > static_cast<std::size_t>(c.max_points)) {
        std::nth_element(
            detections.begin(), detections.begin() + c.max_points, detections.end(),
            [](const Detection &a, const Detection &b) { return a.snr_db > b.snr_db; });
        detections.resize(static_cast<std::size_t>(c.max_points));
    }
    std::sort(detections.begin(), detections.end(),
              [](const Detection &a, const Detection &b) { return a.range < b.range; });

    SimulatedScan out;
    out.scan.frame_id = c.frame_id;
    out.scan.has_power = true;
    out.scan.Resize(static_cast<Eigen::Index>(detections.size()));
    out.source.resize(detections.size());
    for (std::size_t k = 0; k < detections.size(); ++k) {
        const Detection &d = detections[k];
        // Weak returns are measured worse, Doppler above all.
        const double weak =
            std::sqrt(1.0 + std::pow(10.0, (c.doppler_snr_ref_db - d.snr_db) / 10.0));
        const double range = std::max(0.05, d.range + c.range_sigma_m * Gaussian(rng));
        const double az =
            d.azimuth + DegToRad(std::min(weak, 3.0) * c.azimuth_sigma_deg) * Gaussian(rng);
        const double el =
            d.elevation + DegToRad(std::min(weak, 3.0) * c.elevation_sigma_deg) * Gaussian(rng);
        double doppler = d.doppler + weak * c.doppler_sigma_mps * Gaussian(rng);
        if (c.doppler_unambiguous_mps > 0.0) {
            const double span = 2.0 * c.doppler_unambiguous_mps;
            doppler -= span * std::floor((doppler + c.doppler_unambiguous_mps) / span);
        }
        const auto i = static_cast<Eigen::Index>(k);
        out.scan.xyz_radar.col(i) << range * std::cos(el) * std::cos(az),
            range * std::cos(el) * std::sin(az), range * std::sin(el);
        out.scan.range_m[i] = range;
        out.scan.azimuth_rad[i] = HuginAzimuth(out.scan.xyz_radar(0, i), out.scan.xyz_radar(1, i));
        out.scan.elevation_rad[i] = el;
        out.scan.power_db[i] = d.snr_db + c.noise_floor_db;
        out.scan.doppler_mps[i] = doppler;
        out.source[k] = d.source;
    }
    return out;
}

}  // namespace dorado::sim
