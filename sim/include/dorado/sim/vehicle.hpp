#pragma once
/// @file vehicle.hpp
/// The vehicle's true motion over the terrain. A planar speed / yaw-rate profile (with skid and
/// side slip) moves the rear-axle centre; the 3D attitude comes from the ground heights under the
/// four wheels, so pitch follows the hills and roll comes from side slopes and bumps. Every
/// quantity is a smooth function of time, so the twist is exact at any instant.

#include <Eigen/Geometry>
#include <vector>

#include "dorado/core/twist.hpp"
#include "dorado/sim/sequence_config.hpp"
#include "dorado/sim/terrain.hpp"

namespace dorado::sim {

class VehicleTrajectory {
  public:
    /// Draws the speed / yaw-rate profile (seeded) and integrates it over [0, duration_s].
    VehicleTrajectory(const SequenceConfig &config, const Terrain &terrain);

    /// T_world_base at t seconds after the start (clamped to [0, duration]).
    [[nodiscard]] Eigen::Isometry3d Pose(double t) const;
    /// Velocity of the base frame at t (central differences of Pose; error ~1e-7; exact: zero
    /// covariance).
    [[nodiscard]] dorado::Twist Twist(double t) const;
    /// Acceleration [m/s^2] in the world frame of the point p_base fixed on the vehicle.
    [[nodiscard]] Eigen::Vector3d PointAccelerationWorld(double t,
                                                         const Eigen::Vector3d &p_base) const;
    /// Planar positions of the rear-axle centre every ~0.5 s (to place the world around).
    [[nodiscard]] std::vector<Eigen::Vector2d> RouteSamples() const;
    [[nodiscard]] double duration_s() const { return duration_s_; }

  private:
    /// Planar state of the rear-axle centre at one knot, with its time derivative.
    struct Knot {
        Eigen::Vector3d xy_yaw;       ///< x, y [m], heading [rad]
        Eigen::Vector3d xy_yaw_rate;  ///< their derivatives
    };
    [[nodiscard]] Eigen::Vector3d PlanarState(double t) const;
    void Integrate(const SequenceConfig &config);

    const Terrain &terrain_;
    VehicleConfig vehicle_;
    double duration_s_;
    double dt_s_ = 0.002;
    std::vector<Knot> knots_;
};

}  // namespace dorado::sim
