#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dorado/core/radar_scan.hpp"

namespace dorado {
namespace {

RadarScan ThreePoints() {
    RadarScan scan;
    scan.Resize(3);
    scan.xyz_radar << 3, 0, 1, 4, 0, 1, 0, 2, 0;
    scan.doppler_mps << -1, 0.5, 2;
    scan.power_db << 10, 20, 30;
    scan.DeriveSphericalFromXyz();
    return scan;
}

TEST(RadarScan, DerivesSphericalCoordinatesFromXyz) {
    const RadarScan scan = ThreePoints();
    EXPECT_DOUBLE_EQ(scan.range_m[0], 5.0);
    EXPECT_DOUBLE_EQ(scan.azimuth_rad[0], std::atan2(4.0, 3.0));
    // columns: (3, 4, 0), (0, 0, 2), (1, 1, 0)
    EXPECT_DOUBLE_EQ(scan.elevation_rad[1], M_PI / 2);
    EXPECT_DOUBLE_EQ(scan.elevation_rad[2], 0.0);
    EXPECT_DOUBLE_EQ(scan.azimuth_rad[2], M_PI / 4);
}

TEST(RadarScan, UnitDirectionsAreNormalisedAndZeroAtTheOrigin) {
    RadarScan scan = ThreePoints();
    scan.xyz_radar.col(2).setZero();
    const Eigen::Matrix3Xd d = UnitDirections(scan);
    EXPECT_NEAR(d.col(0).norm(), 1.0, 1e-15);
    EXPECT_DOUBLE_EQ(d(0, 0), 0.6);
    EXPECT_EQ(d.col(2).norm(), 0.0);
}

TEST(RadarScan, SelectAndFiniteChecks) {
    RadarScan scan = ThreePoints();
    scan.doppler_mps[1] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(IsFinitePoint(scan, 0));
    EXPECT_FALSE(IsFinitePoint(scan, 1));
    Eigen::Array<bool, Eigen::Dynamic, 1> keep(3);
    keep << true, false, true;
    const RadarScan kept = SelectPoints(scan, keep);
    ASSERT_EQ(kept.size(), 2);
    EXPECT_EQ(kept.power_db[1], 30.0);
    EXPECT_EQ(kept.doppler_mps[0], -1.0);
}

}  // namespace
}  // namespace dorado
