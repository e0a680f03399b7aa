#include "ros_messages.hpp"

#include <cstring>

#include "dorado/core/lie.hpp"

namespace dorado::ros_node {

sensor_msgs::PointCloud2 MakeCloud(const std_msgs::Header &header, const Eigen::Matrix3Xd &points,
                                   const Eigen::VectorXd *doppler, const Eigen::VectorXd *power) {
    sensor_msgs::PointCloud2 cloud;
    cloud.header = header;
    std::vector<std::string> names{"x", "y", "z"};
    if (doppler) names.push_back("doppler");
    if (power) names.push_back("power");
    for (std::size_t i = 0; i < names.size(); ++i) {
        sensor_msgs::PointField field;
        field.name = names[i];
        field.offset = static_cast<uint32_t>(4 * i);
        field.datatype = sensor_msgs::PointField::FLOAT32;
        field.count = 1;
        cloud.fields.push_back(field);
    }
    cloud.height = 1;
    cloud.width = static_cast<uint32_t>(points.cols());
    cloud.point_step = static_cast<uint32_t>(4 * names.size());
    cloud.row_step = cloud.point_step * cloud.width;
    cloud.is_bigendian = false;
    cloud.is_dense = true;
    cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
    uint8_t *out = cloud.data.data();
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
        float values[5] = {static_cast<float>(points(0, i)), static_cast<float>(points(1, i)),
                           static_cast<float>(points(2, i)), 0.0f, 0.0f};
        std::size_t n = 3;
        if (doppler) values[n++] = static_cast<float>((*doppler)(i));
        if (power) values[n++] = static_cast<float>((*power)(i));
        std::memcpy(out, values, 4 * n);  // little-endian host (x86_64, arm64)
        out += cloud.point_step;
    }
    return cloud;
}

sensor_msgs::PointCloud2 MakeCloud(const std_msgs::Header &header, const RadarScan &scan,
                                   const Eigen::Array<bool, Eigen::Dynamic, 1> &keep, bool want) {
    Eigen::Index n = 0;
    for (Eigen::Index i = 0; i < keep.size(); ++i) n += keep(i) == want;
    Eigen::Matrix3Xd points(3, n);
    Eigen::VectorXd doppler(n), power(n);
    for (Eigen::Index i = 0, j = 0; i < scan.size(); ++i) {
        if (keep(i) != want) continue;
        points.col(j) = scan.xyz_radar.col(i);
        doppler(j) = scan.doppler_mps(i);
        power(j++) = scan.power_db(i);
    }
    return MakeCloud(header, points, &doppler, &power);
}

Twist TwistAt(const Twist &twist_base, const Eigen::Isometry3d &T_base_child) {
    const Eigen::Matrix3d Rt = T_base_child.linear().transpose();
    // [v_child; omega_child] = J [v; omega], J = [[R^T, -R^T Hat(p)], [0, R^T]].
    Matrix6d J = Matrix6d::Zero();
    J.topLeftCorner<3, 3>() = Rt;
    J.topRightCorner<3, 3>() = -Rt * Hat(T_base_child.translation());
    J.bottomRightCorner<3, 3>() = Rt;
    Vector6d x;
    x << twist_base.v_base_mps, twist_base.omega_base_radps;
    const Vector6d y = J * x;
    Twist child;
    child.v_base_mps = y.head<3>();
    child.omega_base_radps = y.tail<3>();
    child.covariance = J * twist_base.covariance * J.transpose();
    return child;
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
