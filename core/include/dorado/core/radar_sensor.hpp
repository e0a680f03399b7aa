#pragma once
/// @file radar_sensor.hpp
/// What the radar measures badly: the 1-sigma noise of its range and direction, and the Doppler
/// ambiguity. Part of the dataset description (its `radar:` section): a datasheet, not a tuning.

namespace dorado {

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

    [[nodiscard]] bool has_direction_noise() const {
        return azimuth_sigma_deg > 0.0 || elevation_sigma_deg > 0.0;
    }
};

}  // namespace dorado
