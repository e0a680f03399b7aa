#include "dorado/ros2/ros2_convert.hpp"

#include <Eigen/Geometry>
#include <algorithm>

namespace dorado::ros2 {
namespace {

// The generated structs hold `char *` for strings: the writer only reads them.
char *Borrow(const std::string &text) {
    return const_cast<char *>(text.c_str());
}

geometry_msgs_msg_dds__Vector3_ VectorOf(const Eigen::Vector3d &v) {
    return {v.x(), v.y(), v.z()};
}

geometry_msgs_msg_dds__Quaternion_ QuaternionOf(const Eigen::Quaterniond &q) {
    return {q.x(), q.y(), q.z(), q.w()};
}

void CopyMatrix(const Matrix6d &m, double (&out)[36]) {
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) out[6 * r + c] = m(r, c);
}

std::vector<sensor_msgs_msg_dds__PointField_> &FieldSequence(
    std::vector<sensor_msgs_msg_dds__PointField_> &fields, sensor_msgs_msg_dds__PointCloud2_ &msg) {
    msg.fields._maximum = msg.fields._length = static_cast<uint32_t>(fields.size());
    msg.fields._buffer = fields.data();
    msg.fields._release = false;
    return fields;
}

}  // namespace

builtin_interfaces_msg_dds__Time_ TimeOf(int64_t stamp_ns) {
    int64_t sec = stamp_ns / 1000000000LL, nanosec = stamp_ns % 1000000000LL;
    if (nanosec < 0) sec -= 1, nanosec += 1000000000LL;
    return {static_cast<int32_t>(sec), static_cast<uint32_t>(nanosec)};
}

std_msgs_msg_dds__Header_ HeaderOf(int64_t stamp_ns, const std::string &frame_id) {
    return {TimeOf(stamp_ns), Borrow(frame_id)};
}

nav_msgs_msg_dds__Odometry_ OdometryOf(const ros_node::OdometryOutput &odometry) {
    nav_msgs_msg_dds__Odometry_ msg{};
    msg.header = HeaderOf(odometry.stamp_ns, odometry.frame_id);
    msg.child_frame_id = Borrow(odometry.child_frame_id);
    const Eigen::Isometry3d &T = odometry.T_frame_child;
    const Eigen::Vector3d p = T.translation();
    msg.pose.pose.position = {p.x(), p.y(), p.z()};
    msg.pose.pose.orientation = QuaternionOf(Eigen::Quaterniond(T.linear()));
    CopyMatrix(odometry.pose_covariance, msg.pose.covariance);
    msg.twist.twist.linear = VectorOf(odometry.twist_child.v_base_mps);
    msg.twist.twist.angular = VectorOf(odometry.twist_child.omega_base_radps);
    CopyMatrix(odometry.twist_child.covariance, msg.twist.covariance);
    return msg;
}

geometry_msgs_msg_dds__TransformStamped_ TransformOf(const ros_node::TransformOutput &transform) {
    geometry_msgs_msg_dds__TransformStamped_ msg{};
    msg.header = HeaderOf(transform.stamp_ns, transform.parent_frame);
    msg.child_frame_id = Borrow(transform.child_frame);
    msg.transform.translation = VectorOf(transform.T_parent_child.translation());
    msg.transform.rotation = QuaternionOf(Eigen::Quaterniond(transform.T_parent_child.linear()));
    return msg;
}

sensor_msgs_msg_dds__PointCloud2_ CloudOf(int64_t stamp_ns, const std::string &frame_id,
                                          const ros_node::PackedCloud &packed,
                                          std::vector<sensor_msgs_msg_dds__PointField_> &fields) {
    sensor_msgs_msg_dds__PointCloud2_ msg{};
    msg.header = HeaderOf(stamp_ns, frame_id);
    fields.clear();
    for (std::size_t i = 0; i < packed.fields.size(); ++i)
        fields.push_back({Borrow(packed.fields[i]), static_cast<uint32_t>(4 * i),
                          static_cast<uint8_t>(io::FieldType::kFloat32), 1});
    FieldSequence(fields, msg);
    msg.height = 1;
    msg.width = packed.width;
    msg.is_bigendian = false;
    msg.point_step = packed.point_step;
    msg.row_step = packed.point_step * packed.width;
    msg.data._maximum = msg.data._length = static_cast<uint32_t>(packed.data.size());
    msg.data._buffer = const_cast<uint8_t *>(packed.data.data());
    msg.data._release = false;
    msg.is_dense = true;
    return msg;
}

sensor_msgs_msg_dds__PointCloud2_ CloudOf(const io::CdrPointCloud2 &cloud,
                                          std::vector<sensor_msgs_msg_dds__PointField_> &fields) {
    sensor_msgs_msg_dds__PointCloud2_ msg{};
    msg.header = HeaderOf(cloud.header.stamp_ns, cloud.header.frame_id);
    fields.clear();
    for (const io::PointFieldDesc &f : cloud.cloud.fields)
        fields.push_back({Borrow(f.name), f.offset, f.datatype, f.count});
    FieldSequence(fields, msg);
    msg.height = cloud.cloud.height;
    msg.width = cloud.cloud.width;
    msg.is_bigendian = cloud.cloud.is_bigendian;
    msg.point_step = cloud.cloud.point_step;
    msg.row_step = cloud.cloud.row_step;
    msg.data._maximum = msg.data._length = static_cast<uint32_t>(cloud.cloud.data_size);
    msg.data._buffer = const_cast<uint8_t *>(cloud.cloud.data);
    msg.data._release = false;
    msg.is_dense = cloud.is_dense;
    return msg;
}

sensor_msgs_msg_dds__Imu_ ImuOf(const io::CdrImu &imu) {
    sensor_msgs_msg_dds__Imu_ msg{};
    msg.header = HeaderOf(imu.header.stamp_ns, imu.header.frame_id);
    msg.orientation = QuaternionOf(imu.orientation);
    msg.angular_velocity = VectorOf(imu.omega_radps);
    msg.linear_acceleration = VectorOf(imu.accel_mps2);
    std::copy(imu.orientation_covariance, imu.orientation_covariance + 9,
              msg.orientation_covariance);
    std::copy(imu.omega_covariance, imu.omega_covariance + 9, msg.angular_velocity_covariance);
    std::copy(imu.accel_covariance, imu.accel_covariance + 9, msg.linear_acceleration_covariance);
    return msg;
}

}  // namespace dorado::ros2
