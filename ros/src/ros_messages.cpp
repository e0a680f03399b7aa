#include "ros_messages.hpp"

#include "dorado/core/lie.hpp"

namespace dorado::ros_node {

sensor_msgs::PointCloud2 MakeCloud(const std_msgs::Header &header, const CloudOutput &points) {
    const PackedCloud packed = PackCloud(points);
    sensor_msgs::PointCloud2 cloud;
    cloud.header = header;
    for (std::size_t i = 0; i < packed.fields.size(); ++i) {
        sensor_msgs::PointField field;
        field.name = packed.fields[i];
        field.offset = static_cast<uint32_t>(4 * i);
        field.datatype = sensor_msgs::PointField::FLOAT32;
        field.count = 1;
        cloud.fields.push_back(field);
    }
    cloud.height = 1;
    cloud.width = packed.width;
    cloud.point_step = packed.point_step;
    cloud.row_step = packed.point_step * packed.width;
    cloud.is_bigendian = false;
    cloud.is_dense = true;
    cloud.data = packed.data;
    return cloud;
}

void FillOdometry(const Eigen::Isometry3d &T_world_child, const Matrix6d &pose_covariance,
                  const Twist &twist_child, nav_msgs::Odometry &msg) {
    const Eigen::Vector3d p = T_world_child.translation();
    const Eigen::Quaterniond q(T_world_child.linear());
    msg.pose.pose.position.x = p.x();
    msg.pose.pose.position.y = p.y();
    msg.pose.pose.position.z = p.z();
    msg.pose.pose.orientation.x = q.x();
    msg.pose.pose.orientation.y = q.y();
    msg.pose.pose.orientation.z = q.z();
    msg.pose.pose.orientation.w = q.w();
    msg.twist.twist.linear.x = twist_child.v_base_mps.x();
    msg.twist.twist.linear.y = twist_child.v_base_mps.y();
    msg.twist.twist.linear.z = twist_child.v_base_mps.z();
    msg.twist.twist.angular.x = twist_child.omega_base_radps.x();
    msg.twist.twist.angular.y = twist_child.omega_base_radps.y();
    msg.twist.twist.angular.z = twist_child.omega_base_radps.z();
    for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < 6; ++c) {
            msg.pose.covariance[6 * r + c] = pose_covariance(r, c);
            msg.twist.covariance[6 * r + c] = twist_child.covariance(r, c);
        }
    }
}

}  // namespace dorado::ros_node
