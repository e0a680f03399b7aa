#pragma once
// A synthetic street world and a drive through it for the loop closure's tests: poles and walls
// beside the road, a forward radar (range and field of view) seeing them from the true poses, and
// the written poses of a mapper whose odometry drifts (a yaw bias and noise, with the covariance
// it reports), whose map points are where that drifted mapper puts them.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::loops::test {

struct StreetWorld {
    std::vector<Eigen::Vector3d> points;

    // Structures in [x0, x1] x [y0, y1], kept `road_m` away from the lines y = road_y and
    // x = road_x (the streets), repeated `copies` times `copy_dx_m` apart along x.
    static StreetWorld Make(unsigned seed, double x0, double x1, double y0, double y1,
                            const std::vector<double> &road_x, const std::vector<double> &road_y,
                            int copies = 1, double copy_dx_m = 0.0) {
        std::mt19937 random(seed);
        std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1), unit(0.0, 1.0);
        auto off_road = [&](double x, double y) {
            for (double r : road_x)
                if (std::abs(x - r) < 6.0) return false;
            for (double r : road_y)
                if (std::abs(y - r) < 6.0) return false;
            return true;
        };
        std::vector<Eigen::Vector3d> patch;
        const int structures = static_cast<int>((x1 - x0) * (y1 - y0) / 60.0);
        for (int s = 0; s < structures; ++s) {
            const double x = ux(random), y = uy(random);
            if (!off_road(x, y)) continue;
            if (unit(random) < 0.75) {  // a pole or a tree: a vertical line of returns
                for (double z = 0.0; z <= 3.0; z += 0.6) patch.emplace_back(x, y, z);
            } else {  // a wall 5-20 m long
                const double heading = unit(random) * M_PI, length = 5.0 + 15.0 * unit(random);
                for (double t = 0.0; t <= length; t += 0.5)
                    for (double z = 0.0; z <= 2.0; z += 1.0)
                        patch.emplace_back(x + t * std::cos(heading), y + t * std::sin(heading), z);
            }
        }
        StreetWorld world;
        for (int c = 0; c < copies; ++c)
            for (const Eigen::Vector3d &p : patch)
                world.points.push_back(p + Eigen::Vector3d(c * copy_dx_m, 0.0, 0.0));
        return world;
    }

    // The points a forward radar at T_world_base sees (range, +-60 deg), with noise.
    Eigen::Matrix3Xd Seen(const Eigen::Isometry3d &T_world_base, std::mt19937 &random) const {
        std::normal_distribution<double> noise(0.0, 0.05);
        const Eigen::Isometry3d T_base_world = T_world_base.inverse();
        std::vector<Eigen::Vector3d> seen;
        for (const Eigen::Vector3d &p_world : points) {
            const Eigen::Vector3d p = T_base_world * p_world;
            if (p.head<2>().norm() > 50.0 || p.x() <= 0.0 ||
                std::abs(std::atan2(p.y(), p.x())) > M_PI / 3.0)
                continue;
            seen.push_back(p + Eigen::Vector3d(noise(random), noise(random), noise(random)));
        }
        Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(seen.size()));
        for (std::size_t i = 0; i < seen.size(); ++i)
            out.col(static_cast<Eigen::Index>(i)) = seen[i];
        return out;
    }
};

// Poses every metre along a closed polygon of corners (driven `laps` times), or an open one.
inline std::vector<Eigen::Isometry3d> PathThrough(const std::vector<Eigen::Vector2d> &corners,
                                                  int laps, bool closed) {
    std::vector<Eigen::Isometry3d> poses;
    const std::size_t legs = closed ? corners.size() : corners.size() - 1;
    for (int lap = 0; lap < laps; ++lap)
        for (std::size_t i = 0; i < legs; ++i) {
            const Eigen::Vector2d a = corners[i], b = corners[(i + 1) % corners.size()];
            const double length = (b - a).norm(), yaw = std::atan2(b.y() - a.y(), b.x() - a.x());
            for (double s = 0.0; s < length; s += 1.0) {
                Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
                T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
                T.translation() << a.x() + s * std::cos(yaw), a.y() + s * std::sin(yaw), 0.0;
                poses.push_back(T);
            }
        }
    return poses;
}

// The written poses of a drifting mapper along the true path: each step's motion gets a yaw bias
// and noise, the covariance reports the noise plus the bias's size; its map points are what the
// radar saw, placed at the written pose.
inline std::vector<mapping::WrittenPose> DriftingDrive(const StreetWorld &world,
                                                       const std::vector<Eigen::Isometry3d> &truth,
                                                       double yaw_bias_rad_per_m, unsigned seed) {
    std::mt19937 random(seed);
    const double sigma_m = 0.02, sigma_rad = 4e-4;
    std::normal_distribution<double> noise_m(0.0, sigma_m), noise_rad(0.0, sigma_rad);
    std::vector<mapping::WrittenPose> written;
    Eigen::Isometry3d T_written = truth.front();
    for (std::size_t k = 0; k < truth.size(); ++k) {
        mapping::WrittenPose pose;
        pose.stamp_ns = static_cast<int64_t>(k) * 100'000'000;
        if (k > 0) {
            Vector6d xi;
            xi << noise_m(random), noise_m(random), 0.3 * noise_m(random), 0.3 * noise_rad(random),
                0.3 * noise_rad(random), noise_rad(random) + yaw_bias_rad_per_m;
            T_written = T_written * (truth[k - 1].inverse() * truth[k]) * ExpSE3(xi);
            const double a = sigma_m * sigma_m, b = sigma_rad * sigma_rad;
            pose.covariance = (Vector6d() << a, a, a, b, b, b).finished().asDiagonal();
        }
        pose.T_world_base = T_written;
        pose.map_updated = true;
        pose.map_points_added_world = T_written * world.Seen(truth[k], random);
        written.push_back(std::move(pose));
    }
    return written;
}

}  // namespace dorado::loops::test
