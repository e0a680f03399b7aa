#pragma once
/// @file radar_sensor.hpp
/// What the radar measures badly: the 1-sigma noise of its range and direction, and the Doppler
/// ambiguity. Part of the dataset description (its `radar:` section): a datasheet, not a tuning.

namespace dorado {

/// Whether the radar measures elevation (the dataset's `radar.geometry`).
enum class ScanGeometry {
    /// Decided at the first scan with points: planar when every z is exactly 0, else 3-D.
    kAuto,
    k3d,     ///< x, y, z: the paper's 3-D ego-velocity and SE(3) motion
    kPlanar, ///< a 2D radar (x, y, no elevation): ego-velocity in the plane, SE(2) motion
};

/// "auto" | "3d" | "planar".
[[nodiscard]] inline const char *ToString(ScanGeometry geometry) {
    switch (geometry) {
        case ScanGeometry::kAuto:
            return "auto";
        case ScanGeometry::k3d:
            return "3d";
        case ScanGeometry::kPlanar:
            return "planar";
    }
    return "?";
}

struct RadarSensorModel {
    /// Range noise [m]. The ego-velocity uses only directions, so range noise does not bias it;
    /// kept for the mapper and for honest point positions.
    double range_sigma_m = 0.0;
    /// Azimuth and elevation noise of strong returns [deg] (0 = exact directions). The
    /// ego-velocity removes the errors-in-variables bias this noise causes (see
    /// EgoVelocityConfig::compensate_direction_noise).
    double azimuth_sigma_deg = 0.0;
    double elevation_sigma_deg = 0.0;
    /// The Doppler is measured modulo 2 * this [m/s], wrapped into [-v, v) (0 = no aliasing).
    double doppler_unambiguous_mps = 0.0;
    /// 3-D or a 2D radar (every z = 0); kAuto decides from the first scan.
    ScanGeometry geometry = ScanGeometry::kAuto;

    [[nodiscard]] bool has_direction_noise() const {
        return azimuth_sigma_deg > 0.0 || elevation_sigma_deg > 0.0;
    }
};

}  // namespace dorado
