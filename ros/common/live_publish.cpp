// The live nodes' outputs per scan (REP 105): /doppler_odom and TF odom -> base_link, the smooth
// Doppler odometry; /dorado/map_odom and TF map -> odom, the mapper's pose and its correction, so
// that map -> odom -> base_link composed from TF is /dorado/map_odom's pose.
#include <cstring>

#include "live_pipeline.hpp"
#include "output_frames.hpp"

namespace dorado::ros_node {

const char *TopicName(OdometryTopic topic) {
    switch (topic) {
        case OdometryTopic::kDopplerOdom:
            return "/doppler_odom";
        case OdometryTopic::kMapOdom:
            return "/dorado/map_odom";
        case OdometryTopic::kSmoothedOdom:
            return "/dorado/smoothed_odom";
    }
    return "";
}

const char *TopicName(CloudTopic topic) {
    switch (topic) {
        case CloudTopic::kStaticPoints:
            return "/dorado/static_points";
        case CloudTopic::kDynamicPoints:
            return "/dorado/dynamic_points";
        case CloudTopic::kLocalMap:
            return "/dorado/local_map";
    }
    return "";
}

PackedCloud PackCloud(const CloudOutput &cloud) {
    PackedCloud packed;
    packed.fields = {"x", "y", "z"};
    const bool with_doppler = cloud.doppler.size() == cloud.points.cols();
    const bool with_power = cloud.power.size() == cloud.points.cols();
    if (with_doppler) packed.fields.push_back("doppler");
    if (with_power) packed.fields.push_back("power");
    packed.width = static_cast<uint32_t>(cloud.points.cols());
    packed.point_step = static_cast<uint32_t>(4 * packed.fields.size());
    packed.data.resize(static_cast<std::size_t>(packed.point_step) * packed.width);
    uint8_t *out = packed.data.data();
    for (Eigen::Index i = 0; i < cloud.points.cols(); ++i) {
        float values[5] = {static_cast<float>(cloud.points(0, i)),
                           static_cast<float>(cloud.points(1, i)),
                           static_cast<float>(cloud.points(2, i)), 0.0f, 0.0f};
        std::size_t n = 3;
        if (with_doppler) values[n++] = static_cast<float>(cloud.doppler(i));
        if (with_power) values[n++] = static_cast<float>(cloud.power(i));
        std::memcpy(out, values, 4 * n);  // little-endian host (x86_64, arm64)
        out += packed.point_step;
    }
    return packed;
}

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

namespace {

// The points of `scan` where keep == want (the static or the dynamic part).
CloudOutput SelectPoints(int64_t stamp_ns, const std::string &frame_id, const RadarScan &scan,
                         const Eigen::Array<bool, Eigen::Dynamic, 1> &keep, bool want) {
    Eigen::Index n = 0;
    for (Eigen::Index i = 0; i < keep.size(); ++i) n += keep(i) == want;
    CloudOutput cloud{stamp_ns, frame_id, Eigen::Matrix3Xd(3, n), Eigen::VectorXd(n),
                      Eigen::VectorXd(n)};
    for (Eigen::Index i = 0, j = 0; i < scan.size(); ++i) {
        if (keep(i) != want) continue;
        cloud.points.col(j) = scan.xyz_radar.col(i);
        cloud.doppler(j) = scan.doppler_mps(i);
        cloud.power(j++) = scan.power_db(i);
    }
    return cloud;
}

}  // namespace

void LivePipeline::PublishWritten(const std::vector<mapping::WrittenPose> &written) {
    if (!settings_.front_end.run_mapper) return;
    for (const mapping::WrittenPose &w : written) {
        // The covariance is the written motion's from the previous written pose (covariance.md).
        sink_.Publish(
            OdometryTopic::kSmoothedOdom,
            {w.stamp_ns, settings_.map_frame, settings_.tf_to_frame,
             w.T_world_base * settings_.T_base_child,
             MapPoseCovariance(w.T_world_base, settings_.T_base_child, w.covariance), Twist{}});
    }
}

void LivePipeline::Publish(int64_t stamp_ns, const RadarScan &scan,
                           const frontend::FrontEndResult &result) {
    const Eigen::Isometry3d &T_base_child = settings_.T_base_child;
    const Twist twist_child = TwistAt(result.twist_base, T_base_child);
    const Eigen::Isometry3d T_odom_child = result.T_world_base_odometry * T_base_child;
    sink_.Publish(OdometryTopic::kDopplerOdom,
                  {stamp_ns, settings_.tf_from_frame, settings_.tf_to_frame, T_odom_child,
                   pose_covariance_.covariance(), twist_child});
    if (settings_.publish_tf)
        sink_.Publish(TransformOutput{stamp_ns, settings_.tf_from_frame, settings_.tf_to_frame,
                                      T_odom_child});
    Increment(counts_.published);
    if (!settings_.front_end.run_mapper) return;

    // The mapper's newest (filtered) pose in the map frame, with its covariance (given the map,
    // see mapping::RegistrationResult::covariance), and map -> odom = T_map_base T_odom_base^-1.
    // With loop closure the map frame is the corrected one: T_map_base = C T_world_base, C the
    // loop closer's newest correction (read, never waited for: loop_worker.hpp).
    PublishWritten(result.registration.written);
    if (loops_) loops_->Push(result.registration.written);
    const Eigen::Isometry3d T_map_base =
        loops_ ? Eigen::Isometry3d(loops_->Correction() * result.T_world_base)
               : result.T_world_base;
    sink_.Publish(
        OdometryTopic::kMapOdom,
        {stamp_ns, settings_.map_frame, settings_.tf_to_frame, T_map_base * T_base_child,
         MapPoseCovariance(T_map_base, T_base_child, result.registration.covariance), twist_child});
    if (settings_.publish_tf)
        sink_.Publish(TransformOutput{stamp_ns, settings_.map_frame, settings_.tf_from_frame,
                                      T_map_base * result.T_world_base_odometry.inverse()});
    PublishClouds(stamp_ns, scan.frame_id, scan, result);
}

void LivePipeline::PublishClouds(int64_t stamp_ns, const std::string &radar_frame,
                                 const RadarScan &scan, const frontend::FrontEndResult &result) {
    if (result.static_mask.size() == scan.size()) {
        if (sink_.HasSubscribers(CloudTopic::kStaticPoints))
            sink_.Publish(CloudTopic::kStaticPoints,
                          SelectPoints(stamp_ns, radar_frame, scan, result.static_mask, true));
        if (sink_.HasSubscribers(CloudTopic::kDynamicPoints))
            sink_.Publish(CloudTopic::kDynamicPoints,
                          SelectPoints(stamp_ns, radar_frame, scan, result.static_mask, false));
    }
    const mapping::LocalMap *map = front_end_.local_map();
    if (map && sink_.HasSubscribers(CloudTopic::kLocalMap) &&
        std::chrono::duration<double>(Clock::now() - last_local_map_).count() >=
            settings_.local_map_period_s) {
        last_local_map_ = Clock::now();
        sink_.Publish(CloudTopic::kLocalMap,
                      CloudOutput{stamp_ns, settings_.map_frame, map->Points(), {}, {}});
    }
}

}  // namespace dorado::ros_node
