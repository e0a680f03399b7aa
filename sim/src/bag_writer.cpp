#include "dorado/sim/bag_writer.hpp"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstring>
#include <stdexcept>

namespace dorado::sim {

namespace {

ros::Time ToRosTime(int64_t stamp_ns) {
    ros::Time t;
    t.fromNSec(static_cast<uint64_t>(stamp_ns));
    return t;
}

}  // namespace

struct BagWriter::Impl {
    rosbag::Bag bag;
    uint32_t seq = 0;
};

BagWriter::BagWriter(const std::string &path) : impl_(std::make_unique<Impl>()), path_(path) {
    try {
        impl_->bag.open(path, rosbag::bagmode::Write);
        impl_->bag.setCompression(rosbag::compression::Uncompressed);
    } catch (const std::exception &e) {
        throw std::runtime_error(path + ": cannot create the bag: " + e.what());
    }
}

BagWriter::~BagWriter() {
    try {
        impl_->bag.close();
    } catch (...) {
    }
}

void BagWriter::WriteRadar(const std::string &topic, const RadarScan &scan) {
    sensor_msgs::PointCloud2 msg;
    msg.header.stamp = ToRosTime(scan.stamp_ns);
    msg.header.frame_id = scan.frame_id;
    msg.header.seq = impl_->seq++;
    static const char *kNames[] = {"x",         "y",       "z",     "range",
                                   "elevation", "azimuth", "power", "doppler"};
    for (uint32_t k = 0; k < 8; ++k) {
        sensor_msgs::PointField f;
        f.name = kNames[k];
        f.offset = 4 * k;
        f.datatype = sensor_msgs::PointField::FLOAT32;
        f.count = 1;
        msg.fields.push_back(f);
    }
    const auto n = static_cast<uint32_t>(scan.size());
    msg.height = 1;
    msg.width = n;
    msg.is_bigendian = false;
    msg.point_step = 32;
    msg.row_step = 32 * n;
    msg.is_dense = true;
    msg.data.resize(static_cast<std::size_t>(msg.row_step));
    for (uint32_t i = 0; i < n; ++i) {
        const float values[8] = {
            static_cast<float>(scan.xyz_radar(0, i)),  static_cast<float>(scan.xyz_radar(1, i)),
            static_cast<float>(scan.xyz_radar(2, i)),  static_cast<float>(scan.range_m[i]),
            static_cast<float>(scan.elevation_rad[i]), static_cast<float>(scan.azimuth_rad[i]),
            static_cast<float>(scan.power_db[i]),      static_cast<float>(scan.doppler_mps[i])};
        std::memcpy(&msg.data[static_cast<std::size_t>(i) * 32], values, sizeof(values));
    }
    impl_->bag.write(topic, msg.header.stamp, msg);
}

void BagWriter::WriteImu(const std::string &topic, const std::string &frame_id,
                         const ImuSample &sample) {
    sensor_msgs::Imu msg;
    msg.header.stamp = ToRosTime(sample.stamp_ns);
    msg.header.frame_id = frame_id;
    msg.orientation_covariance[0] = -1.0;  // no orientation estimate
    msg.angular_velocity.x = sample.omega_imu_radps.x();
    msg.angular_velocity.y = sample.omega_imu_radps.y();
    msg.angular_velocity.z = sample.omega_imu_radps.z();
    msg.linear_acceleration.x = sample.accel_imu_mps2.x();
    msg.linear_acceleration.y = sample.accel_imu_mps2.y();
    msg.linear_acceleration.z = sample.accel_imu_mps2.z();
    impl_->bag.write(topic, msg.header.stamp, msg);
}

void BagWriter::WriteOdometry(const std::string &topic, const std::string &frame_id,
                              const std::string &child_frame_id, int64_t stamp_ns,
                              const Eigen::Isometry3d &T_world_base) {
    nav_msgs::Odometry msg;
    msg.header.stamp = ToRosTime(stamp_ns);
    msg.header.frame_id = frame_id;
    msg.child_frame_id = child_frame_id;
    const Eigen::Quaterniond q(T_world_base.linear());
    msg.pose.pose.position.x = T_world_base.translation().x();
    msg.pose.pose.position.y = T_world_base.translation().y();
    msg.pose.pose.position.z = T_world_base.translation().z();
    msg.pose.pose.orientation.x = q.x();
    msg.pose.pose.orientation.y = q.y();
    msg.pose.pose.orientation.z = q.z();
    msg.pose.pose.orientation.w = q.w();
    msg.twist.covariance[0] = -1.0;
    impl_->bag.write(topic, msg.header.stamp, msg);
}

void BagWriter::Close() {
    try {
        impl_->bag.close();
    } catch (const std::exception &e) {
        throw std::runtime_error(path_ + ": cannot finish the bag: " + e.what());
    }
}

}  // namespace dorado::sim
