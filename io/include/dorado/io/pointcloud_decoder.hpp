#pragma once
/// @file pointcloud_decoder.hpp
/// Decodes a PointCloud2-shaped buffer (ROS sensor_msgs/PointCloud2 or PCL's PCLPointCloud2) into a
/// RadarScan, whatever the field names, types, offsets and byte order.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "dorado/core/radar_scan.hpp"

namespace dorado::io {

/// sensor_msgs/PointField datatype codes (identical in PCL's pcl::PCLPointField).
enum class FieldType : uint8_t {
    kInt8 = 1,
    kUint8 = 2,
    kInt16 = 3,
    kUint16 = 4,
    kInt32 = 5,
    kUint32 = 6,
    kFloat32 = 7,
    kFloat64 = 8
};

struct PointFieldDesc {
    std::string name;
    uint32_t offset = 0;
    uint8_t datatype = 7;  ///< a FieldType code; anything else is rejected
    uint32_t count = 1;
};

/// A view of a PointCloud2's layout and bytes (not owning).
struct CloudBufferView {
    uint32_t height = 1;
    uint32_t width = 0;
    uint32_t point_step = 0;
    uint32_t row_step = 0;
    bool is_bigendian = false;
    std::vector<PointFieldDesc> fields;
    const uint8_t *data = nullptr;
    std::size_t data_size = 0;
};

/// Which dataset field holds which quantity. An empty name means "the dataset has none":
/// range, azimuth and elevation are then derived from x, y, z and power is set to 0.
/// The default is the paper's Hugin layout (all float32).
struct FieldMap {
    std::string x = "x";
    std::string y = "y";
    std::string z = "z";
    std::string range = "range";
    std::string azimuth = "azimuth";
    std::string elevation = "elevation";
    std::string power = "power";
    std::string doppler = "doppler";
    /// Multiplies the recorded Doppler so that it becomes "positive = receding" (use -1 for sensors
    /// that report approaching points as positive).
    double doppler_sign = 1.0;
};

/// Thrown when the layout cannot be decoded (a field missing, a size that lies).
class DecodeError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Decodes every point (NaN values are kept; see CountNonFinite / RemoveNonFinite).
/// Throws DecodeError naming the field or the size that does not fit.
[[nodiscard]] RadarScan DecodePointCloud(const CloudBufferView &cloud, const FieldMap &map);

/// Decodes a raw little-endian float32 scan file (View-of-Delft, ColoRadar): `columns` names each
/// float32 column ("_" = ignored), then the field map picks the quantities. Throws DecodeError when
/// the size is not a whole number of points.
[[nodiscard]] RadarScan DecodeFloat32Columns(const uint8_t *data, std::size_t size,
                                             const std::vector<std::string> &columns,
                                             const FieldMap &map);

/// Names of the fields, comma separated, with their types (for messages and `dorado info`).
[[nodiscard]] std::string DescribeFields(const std::vector<PointFieldDesc> &fields);

/// Removes the points with a non-finite value; returns how many were removed.
Eigen::Index RemoveNonFinitePoints(RadarScan &scan);

}  // namespace dorado::io
