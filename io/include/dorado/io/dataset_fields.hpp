#pragma once
/// @file dataset_fields.hpp
/// The dataset description's field list (`VisitFields`, core/config_fields.hpp): every key of a
/// dataset YAML once, with its doc. LoadDatasetConfig reads it, DatasetConfigToYaml writes it and
/// `dorado config keys` lists it. The `radars:` list has a reader of its own; each radar's keys
/// are the RadarStream list below.

#include "dorado/core/config_fields.hpp"
#include "dorado/io/dataset_config.hpp"

namespace dorado {

inline Choices<VehicleModel> VehicleModelChoices() {
    return {{"ackermann", VehicleModel::kAckermann},
            {"skid_steer", VehicleModel::kSkidSteer},
            {"unconstrained", VehicleModel::kUnconstrained}};
}
inline Choices<ScanGeometry> ScanGeometryChoices() {
    return {{"auto", ScanGeometry::kAuto},
            {"3d", ScanGeometry::k3d},
            {"planar", ScanGeometry::kPlanar}};
}

template <typename Visitor>
void VisitFields(KinematicModelNoise &c, Visitor &&v) {
    v("sigma_icr_x_m", c.sigma_icr_x_m, "1-sigma wander of the Z-ICR along x [m] (>= 0)");
    v("rear_slip_rad_per_mps2", c.rear_slip_rad_per_mps2,
      "rear-axle slip angle per lateral acceleration [rad/(m/s^2)] (>= 0)");
    v("sigma_lateral_mps", c.sigma_lateral_mps, "1-sigma lateral velocity at the ICR [m/s] (>= 0)");
    v("sigma_vertical_mps", c.sigma_vertical_mps, "1-sigma vertical velocity [m/s] (>= 0)");
    v("sigma_roll_rate_radps", c.sigma_roll_rate_radps, "1-sigma roll rate [rad/s] (>= 0)");
    v("angular_rate_prior_sigma_radps", c.angular_rate_prior_sigma_radps,
      "spread of the angular-rate prior, x y z [rad/s] (> 0)");
}

template <typename Visitor>
void VisitFields(VehicleVelocityPrior &c, Visitor &&v) {
    v("enabled", c.enabled, "the ground vehicle's constraint on the ego-velocity");
    v("sigma_lateral_mps", c.sigma_lateral_mps, "its lateral spread [m/s] (> 0)");
    v("sigma_vertical_mps", c.sigma_vertical_mps, "its vertical spread [m/s] (> 0)");
}

template <typename Visitor>
void VisitFields(VehicleGeometry &c, Visitor &&v) {
    v("model", c.model, VehicleModelChoices(), "the platform's kinematic constraint");
    v("half_wheelbase_m", c.half_wheelbase_m,
      "m: the Y-ICR axis ahead of the base origin [m] (>= 0; 0 for skid_steer)");
    v("base_height_m", c.base_height_m,
      "the base origin's height above the road [m] (0, 10); absent: unknown");
    VisitFields(c.model_noise, Prefixed{"model_noise.", v});
    VisitFields(c.velocity_prior, Prefixed{"velocity_prior.", v});
}

template <typename Visitor>
void VisitFields(RadarSensorModel &c, Visitor &&v) {
    v("range_sigma_m", c.range_sigma_m, "1-sigma range noise [m] in [0, 100); 0: unknown");
    v("azimuth_sigma_deg", c.azimuth_sigma_deg, "1-sigma azimuth noise [deg] in [0, 20)");
    v("elevation_sigma_deg", c.elevation_sigma_deg, "1-sigma elevation noise [deg] in [0, 20)");
    v("doppler_unambiguous_mps", c.doppler_unambiguous_mps,
      "Doppler wraps into [-v, v) [m/s] in [0, 1000); 0: no aliasing");
    v("geometry", c.geometry, ScanGeometryChoices(), "the scan's geometry");
}

template <typename Visitor>
void VisitFields(Extrinsics &c, Visitor &&v) {
    v("T_base_radar", c.T_base_radar,
      "the radar's mount: translation_m, rotation_rpy_deg or quaternion_xyzw; absent: the data "
      "set's own (radarscenes, nuscenes)");
    v("T_base_imu", c.T_base_imu, "the IMU's mount");
}

namespace io {

inline Choices<ReaderKind> ReaderKindChoices() {
    return {{"rosbag", ReaderKind::kRosbag},
            {"folder", ReaderKind::kFolder},
            {"radarscenes", ReaderKind::kRadarScenes},
            {"nuscenes", ReaderKind::kNuScenes}};
}
inline Choices<TrajectoryFormat> TrajectoryFormatChoices() {
    return {{"tum", TrajectoryFormat::kTum},
            {"kitti", TrajectoryFormat::kKitti},
            {"paper_csv", TrajectoryFormat::kPaperCsv}};
}
inline Choices<ImuFileFormat> ImuFileFormatChoices() {
    return {{"nuscenes_can_bus", ImuFileFormat::kNuScenesCanBus}};
}

template <typename Visitor>
void VisitFields(RosbagSource &c, Visitor &&v) {
    v("path", c.path, kPath, "the .bag, .db3 or .mcap recording (required for reader rosbag)");
    v("radar_topic", c.radar_topic, "PointCloud2 or PointCloud");
    v("imu_topic", c.imu_topic, "sensor_msgs/Imu; empty: none");
    v("ground_truth_topic", c.ground_truth_topic,
      "nav_msgs/Odometry or geometry_msgs/PoseStamped; empty: none");
    v("radar_trigger_topic", c.radar_trigger_topic,
      "std_msgs/Header at each frame's start (ROS1): scans stamped by it; empty: none");
    v("radar_trigger_offset_s", c.radar_trigger_offset_s,
      "added to the trigger stamp [s] in (-1, 1)");
}

template <typename Visitor>
void VisitFields(FolderSource &c, Visitor &&v) {
    v("scans_dir", c.scans_dir, kPath, "one file per scan, in lexicographic order");
    v("extension", c.extension, "the scan files' extension: .bin or .pcd");
    v("timestamps_file", c.timestamps_file, kPath, "one time [s] per line, one line per scan");
    v("columns", c.columns, ".bin: one field name per float32 column (_ = ignored)");
}

template <typename Visitor>
void VisitFields(RadarScenesSource &c, Visitor &&v) {
    v("sequence_dir", c.sequence_dir, kPath, "holds radar_data.h5 and scenes.json");
    v("sensor_id", c.sensor_id, "1..4: that radar alone; 0: every radar (the radars: list)");
}

template <typename Visitor>
void VisitFields(NuScenesSource &c, Visitor &&v) {
    v("dataroot", c.dataroot, kPath, "holds samples/ and sweeps/");
    v("version", c.version, "the JSON tables' folder under dataroot, e.g. v1.0-mini");
    v("scene", c.scene, "the scene's name, e.g. scene-0061 (--scene NAME reads another)");
    v("channel", c.channel,
      "one radar's channel, e.g. RADAR_FRONT; empty: every RADAR_* channel (the radars: list)");
}

template <typename Visitor>
void VisitFields(GroundTruthFile &c, Visitor &&v) {
    v("path", c.path, kPath, "the reference trajectory; empty: none");
    v("format", c.format, TrajectoryFormatChoices(), "its format");
    v("kitti_times", c.kitti_times_path, kPath, "kitti: one time [s] per line");
}

template <typename Visitor>
void VisitFields(ImuFile &c, Visitor &&v) {
    v("path", c.path, kPath, "the IMU's samples beside the scans; empty: none");
    v("format", c.format, ImuFileFormatChoices(), "their format");
}

template <typename Visitor>
void VisitFields(FieldMap &c, Visitor &&v) {
    v("x", c.x, "the point's x field (required)");
    v("y", c.y, "y (required)");
    v("z", c.z, "z (required)");
    v("range", c.range, "range [m]");
    v("azimuth", c.azimuth, "azimuth");
    v("elevation", c.elevation, "elevation");
    v("power", c.power, "power or SNR [dB]");
    v("doppler", c.doppler, "radial velocity [m/s] (required)");
    v("doppler_sign", c.doppler_sign, "1 or -1: makes the Doppler positive = receding");
}

/// One radar of the `radars:` list (reader folder; each key required but name).
template <typename Visitor>
void VisitFields(RadarStream &c, Visitor &&v) {
    v("name", c.name, "for messages and reports; absent: radarK");
    v("scans_dir", c.scans_dir, kPath, "as folder.scans_dir");
    v("timestamps_file", c.timestamps_file, kPath, "as folder.timestamps_file");
    v("T_base_radar", c.T_base_radar, "its mount");
}

/// Every key but `radars:` (a list: LoadDatasetConfig reads each radar by RadarStream's list).
/// config_path is where the description came from, not a key.
template <typename Visitor>
void VisitFields(DatasetConfig &c, Visitor &&v) {
    v("name", c.name, "for messages and reports; absent: the file's name");
    v("reader", c.reader, ReaderKindChoices(), "which reader");
    // Read first: the relative paths after it are taken from it (LoadDatasetConfig).
    v("data_dir", c.data_dir, kPath,
      "the folder the other relative paths are taken from, itself relative to this file; absent: "
      "this file's folder; --data DIR replaces it");
    VisitFields(c.rosbag, Prefixed{"rosbag.", v});
    VisitFields(c.folder, Prefixed{"folder.", v});
    VisitFields(c.radarscenes, Prefixed{"radarscenes.", v});
    VisitFields(c.nuscenes, Prefixed{"nuscenes.", v});
    VisitFields(c.fields, Prefixed{"fields.", v});
    VisitFields(c.ground_truth, Prefixed{"ground_truth.", v});
    VisitFields(c.imu, Prefixed{"imu.", v});
    VisitFields(c.extrinsics, Prefixed{"extrinsics.", v});
    VisitFields(c.vehicle, Prefixed{"vehicle.", v});
    VisitFields(c.radar, Prefixed{"radar.", v});
}

}  // namespace io
}  // namespace dorado
