#pragma once
/// @file moving_objects.hpp
/// People, cyclists, cars, crowds and large vehicles moving near the vehicle's route. Each object
/// moves on the ground along an arc at constant speed during its lifetime; its reflectors may
/// swing (limbs, wheels), which spreads their Doppler like micro-Doppler does.

#include <Eigen/Core>
#include <vector>

#include "dorado/sim/sequence_config.hpp"
#include "dorado/sim/terrain.hpp"
#include "dorado/sim/vehicle.hpp"
#include "dorado/sim/world.hpp"

namespace dorado::sim {

/// A reflector of a moving object at one instant, in the world frame.
struct MovingReflector {
    Eigen::Vector3d position_world;
    Eigen::Vector3d velocity_world;  ///< [m/s]
    double rcs_dbsm;
};

class MovingObjects {
  public:
    /// Spawns the configured objects near the route at random times (seeded).
    MovingObjects(const DynamicConfig &config, const Terrain &terrain,
                  const VehicleTrajectory &vehicle, uint64_t seed);

    /// Reflectors and occluding boxes of the objects alive at t within `radius` of `center`.
    void Snapshot(double t, const Eigen::Vector3d &center, double radius,
                  std::vector<MovingReflector> &reflectors, std::vector<Occluder> &boxes) const;

    [[nodiscard]] std::size_t size() const { return objects_.size(); }

  private:
    struct LocalReflector {
        Eigen::Vector3d offset_m;  ///< in the object's frame (X along its heading, Z up)
        double rcs_dbsm;
        double swing_mps;  ///< amplitude of the oscillating velocity along X
        double swing_hz;
        double swing_phase;
    };
    struct Object {
        double t_ref_s, t_begin_s, t_end_s;
        Eigen::Vector2d xy_ref;  ///< position at t_ref
        double heading_ref_rad, speed_mps, yaw_rate_radps;
        Eigen::Vector3d half_extent_m;
        std::vector<LocalReflector> reflectors;
    };
    /// Planar position and heading of an object at t.
    static Eigen::Vector3d PlanarPose(const Object &object, double t);

    const Terrain &terrain_;
    std::vector<Object> objects_;
};

}  // namespace dorado::sim
