// The decoder on hand-built buffers: every datatype, both byte orders, and layouts that lie.
#include <gtest/gtest.h>

#include <cstring>

#include "dorado/io/pointcloud_decoder.hpp"

namespace dorado::io {
namespace {

/// Writes value as type `T` at p, in the requested byte order.
template <typename T>
void Put(uint8_t *p, T value, bool big_endian) {
    std::memcpy(p, &value, sizeof(T));
    if (big_endian) std::reverse(p, p + sizeof(T));  // the test machine is little-endian
}

struct Buffer {
    CloudBufferView view;
    std::vector<uint8_t> bytes;
};

/// One point per integer type: x as int8, y as uint16, z as int32, doppler as uint8, power as
/// int16, range as uint32, azimuth as float64, elevation as float32.
Buffer MixedTypes(bool big_endian, int n) {
    Buffer b;
    b.view.fields = {{"x", 0, 1, 1},        {"y", 1, 4, 1},         {"z", 3, 5, 1},
                     {"doppler", 7, 2, 1},  {"power", 8, 3, 1},     {"range", 10, 6, 1},
                     {"azimuth", 14, 8, 1}, {"elevation", 22, 7, 1}};
    b.view.point_step = 26;
    b.view.width = static_cast<uint32_t>(n);
    b.view.row_step = b.view.point_step * b.view.width;
    b.view.is_bigendian = big_endian;
    b.bytes.resize(b.view.row_step);
    for (int i = 0; i < n; ++i) {
        uint8_t *p = b.bytes.data() + i * b.view.point_step;
        Put<int8_t>(p + 0, static_cast<int8_t>(-3 * i), big_endian);
        Put<uint16_t>(p + 1, static_cast<uint16_t>(60000 + i), big_endian);
        Put<int32_t>(p + 3, -100000 * i, big_endian);
        Put<uint8_t>(p + 7, static_cast<uint8_t>(200 + i), big_endian);
        Put<int16_t>(p + 8, static_cast<int16_t>(-30000 + i), big_endian);
        Put<uint32_t>(p + 10, 4000000000u + i, big_endian);
        Put<double>(p + 14, 1e-300 * (i + 1), big_endian);
        Put<float>(p + 22, 0.25f * i, big_endian);
    }
    b.view.data = b.bytes.data();
    b.view.data_size = b.bytes.size();
    return b;
}

void ExpectMixed(const RadarScan &scan, int n) {
    ASSERT_EQ(scan.size(), n);
    for (int i = 0; i < n; ++i) {
        EXPECT_EQ(scan.xyz_radar(0, i), -3.0 * i);
        EXPECT_EQ(scan.xyz_radar(1, i), 60000.0 + i);
        EXPECT_EQ(scan.xyz_radar(2, i), -100000.0 * i);
        EXPECT_EQ(scan.doppler_mps[i], 200.0 + i);
        EXPECT_EQ(scan.power_db[i], -30000.0 + i);
        EXPECT_EQ(scan.range_m[i], 4000000000.0 + i);
        EXPECT_EQ(scan.azimuth_rad[i], 1e-300 * (i + 1));
        EXPECT_EQ(scan.elevation_rad[i], 0.25 * i);
    }
}

TEST(PointCloudDecoder, EveryDatatypeLittleEndian) {
    const Buffer b = MixedTypes(false, 7);
    ExpectMixed(DecodePointCloud(b.view, FieldMap{}), 7);
}

TEST(PointCloudDecoder, EveryDatatypeBigEndian) {
    const Buffer b = MixedTypes(true, 7);
    ExpectMixed(DecodePointCloud(b.view, FieldMap{}), 7);
}

TEST(PointCloudDecoder, DopplerSignFlipsTheConvention) {
    const Buffer b = MixedTypes(false, 3);
    FieldMap map;
    map.doppler_sign = -1.0;
    EXPECT_EQ(DecodePointCloud(b.view, map).doppler_mps[1], -201.0);
}

TEST(PointCloudDecoder, DataShorterThanTheLayoutClaimsIsAnError) {
    Buffer b = MixedTypes(false, 5);
    b.view.data_size -= 1;
    EXPECT_THROW((void)DecodePointCloud(b.view, FieldMap{}), DecodeError);
    b = MixedTypes(false, 5);
    b.view.width = 6;  // row_step now lies too
    EXPECT_THROW((void)DecodePointCloud(b.view, FieldMap{}), DecodeError);
    b = MixedTypes(false, 5);
    b.view.height = 2;
    EXPECT_THROW((void)DecodePointCloud(b.view, FieldMap{}), DecodeError);
}

TEST(PointCloudDecoder, PointStepSmallerThanAFieldIsAnError) {
    Buffer b = MixedTypes(false, 5);
    b.view.point_step = 20;  // elevation at offset 22 no longer fits
    b.view.row_step = 100;
    try {
        (void)DecodePointCloud(b.view, FieldMap{});
        FAIL();
    } catch (const DecodeError &e) {
        EXPECT_NE(std::string(e.what()).find("'azimuth'"), std::string::npos) << e.what();
    }
}

TEST(PointCloudDecoder, UnknownDatatypeAndZeroPointStepAreErrors) {
    Buffer b = MixedTypes(false, 2);
    b.view.fields[0].datatype = 9;
    EXPECT_THROW((void)DecodePointCloud(b.view, FieldMap{}), DecodeError);
    b = MixedTypes(false, 2);
    b.view.point_step = 0;
    EXPECT_THROW((void)DecodePointCloud(b.view, FieldMap{}), DecodeError);
}

TEST(PointCloudDecoder, EmptyCloudDecodesToAnEmptyScan) {
    CloudBufferView view;
    view.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"doppler", 12, 7, 1}};
    view.point_step = 16;
    FieldMap map;
    map.range = map.azimuth = map.elevation = map.power = "";
    const RadarScan scan = DecodePointCloud(view, map);
    EXPECT_TRUE(scan.empty());
    EXPECT_FALSE(scan.has_power);
}

TEST(PointCloudDecoder, RemoveNonFinitePoints) {
    Buffer b = MixedTypes(false, 4);
    RadarScan scan = DecodePointCloud(b.view, FieldMap{});
    scan.xyz_radar(1, 1) = std::numeric_limits<double>::infinity();
    scan.doppler_mps[3] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(RemoveNonFinitePoints(scan), 2);
    ASSERT_EQ(scan.size(), 2);
    EXPECT_EQ(scan.xyz_radar(0, 1), -6.0);
}

}  // namespace
}  // namespace dorado::io
