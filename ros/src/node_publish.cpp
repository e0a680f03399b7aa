// dorado_ros's outputs per scan (REP 105): /doppler_odom and TF odom -> base_link, the smooth
// Doppler odometry; /dorado/map_odom and TF map -> odom, the mapper's pose and its correction, so
// that map -> odom -> base_link composed from TF is /dorado/map_odom's pose.
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>

#include "dorado_node.hpp"
#include "ros_messages.hpp"

namespace dorado::ros_node {
namespace {

geometry_msgs::TransformStamped TransformOf(const std_msgs::Header &header,
                                            const std::string &child, const Eigen::Isometry3d &T) {
    geometry_msgs::TransformStamped tf;
    tf.header = header;
    tf.child_frame_id = child;
    const Eigen::Quaterniond q(T.linear());
    tf.transform.translation.x = T.translation().x();
    tf.transform.translation.y = T.translation().y();
    tf.transform.translation.z = T.translation().z();
    tf.transform.rotation.x = q.x();
    tf.transform.rotation.y = q.y();
    tf.transform.rotation.z = q.z();
    tf.transform.rotation.w = q.w();
    return tf;
}

}  // namespace

Matrix6d MapPoseCovariance(const Eigen::Isometry3d &T_map_base,
                           const Eigen::Isometry3d &T_base_child, const Matrix6d &C_base) {
    // T_true = T_map_base Exp([rho; phi]) (the mapper's convention, base frame). The child's
    // position error in the map frame is R rho - [R t_base_child]x R phi and its rotation error
    // about the map's axes R phi (nav_msgs/Odometry: x, y, z, rotation about X, Y, Z).
    const Eigen::Matrix3d R = T_map_base.linear();
    Matrix6d J = Matrix6d::Zero();
    J.topLeftCorner<3, 3>() = R;
    J.topRightCorner<3, 3>() = -Hat(R * T_base_child.translation()) * R;
    J.bottomRightCorner<3, 3>() = R;
    return J * C_base * J.transpose();
}

void DoradoNode::PublishWritten(const std::vector<mapping::WrittenPose> &written) {
    if (!settings_.front_end.run_mapper) return;
    for (const mapping::WrittenPose &w : written) {
        nav_msgs::Odometry odom;
        odom.header.stamp.fromNSec(static_cast<uint64_t>(w.stamp_ns));
        odom.header.frame_id = settings_.map_frame;
        odom.child_frame_id = settings_.tf_to_frame;
        // The covariance is the written motion's from the previous written pose (covariance.md).
        FillOdometry(w.T_world_base * settings_.T_base_child,
                     MapPoseCovariance(w.T_world_base, settings_.T_base_child, w.covariance),
                     Twist{}, odom);
        smoothed_odom_pub_.publish(odom);
    }
}

void DoradoNode::Publish(const std_msgs::Header &header, const RadarScan &scan,
                         const frontend::FrontEndResult &result) {
    std_msgs::Header odom_header = header;
    odom_header.frame_id = settings_.tf_from_frame;
    const Eigen::Isometry3d &T_base_child = settings_.T_base_child;
    const Twist twist_child = TwistAt(result.twist_base, T_base_child);
    const Eigen::Isometry3d T_odom_child = result.T_world_base_odometry * T_base_child;

    nav_msgs::Odometry odom;
    odom.header = odom_header;
    odom.child_frame_id = settings_.tf_to_frame;
    FillOdometry(T_odom_child, pose_covariance_.covariance(), twist_child, odom);
    odom_pub_.publish(odom);
    if (settings_.publish_tf)
        tf_broadcaster_.sendTransform(
            TransformOf(odom_header, settings_.tf_to_frame, T_odom_child));
    ++published_;
    if (!settings_.front_end.run_mapper) return;

    // The mapper's newest (filtered) pose in the map frame, with its covariance (given the map,
    // see mapping::RegistrationResult::covariance), and map -> odom = T_map_base T_odom_base^-1.
    // With loop closure the map frame is the corrected one: T_map_base = C T_world_base, C the
    // loop closer's newest correction (read, never waited for: loop_worker.hpp).
    PublishWritten(result.registration.written);
    if (loops_) loops_->Push(result.registration.written);
    std_msgs::Header map_header = header;
    map_header.frame_id = settings_.map_frame;
    const Eigen::Isometry3d T_map_base =
        loops_ ? Eigen::Isometry3d(loops_->Correction() * result.T_world_base)
               : result.T_world_base;
    nav_msgs::Odometry map_odom;
    map_odom.header = map_header;
    map_odom.child_frame_id = settings_.tf_to_frame;
    FillOdometry(T_map_base * T_base_child,
                 MapPoseCovariance(T_map_base, T_base_child, result.registration.covariance),
                 twist_child, map_odom);
    map_odom_pub_.publish(map_odom);
    if (settings_.publish_tf)
        tf_broadcaster_.sendTransform(
            TransformOf(map_header, settings_.tf_from_frame,
                        T_map_base * result.T_world_base_odometry.inverse()));
    if (result.static_mask.size() == scan.size()) {
        if (static_pub_.getNumSubscribers() > 0)
            static_pub_.publish(MakeCloud(header, scan, result.static_mask, true));
        if (dynamic_pub_.getNumSubscribers() > 0)
            dynamic_pub_.publish(MakeCloud(header, scan, result.static_mask, false));
    }
    const mapping::LocalMap *map = front_end_.local_map();
    if (map && local_map_pub_.getNumSubscribers() > 0 &&
        std::chrono::duration<double>(Clock::now() - last_local_map_).count() >=
            settings_.local_map_period_s) {
        last_local_map_ = Clock::now();
        local_map_pub_.publish(MakeCloud(map_header, map->Points()));
    }
}

}  // namespace dorado::ros_node
