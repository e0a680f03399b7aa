#include "dorado/core/radar_scan.hpp"

#include <cmath>

namespace dorado {

void RadarScan::Resize(Eigen::Index n) {
    xyz_radar.resize(3, n);
    range_m.resize(n);
    azimuth_rad.resize(n);
    elevation_rad.resize(n);
    power_db.resize(n);
    doppler_mps.resize(n);
}

void RadarScan::DeriveSphericalFromXyz() {
    range_m = xyz_radar.colwise().norm().transpose();
    azimuth_rad.resize(size());
    elevation_rad.resize(size());
    for (Eigen::Index i = 0; i < size(); ++i) {
        const Eigen::Vector3d p = xyz_radar.col(i);
        azimuth_rad[i] = std::atan2(p.y(), p.x());
        elevation_rad[i] = std::atan2(p.z(), p.head<2>().norm());
    }
}

Eigen::Matrix3Xd UnitDirections(const RadarScan &scan) {
    Eigen::Matrix3Xd d(3, scan.size());
    for (Eigen::Index i = 0; i < scan.size(); ++i) {
        const double r = scan.xyz_radar.col(i).norm();
        d.col(i) = r > 0.0 ? Eigen::Vector3d(scan.xyz_radar.col(i) / r) : Eigen::Vector3d::Zero();
    }
    return d;
}

bool IsFinitePoint(const RadarScan &scan, Eigen::Index i) {
    return scan.xyz_radar.col(i).allFinite() && std::isfinite(scan.doppler_mps[i]) &&
           std::isfinite(scan.power_db[i]) && std::isfinite(scan.range_m[i]);
}

RadarScan SelectPoints(const RadarScan &scan, const Eigen::Array<bool, Eigen::Dynamic, 1> &keep) {
    RadarScan out;
    out.stamp_ns = scan.stamp_ns;
    out.frame_id = scan.frame_id;
    out.has_power = scan.has_power;
    out.Resize(keep.count());
    Eigen::Index j = 0;
    for (Eigen::Index i = 0; i < scan.size(); ++i) {
        if (!keep[i]) continue;
        out.xyz_radar.col(j) = scan.xyz_radar.col(i);
        out.range_m[j] = scan.range_m[i];
        out.azimuth_rad[j] = scan.azimuth_rad[i];
        out.elevation_rad[j] = scan.elevation_rad[i];
        out.power_db[j] = scan.power_db[i];
        out.doppler_mps[j] = scan.doppler_mps[i];
        ++j;
    }
    return out;
}

}  // namespace dorado
