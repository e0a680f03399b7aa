#include "dorado/io/pointcloud_decoder.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace dorado::io {

namespace {

std::size_t TypeSize(uint8_t datatype) {
    switch (static_cast<FieldType>(datatype)) {
        case FieldType::kInt8:
        case FieldType::kUint8:
            return 1;
        case FieldType::kInt16:
        case FieldType::kUint16:
            return 2;
        case FieldType::kInt32:
        case FieldType::kUint32:
        case FieldType::kFloat32:
            return 4;
        case FieldType::kFloat64:
            return 8;
    }
    return 0;
}

const char *TypeName(uint8_t datatype) {
    static const char *kNames[] = {"?",     "INT8",   "UINT8",   "INT16",  "UINT16",
                                   "INT32", "UINT32", "FLOAT32", "FLOAT64"};
    return datatype <= 8 ? kNames[datatype] : "?";
}

template <typename T>
double Load(const uint8_t *p, bool swap) {
    uint8_t bytes[sizeof(T)];
    std::memcpy(bytes, p, sizeof(T));
    if (swap) std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return static_cast<double>(value);
}

/// A field resolved against the layout: where to read and how.
struct Accessor {
    std::size_t offset = 0;
    uint8_t datatype = 0;
    bool present = false;

    [[nodiscard]] double Read(const uint8_t *point, bool swap) const {
        const uint8_t *p = point + offset;
        switch (static_cast<FieldType>(datatype)) {
            case FieldType::kInt8:
                return Load<int8_t>(p, swap);
            case FieldType::kUint8:
                return Load<uint8_t>(p, swap);
            case FieldType::kInt16:
                return Load<int16_t>(p, swap);
            case FieldType::kUint16:
                return Load<uint16_t>(p, swap);
            case FieldType::kInt32:
                return Load<int32_t>(p, swap);
            case FieldType::kUint32:
                return Load<uint32_t>(p, swap);
            case FieldType::kFloat32:
                return Load<float>(p, swap);
            case FieldType::kFloat64:
                return Load<double>(p, swap);
        }
        return std::numeric_limits<double>::quiet_NaN();
    }
};

Accessor Resolve(const CloudBufferView &cloud, const std::string &name, bool required,
                 const char *role) {
    Accessor accessor;
    if (name.empty()) {
        if (required) throw DecodeError(std::string("the field map gives no name for ") + role);
        return accessor;
    }
    const auto it = std::find_if(cloud.fields.begin(), cloud.fields.end(),
                                 [&](const PointFieldDesc &f) { return f.name == name; });
    if (it == cloud.fields.end()) {
        throw DecodeError("missing field '" + name + "' (the field map's " + role +
                          "); fields present: " + DescribeFields(cloud.fields));
    }
    const std::size_t size = TypeSize(it->datatype);
    if (size == 0) {
        throw DecodeError("field '" + name + "' has unknown datatype code " +
                          std::to_string(it->datatype));
    }
    if (it->count < 1) throw DecodeError("field '" + name + "' has count 0");
    if (static_cast<std::size_t>(it->offset) + size > cloud.point_step) {
        throw DecodeError("field '" + name + "' at offset " + std::to_string(it->offset) +
                          " does not fit in point_step " + std::to_string(cloud.point_step));
    }
    accessor.offset = it->offset;
    accessor.datatype = it->datatype;
    accessor.present = true;
    return accessor;
}

void CheckLayout(const CloudBufferView &cloud) {
    const std::size_t points = static_cast<std::size_t>(cloud.width) * cloud.height;
    if (points == 0) return;
    if (cloud.point_step == 0) throw DecodeError("point_step is 0 for a non-empty cloud");
    if (static_cast<std::size_t>(cloud.row_step) <
        static_cast<std::size_t>(cloud.width) * cloud.point_step) {
        throw DecodeError("row_step " + std::to_string(cloud.row_step) + " is less than width " +
                          std::to_string(cloud.width) + " x point_step " +
                          std::to_string(cloud.point_step));
    }
    const std::size_t needed = static_cast<std::size_t>(cloud.row_step) * (cloud.height - 1) +
                               static_cast<std::size_t>(cloud.width) * cloud.point_step;
    if (cloud.data == nullptr || cloud.data_size < needed) {
        throw DecodeError("data holds " + std::to_string(cloud.data_size) + " bytes but " +
                          std::to_string(cloud.height) + " rows of " + std::to_string(cloud.width) +
                          " points need " + std::to_string(needed) + " (point_step " +
                          std::to_string(cloud.point_step) + ", row_step " +
                          std::to_string(cloud.row_step) + ")");
    }
}

bool HostIsBigEndian() {
    const uint16_t probe = 1;
    uint8_t first;
    std::memcpy(&first, &probe, 1);
    return first == 0;
}

}  // namespace

std::string DescribeFields(const std::vector<PointFieldDesc> &fields) {
    std::ostringstream out;
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (i) out << ", ";
        out << fields[i].name << ":" << TypeName(fields[i].datatype);
        if (fields[i].count != 1) out << "[" << fields[i].count << "]";
    }
    if (fields.empty()) out << "(none)";
    return out.str();
}

RadarScan DecodePointCloud(const CloudBufferView &cloud, const FieldMap &map) {
    CheckLayout(cloud);
    const Accessor x = Resolve(cloud, map.x, true, "x");
    const Accessor y = Resolve(cloud, map.y, true, "y");
    const Accessor z = Resolve(cloud, map.z, true, "z");
    const Accessor doppler = Resolve(cloud, map.doppler, true, "doppler");
    const Accessor range = Resolve(cloud, map.range, false, "range");
    const Accessor azimuth = Resolve(cloud, map.azimuth, false, "azimuth");
    const Accessor elevation = Resolve(cloud, map.elevation, false, "elevation");
    const Accessor power = Resolve(cloud, map.power, false, "power");
    const bool swap = cloud.is_bigendian != HostIsBigEndian();

    RadarScan scan;
    scan.has_power = power.present;
    const Eigen::Index n = static_cast<Eigen::Index>(cloud.width) * cloud.height;
    scan.Resize(n);
    Eigen::Index i = 0;
    for (uint32_t row = 0; row < cloud.height; ++row) {
        const uint8_t *row_start = cloud.data + static_cast<std::size_t>(row) * cloud.row_step;
        for (uint32_t col = 0; col < cloud.width; ++col, ++i) {
            const uint8_t *point = row_start + static_cast<std::size_t>(col) * cloud.point_step;
            scan.xyz_radar.col(i) << x.Read(point, swap), y.Read(point, swap), z.Read(point, swap);
            scan.doppler_mps[i] = map.doppler_sign * doppler.Read(point, swap);
            scan.power_db[i] = power.present ? power.Read(point, swap) : 0.0;
            scan.range_m[i] = range.present ? range.Read(point, swap) : 0.0;
            scan.azimuth_rad[i] = azimuth.present ? azimuth.Read(point, swap) : 0.0;
            scan.elevation_rad[i] = elevation.present ? elevation.Read(point, swap) : 0.0;
        }
    }
    if (!range.present || !azimuth.present || !elevation.present) {
        // Derived values only replace what the dataset lacks.
        const Eigen::VectorXd r = scan.range_m, a = scan.azimuth_rad, e = scan.elevation_rad;
        scan.DeriveSphericalFromXyz();
        if (range.present) scan.range_m = r;
        if (azimuth.present) scan.azimuth_rad = a;
        if (elevation.present) scan.elevation_rad = e;
    }
    return scan;
}

RadarScan DecodeFloat32Columns(const uint8_t *data, std::size_t size,
                               const std::vector<std::string> &columns, const FieldMap &map) {
    if (columns.empty()) throw DecodeError("no columns given for the float32 scan file");
    const std::size_t point_step = 4 * columns.size();
    if (size % point_step != 0) {
        throw DecodeError("size " + std::to_string(size) + " bytes is not a multiple of " +
                          std::to_string(columns.size()) + " float32 columns");
    }
    CloudBufferView view;
    view.width = static_cast<uint32_t>(size / point_step);
    view.point_step = static_cast<uint32_t>(point_step);
    view.row_step = view.width * view.point_step;
    view.data = data;
    view.data_size = size;
    for (std::size_t k = 0; k < columns.size(); ++k) {
        if (columns[k] != "_")
            view.fields.push_back({columns[k], static_cast<uint32_t>(4 * k), 7, 1});
    }
    return DecodePointCloud(view, map);
}

Eigen::Index RemoveNonFinitePoints(RadarScan &scan) {
    Eigen::Array<bool, Eigen::Dynamic, 1> keep(scan.size());
    for (Eigen::Index i = 0; i < scan.size(); ++i) keep[i] = IsFinitePoint(scan, i);
    const Eigen::Index removed = scan.size() - keep.count();
    if (removed > 0) scan = SelectPoints(scan, keep);
    return removed;
}

}  // namespace dorado::io
