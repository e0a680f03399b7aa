#include "dorado/sim/vehicle.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "dorado/core/lie.hpp"

namespace dorado::sim {

namespace {

constexpr double kGravity = 9.81;

double WrapAngle(double a) {
    return std::atan2(std::sin(a), std::cos(a));
}

/// The speed and yaw rate the driver aims for during one segment of the route.
struct Segment {
    double end_s;
    double speed_mps;
    double yaw_rate_radps;
};

std::vector<Segment> DrawProfile(const SequenceConfig &config, std::mt19937_64 &rng) {
    const MotionConfig &m = config.motion;
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::normal_distribution<double> normal(0.0, 1.0);
    // Sequences start standing still for a second, like a recording does.
    std::vector<Segment> segments{{1.0, 0.0, 0.0}};
    double t = 1.0;
    while (t < config.duration_s + 1.0) {
        t += m.segment_min_s + (m.segment_max_s - m.segment_min_s) * uniform(rng);
        Segment s{t, 0.0, 0.0};
        const double u = uniform(rng);
        if (u < m.stop_probability) {
            segments.push_back(s);
            continue;
        }
        s.speed_mps = std::clamp(m.speed_mps + m.speed_sigma_mps * normal(rng),
                                 std::min(0.2, m.speed_mps), m.max_speed_mps);
        if (u < m.stop_probability + m.reverse_probability) s.speed_mps *= -0.5;
        s.yaw_rate_radps = std::clamp(m.yaw_rate_sigma_radps * normal(rng), -m.max_yaw_rate_radps,
                                      m.max_yaw_rate_radps);
        segments.push_back(s);
    }
    return segments;
}

/// Cubic Hermite interpolation between (p0, d0) and (p1, d1) over an interval of length h.
Eigen::Vector3d Hermite(const Eigen::Vector3d &p0, const Eigen::Vector3d &d0,
                        const Eigen::Vector3d &p1, const Eigen::Vector3d &d1, double h, double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * d0 + (-2 * s3 + 3 * s2) * p1 +
           (s3 - s2) * h * d1;
}

}  // namespace

VehicleTrajectory::VehicleTrajectory(const SequenceConfig &config, const Terrain &terrain)
    : terrain_(terrain), vehicle_(config.vehicle), duration_s_(config.duration_s) {
    Integrate(config);
}

void VehicleTrajectory::Integrate(const SequenceConfig &config) {
    std::mt19937_64 rng(config.seed * 0x9E3779B97F4A7C15ull + 17);
    const auto segments = DrawProfile(config, rng);
    std::normal_distribution<double> normal(0.0, 1.0);
    const MotionConfig &m = config.motion;
    const double tau = m.response_time_s;
    const double icr_tau_s = 2.0;
    // Ackermann steering cannot turn tighter than about 1.4 wheelbases.
    const double min_radius_m =
        vehicle_.type == VehicleType::kAckermann ? 2.8 * vehicle_.half_wheelbase_m : 0.0;

    double speed = 0.0, yaw_rate = 0.0, icr = vehicle_.icr_offset_m;
    // Derivative of the planar state for the current speed, yaw rate and slip.
    auto derivative = [&](const Eigen::Vector3d &s) {
        const double heading = s.z();
        const Eigen::Vector3d n = terrain_.Normal(s.x(), s.y());
        const Eigen::Vector2d left(-std::sin(heading), std::cos(heading));
        // Skid: the Z-ICR sits at x = icr, so the rear-axle centre slips sideways by -omega * icr;
        // on a side slope the vehicle also creeps downhill.
        const double slide = vehicle_.side_slip_gain_s * kGravity * n.head<2>().dot(left) *
                             std::min(1.0, std::abs(speed) / 0.5);
        const double v_lateral = -yaw_rate * icr + slide;
        return Eigen::Vector3d(speed * std::cos(heading) - v_lateral * std::sin(heading),
                               speed * std::sin(heading) + v_lateral * std::cos(heading), yaw_rate);
    };

    const auto n_knots = static_cast<std::size_t>(std::ceil(duration_s_ / dt_s_)) + 2;
    knots_.reserve(n_knots);
    Eigen::Vector3d state = Eigen::Vector3d::Zero();
    std::size_t segment = 0;
    for (std::size_t k = 0; k < n_knots; ++k) {
        const double t = static_cast<double>(k) * dt_s_;
        while (segment + 1 < segments.size() && t > segments[segment].end_s) ++segment;
        double target_speed = segments[segment].speed_mps;
        double target_yaw_rate = segments[segment].yaw_rate_radps;
        const double distance = state.head<2>().norm();
        if (m.max_distance_from_start_m > 0.0 && distance > m.max_distance_from_start_m &&
            std::abs(target_speed) > 0.0) {
            // Steer back towards the start (a driver keeping to the test area).
            const double home = std::atan2(-state.y(), -state.x());
            const double error = WrapAngle(home - state.z() + (target_speed < 0 ? M_PI : 0.0));
            target_yaw_rate = std::clamp(0.8 * error, -m.max_yaw_rate_radps, m.max_yaw_rate_radps);
        }
        const double abs_speed = std::max(std::abs(speed), 0.1);
        double limit = m.max_lateral_accel_mps2 / abs_speed;
        if (min_radius_m > 0.0) limit = std::min(limit, std::abs(speed) / min_radius_m);
        target_yaw_rate = std::clamp(target_yaw_rate, -limit, limit);

        const Eigen::Vector3d d0 = derivative(state);
        knots_.push_back({state, d0});
        // Heun step: the speed and yaw rate lag behind their targets.
        speed += (target_speed - speed) * dt_s_ / tau;
        yaw_rate += (target_yaw_rate - yaw_rate) * dt_s_ / tau;
        icr += -(icr - vehicle_.icr_offset_m) * dt_s_ / icr_tau_s +
               vehicle_.icr_offset_sigma_m * std::sqrt(2.0 * dt_s_ / icr_tau_s) * normal(rng);
        const Eigen::Vector3d predicted = state + dt_s_ * d0;
        state += 0.5 * dt_s_ * (d0 + derivative(predicted));
    }
}

Eigen::Vector3d VehicleTrajectory::PlanarState(double t) const {
    const double u = std::clamp(t, 0.0, duration_s_) / dt_s_;
    const auto k = std::min(static_cast<std::size_t>(u), knots_.size() - 2);
    const double s = u - static_cast<double>(k);
    return Hermite(knots_[k].xy_yaw, knots_[k].xy_yaw_rate, knots_[k + 1].xy_yaw,
                   knots_[k + 1].xy_yaw_rate, dt_s_, s);
}

Eigen::Isometry3d VehicleTrajectory::Pose(double t) const {
    const Eigen::Vector3d planar = PlanarState(t);
    const Eigen::Vector2d rear(planar.x(), planar.y());
    const Eigen::Vector2d forward(std::cos(planar.z()), std::sin(planar.z()));
    const Eigen::Vector2d left(-forward.y(), forward.x());
    const double wheelbase = 2.0 * vehicle_.half_wheelbase_m;
    const double half_track = 0.5 * vehicle_.track_width_m;
    // Ground contact of each wheel (the heights include the bumps).
    auto contact = [&](const Eigen::Vector2d &xy) {
        return Eigen::Vector3d(xy.x(), xy.y(), terrain_.Height(xy.x(), xy.y()));
    };
    const Eigen::Vector3d rear_left = contact(rear + half_track * left);
    const Eigen::Vector3d rear_right = contact(rear - half_track * left);
    const Eigen::Vector3d front_left = contact(rear + wheelbase * forward + half_track * left);
    const Eigen::Vector3d front_right = contact(rear + wheelbase * forward - half_track * left);
    const Eigen::Vector3d rear_mid = 0.5 * (rear_left + rear_right);
    const Eigen::Vector3d x_axis = (0.5 * (front_left + front_right) - rear_mid).normalized();
    const Eigen::Vector3d across =
        0.5 * (rear_left + front_left) - 0.5 * (rear_right + front_right);
    const Eigen::Vector3d z_axis = x_axis.cross(across).normalized();
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    T_world_base.linear() << x_axis, z_axis.cross(x_axis), z_axis;
    T_world_base.translation() = rear_mid + vehicle_.wheel_radius_m * z_axis;
    return T_world_base;
}

dorado::Twist VehicleTrajectory::Twist(double t) const {
    constexpr double h = 1e-4;
    const double t0 = std::clamp(t, h, duration_s_ - h);
    const Eigen::Isometry3d before = Pose(t0 - h), at = Pose(t0), after = Pose(t0 + h);
    dorado::Twist twist;
    twist.v_base_mps =
        at.linear().transpose() * (after.translation() - before.translation()) / (2 * h);
    twist.omega_base_radps = LogSO3(before.linear().transpose() * after.linear()) / (2 * h);
    return twist;
}

Eigen::Vector3d VehicleTrajectory::PointAccelerationWorld(double t,
                                                          const Eigen::Vector3d &p_base) const {
    constexpr double h = 2e-3;
    const double t0 = std::clamp(t, h, duration_s_ - h);
    return (Pose(t0 + h) * p_base - 2.0 * (Pose(t0) * p_base) + Pose(t0 - h) * p_base) / (h * h);
}

std::vector<Eigen::Vector2d> VehicleTrajectory::RouteSamples() const {
    std::vector<Eigen::Vector2d> samples;
    const auto step = static_cast<std::size_t>(0.5 / dt_s_);
    for (std::size_t k = 0; k < knots_.size(); k += step)
        samples.push_back(knots_[k].xy_yaw.head<2>());
    samples.push_back(knots_.back().xy_yaw.head<2>());
    return samples;
}

}  // namespace dorado::sim
