#pragma once
/// @file radar_scan.hpp
/// One scan of a Doppler-capable range sensor (4D radar or FMCW lidar), stored as structure of
/// arrays so that the estimators read the columns with Eigen without copying.

#include <Eigen/Core>
#include <cstdint>
#include <string>

namespace dorado {

/// A radar scan in the sensor frame ("radar"). Column i of every array belongs to point i.
///
/// Conventions (independent of what a dataset calls its fields):
/// - `doppler_mps` is the radial velocity of the point relative to the sensor, positive when the
/// point
///   moves away. For a static point and a sensor moving with velocity v_radar: doppler = -d .
///   v_radar (paper eq. 1), with d the unit direction from the sensor to the point.
/// - Directions are derived from `xyz_radar`, never from `azimuth_rad`/`elevation_rad`: datasets
///   disagree on the azimuth reference (the paper's Hugin dataset measures it from the Y axis).
struct RadarScan {
    int64_t stamp_ns = 0;  ///< acquisition time, nanoseconds since the epoch (or bag start)
    std::string frame_id;  ///< the sensor frame name, as recorded

    Eigen::Matrix3Xd xyz_radar;     ///< point positions [m] in the radar frame
    Eigen::VectorXd range_m;        ///< range [m]; equals |xyz| when the dataset has no range field
    Eigen::VectorXd azimuth_rad;    ///< as recorded by the sensor (informative only)
    Eigen::VectorXd elevation_rad;  ///< as recorded by the sensor (informative only)
    Eigen::VectorXd power_db;       ///< return power / RCS / intensity; 0 when the dataset has none
    Eigen::VectorXd doppler_mps;    ///< radial velocity [m/s], positive = receding

    bool has_power = false;  ///< false when the dataset provides no power-like field

    /// Number of points.
    [[nodiscard]] Eigen::Index size() const { return xyz_radar.cols(); }
    [[nodiscard]] bool empty() const { return size() == 0; }

    /// Resizes every column to n points (contents undefined).
    void Resize(Eigen::Index n);

    /// Fills range/azimuth/elevation from xyz (azimuth from +X towards +Y, elevation from the XY
    /// plane).
    void DeriveSphericalFromXyz();
};

/// Unit direction from the sensor to each point, from xyz. Points at the origin get a zero column.
[[nodiscard]] Eigen::Matrix3Xd UnitDirections(const RadarScan &scan);

/// True when every value of point i (position, Doppler, power, range) is finite.
[[nodiscard]] bool IsFinitePoint(const RadarScan &scan, Eigen::Index i);

/// Copies the points whose `keep` flag is set, keeping stamp and frame id.
[[nodiscard]] RadarScan SelectPoints(const RadarScan &scan,
                                     const Eigen::Array<bool, Eigen::Dynamic, 1> &keep);

}  // namespace dorado
