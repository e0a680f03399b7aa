#include "dorado/sim/moving_objects.hpp"

#include <cmath>
#include <random>

namespace dorado::sim {

namespace {

using Rng = std::mt19937_64;

double Uniform(Rng &rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

/// Where and when an object appears: relative to the vehicle's pose at t_ref.
struct Anchor {
    double t_ref;
    Eigen::Vector2d xy;
    double heading;  ///< of the vehicle at t_ref
};

Anchor AnchorNearRoute(const VehicleTrajectory &vehicle, Rng &rng, double ahead_m, double left_m) {
    const double t = Uniform(rng, 0.0, std::max(0.0, vehicle.duration_s() - 3.0));
    const Eigen::Isometry3d T = vehicle.Pose(t);
    const double heading = std::atan2(T.linear()(1, 0), T.linear()(0, 0));
    const Eigen::Vector2d forward(std::cos(heading), std::sin(heading));
    const Eigen::Vector2d left(-forward.y(), forward.x());
    return {t, T.translation().head<2>() + ahead_m * forward + left_m * left, heading};
}

}  // namespace

MovingObjects::MovingObjects(const DynamicConfig &config, const Terrain &terrain,
                             const VehicleTrajectory &vehicle, uint64_t seed)
    : terrain_(terrain) {
    Rng rng(seed ^ 0xd1a3b0c5ull);
    std::normal_distribution<double> normal(0.0, 1.0);
    const double d_min = config.spawn_distance_min_m, d_max = config.spawn_distance_max_m;

    // A walking person: torso, arms and legs swinging at the gait frequency.
    auto person = [&](double speed) {
        std::vector<LocalReflector> r;
        const double gait_hz = 0.9 * std::max(speed, 0.3) + 0.6;
        const int n = 12 + static_cast<int>(rng() % 12);
        for (int i = 0; i < n; ++i) {
            const double part = Uniform(rng, 0.0, 1.0);
            const double z = part < 0.4 ? Uniform(rng, 0.1, 0.85) : Uniform(rng, 0.85, 1.6);
            const double swing = part < 0.4   ? Uniform(rng, 0.6, 1.4) * speed
                                 : part < 0.6 ? Uniform(rng, 0.3, 0.8) * speed
                                              : 0.0;
            r.push_back({{Uniform(rng, -0.15, 0.15), Uniform(rng, -0.22, 0.22), z},
                         Uniform(rng, -12.0, -3.0),
                         swing,
                         gait_hz,
                         Uniform(rng, 0.0, 2 * M_PI)});
        }
        return r;
    };
    // Reflectors on the surface of a box (car body, bus side), wheels spinning.
    auto box = [&](const Eigen::Vector3d &half, int n, double rcs_lo, double rcs_hi, double speed) {
        std::vector<LocalReflector> r;
        for (int i = 0; i < n; ++i) {
            Eigen::Vector3d u(Uniform(rng, -1, 1), Uniform(rng, -1, 1), Uniform(rng, -1, 1));
            const int axis = static_cast<int>(rng() % 4);  // sides twice as likely as roof/front
            if (axis < 2) {
                u.y() = u.y() > 0 ? 1.0 : -1.0;
            } else if (axis == 2) {
                u.x() = u.x() > 0 ? 1.0 : -1.0;
            } else {
                u.z() = 1.0;
            }
            const Eigen::Vector3d offset = half.cwiseProduct(u) + Eigen::Vector3d(0, 0, half.z());
            const bool wheel = offset.z() < 0.5 && std::abs(u.y()) == 1.0;
            r.push_back({offset, Uniform(rng, rcs_lo, rcs_hi), wheel ? speed : 0.0,
                         speed / (2 * M_PI * 0.35), Uniform(rng, 0.0, 2 * M_PI)});
        }
        return r;
    };
    auto add = [&](const Anchor &a, double heading, double speed, double yaw_rate, double before_s,
                   double after_s, const Eigen::Vector3d &half, std::vector<LocalReflector> r) {
        objects_.push_back({a.t_ref, a.t_ref - before_s, a.t_ref + after_s, a.xy, heading, speed,
                            yaw_rate, half, std::move(r)});
    };
    auto side = [&] { return rng() % 2 ? 1.0 : -1.0; };

    for (int i = 0; i < config.people; ++i) {
        const double d = Uniform(rng, d_min, d_max), bearing = Uniform(rng, -0.9, 0.9);
        const Anchor a =
            AnchorNearRoute(vehicle, rng, d * std::cos(bearing), d * std::sin(bearing));
        const double speed = Uniform(rng, 0.7, 1.6);
        add(a, Uniform(rng, 0, 2 * M_PI), speed, 0.1 * normal(rng), 15.0, 30.0, {0.25, 0.25, 0.85},
            person(speed));
    }
    for (int i = 0; i < config.crowds; ++i) {
        const Anchor a =
            AnchorNearRoute(vehicle, rng, Uniform(rng, 6.0, 18.0), Uniform(rng, -6.0, 6.0));
        const double heading = Uniform(rng, 0, 2 * M_PI), speed = Uniform(rng, 0.8, 1.3);
        const int n = 10 + static_cast<int>(rng() % 16);
        for (int k = 0; k < n; ++k) {
            Anchor member = a;
            member.xy += Eigen::Vector2d(Uniform(rng, -3.0, 3.0), Uniform(rng, -3.0, 3.0));
            const double s = speed * Uniform(rng, 0.9, 1.1);
            add(member, heading + 0.1 * normal(rng), s, 0.02 * normal(rng), 20.0, 30.0,
                {0.25, 0.25, 0.85}, person(s));
        }
    }
    for (int i = 0; i < config.cyclists; ++i) {
        const double d = Uniform(rng, d_min, d_max);
        const Anchor a = AnchorNearRoute(vehicle, rng, d, side() * Uniform(rng, 2.0, 8.0));
        const double speed = Uniform(rng, 3.0, 6.0);
        auto r = box({0.9, 0.2, 0.55}, 10, -10.0, 0.0, speed);
        const auto rider = person(0.5);
        r.insert(r.end(), rider.begin(), rider.end());
        add(a, a.heading + (rng() % 2 ? 0.0 : M_PI) + 0.2 * normal(rng), speed, 0.03 * normal(rng),
            10.0, 15.0, {0.9, 0.3, 0.85}, std::move(r));
    }
    for (int i = 0; i < config.cars; ++i) {
        const Anchor a = AnchorNearRoute(vehicle, rng, Uniform(rng, 15.0, 50.0),
                                         side() * Uniform(rng, 3.0, 10.0));
        const int pattern = static_cast<int>(rng() % 3);  // oncoming, same way, crossing
        const double heading = a.heading +
                               (pattern == 0   ? M_PI
                                : pattern == 1 ? 0.0
                                               : M_PI / 2) +
                               0.05 * normal(rng);
        const double speed = Uniform(rng, 3.0, 12.0);
        add(a, heading, speed, 0.01 * normal(rng), 8.0, 12.0, {2.25, 0.9, 0.75},
            box({2.25, 0.9, 0.75}, 90, -6.0, 10.0, speed));
    }
    for (int i = 0; i < config.large_vehicles; ++i) {
        // Overtakes the vehicle close by: while it passes it fills much of the field of view.
        const Anchor a = AnchorNearRoute(vehicle, rng, Uniform(rng, -20.0, -12.0),
                                         side() * Uniform(rng, 3.5, 6.0));
        const auto twist = vehicle.Twist(a.t_ref);
        const double speed = std::abs(twist.v_base_mps.x()) + Uniform(rng, 1.0, 3.0);
        add(a, a.heading, speed, 0.0, 2.0, 25.0, {6.0, 1.25, 1.75},
            box({6.0, 1.25, 1.75}, 900, -8.0, 8.0, speed));
    }
}

Eigen::Vector3d MovingObjects::PlanarPose(const Object &o, double t) {
    const double dt = t - o.t_ref_s;
    const double heading = o.heading_ref_rad + o.yaw_rate_radps * dt;
    Eigen::Vector2d xy;
    if (std::abs(o.yaw_rate_radps) < 1e-6) {
        xy = o.xy_ref + o.speed_mps * dt * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    } else {
        const double r = o.speed_mps / o.yaw_rate_radps;
        xy = o.xy_ref + r * Eigen::Vector2d(std::sin(heading) - std::sin(o.heading_ref_rad),
                                            std::cos(o.heading_ref_rad) - std::cos(heading));
    }
    return {xy.x(), xy.y(), heading};
}

void MovingObjects::Snapshot(double t, const Eigen::Vector3d &center, double radius,
                             std::vector<MovingReflector> &reflectors,
                             std::vector<Occluder> &boxes) const {
    constexpr double h = 1e-3;
    for (const auto &o : objects_) {
        if (t < o.t_begin_s || t > o.t_end_s) continue;
        const Eigen::Vector3d pose = PlanarPose(o, t);
        if ((pose.head<2>() - center.head<2>()).norm() > radius + 8.0) continue;
        auto ground = [&](const Eigen::Vector3d &p) {
            return Eigen::Vector3d(p.x(), p.y(), terrain_.SmoothHeight(p.x(), p.y()));
        };
        const Eigen::Vector3d origin = ground(pose);
        const Eigen::Vector3d v_origin =
            (ground(PlanarPose(o, t + h)) - ground(PlanarPose(o, t - h))) / (2 * h);
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(pose.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
        const Eigen::Vector3d omega(0.0, 0.0, o.yaw_rate_radps);
        for (const auto &r : o.reflectors) {
            const Eigen::Vector3d arm = R * r.offset_m;
            const double swing = r.swing_mps * std::sin(2 * M_PI * r.swing_hz * t + r.swing_phase);
            reflectors.push_back(
                {origin + arm, v_origin + omega.cross(arm) + swing * R.col(0), r.rcs_dbsm});
        }
        boxes.push_back(
            {origin + Eigen::Vector3d(0, 0, o.half_extent_m.z()), o.half_extent_m, pose.z()});
    }
}

}  // namespace dorado::sim
