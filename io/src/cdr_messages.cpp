// ROS2 CDR messages through Debian's Fast-CDR (libfastcdr): the encapsulation header, byte order,
// alignment and bounds checks are Fast-CDR's. Hand-written here is only the field order of the four
// message definitions (rosidl generates it in ROS2, which Debian does not ship), and the point
// data, which is taken as a view into the message bytes instead of a copy.
#include "dorado/io/cdr_messages.hpp"

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>

#include <functional>

namespace dorado::io {

namespace {

using eprosima::fastcdr::Cdr;

/// builtin_interfaces/msg/Time: int32 sec, uint32 nanosec.
int64_t ReadTime(Cdr &cdr) {
    int32_t sec = 0;
    uint32_t nanosec = 0;
    cdr.deserialize(sec).deserialize(nanosec);
    return static_cast<int64_t>(sec) * 1000000000LL + static_cast<int64_t>(nanosec);
}

CdrHeader ReadHeader(Cdr &cdr) {
    CdrHeader header;
    header.stamp_ns = ReadTime(cdr);
    cdr.deserialize(header.frame_id);
    return header;
}

Eigen::Vector3d ReadVector3(Cdr &cdr) {
    Eigen::Vector3d v;
    cdr.deserializeArray(v.data(), 3);
    return v;
}

/// geometry_msgs/msg/Quaternion: x, y, z, w.
Eigen::Quaterniond ReadQuaternion(Cdr &cdr) {
    double q[4];
    cdr.deserializeArray(q, 4);
    return Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
}

/// geometry_msgs/msg/Pose: position (x, y, z), orientation (x, y, z, w).
void ReadPose(Cdr &cdr, CdrPose &out) {
    out.position = ReadVector3(cdr);
    out.orientation = ReadQuaternion(cdr);
}

/// Runs `body` on a Cdr over the bytes after reading the encapsulation; Fast-CDR's exceptions
/// (bytes ending early, a bool that is not 0/1, an unknown encapsulation) become DecodeError.
template <typename T>
T Decode(const std::vector<uint8_t> &bytes, const char *type,
         const std::function<void(Cdr &, T &)> &body) {
    // FastBuffer wants a mutable pointer; the bytes are only read.
    eprosima::fastcdr::FastBuffer buffer(
        reinterpret_cast<char *>(const_cast<uint8_t *>(bytes.data())), bytes.size());
    Cdr cdr(buffer, Cdr::DEFAULT_ENDIAN, Cdr::DDS_CDR);
    T out;
    try {
        cdr.read_encapsulation();
        body(cdr, out);
    } catch (const eprosima::fastcdr::exception::Exception &e) {
        throw DecodeError(std::string(type) + " does not deserialize from its " +
                          std::to_string(bytes.size()) + " CDR bytes: " + e.what());
    }
    return out;
}

}  // namespace

CdrPointCloud2 DecodePointCloud2Cdr(const std::vector<uint8_t> &bytes) {
    return Decode<CdrPointCloud2>(
        bytes, "sensor_msgs/msg/PointCloud2", [&bytes](Cdr &cdr, CdrPointCloud2 &out) {
            out.header = ReadHeader(cdr);
            CloudBufferView &cloud = out.cloud;
            uint32_t n_fields = 0;
            cdr.deserialize(cloud.height).deserialize(cloud.width).deserialize(n_fields);
            if (n_fields > bytes.size()) throw DecodeError("field count larger than the message");
            cloud.fields.resize(n_fields);
            for (auto &f : cloud.fields) {
                cdr.deserialize(f.name).deserialize(f.offset).deserialize(f.datatype);
                cdr.deserialize(f.count);
            }
            uint32_t data_size = 0;
            cdr.deserialize(cloud.is_bigendian).deserialize(cloud.point_step);
            cdr.deserialize(cloud.row_step).deserialize(data_size);
            const std::size_t at = cdr.getSerializedDataLength();
            if (data_size > bytes.size() - at) {
                throw DecodeError("data has " + std::to_string(data_size) + " bytes but only " +
                                  std::to_string(bytes.size() - at) + " remain in the message");
            }
            cloud.data = bytes.data() + at;
            cloud.data_size = data_size;
            cdr.jump(data_size);
            cdr.deserialize(out.is_dense);
        });
}

CdrImu DecodeImuCdr(const std::vector<uint8_t> &bytes) {
    return Decode<CdrImu>(bytes, "sensor_msgs/msg/Imu", [](Cdr &cdr, CdrImu &out) {
        out.header = ReadHeader(cdr);
        out.orientation = ReadQuaternion(cdr);
        cdr.deserializeArray(out.orientation_covariance, 9);
        out.omega_radps = ReadVector3(cdr);
        cdr.deserializeArray(out.omega_covariance, 9);
        out.accel_mps2 = ReadVector3(cdr);
        cdr.deserializeArray(out.accel_covariance, 9);
    });
}

CdrPose DecodeOdometryCdr(const std::vector<uint8_t> &bytes) {
    return Decode<CdrPose>(bytes, "nav_msgs/msg/Odometry", [](Cdr &cdr, CdrPose &out) {
        out.header = ReadHeader(cdr);
        cdr.deserialize(out.child_frame_id);
        ReadPose(cdr, out);  // pose.pose; the twist is not read
        cdr.deserializeArray(out.covariance, 36);
    });
}

CdrPose DecodePoseStampedCdr(const std::vector<uint8_t> &bytes) {
    return Decode<CdrPose>(bytes, "geometry_msgs/msg/PoseStamped", [](Cdr &cdr, CdrPose &out) {
        out.header = ReadHeader(cdr);
        ReadPose(cdr, out);
    });
}

int64_t DecodeClockCdr(const std::vector<uint8_t> &bytes) {
    struct Clock {
        int64_t ns = 0;
    };
    return Decode<Clock>(bytes, "rosgraph_msgs/msg/Clock",
                         [](Cdr &cdr, Clock &out) { out.ns = ReadTime(cdr); })
        .ns;
}

}  // namespace dorado::io
