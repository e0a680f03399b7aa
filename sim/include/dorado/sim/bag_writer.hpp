#pragma once
/// @file bag_writer.hpp
/// Writes a ROS1 bag like the paper's dataset: radar scans as sensor_msgs/PointCloud2 in the
/// Hugin layout (float32 x, y, z, range, elevation, azimuth, power, doppler), sensor_msgs/Imu and
/// the ground truth as nav_msgs/Odometry. The ROS headers stay inside bag_writer.cpp.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>

#include "dorado/core/imu.hpp"
#include "dorado/core/radar_scan.hpp"

namespace dorado::sim {

class BagWriter {
  public:
    /// Creates (overwrites) the bag; throws std::runtime_error naming the file.
    explicit BagWriter(const std::string &path);
    ~BagWriter();
    BagWriter(const BagWriter &) = delete;
    BagWriter &operator=(const BagWriter &) = delete;

    /// The scan's stamp is the header stamp and the record time.
    void WriteRadar(const std::string &topic, const RadarScan &scan);
    void WriteImu(const std::string &topic, const std::string &frame_id, const ImuSample &sample);
    /// Pose only (the twist is marked unknown, covariance -1).
    void WriteOdometry(const std::string &topic, const std::string &frame_id,
                       const std::string &child_frame_id, int64_t stamp_ns,
                       const Eigen::Isometry3d &T_world_base);
    /// Writes the index and closes; throws std::runtime_error on failure.
    void Close();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string path_;
};

}  // namespace dorado::sim
