#pragma once
/// @file dataset_config.hpp
/// The dataset description (a YAML file under configs/): which reader, which topics or paths, the
/// field map, the extrinsics and the vehicle geometry. Every key: dataset_fields.hpp, listed in
/// docs/config_keys.md.

#include <string>
#include <vector>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/radar_sensor.hpp"
#include "dorado/io/config_error.hpp"
#include "dorado/io/pointcloud_decoder.hpp"

namespace dorado::io {

struct FieldRow;  // field_yaml.hpp

/// kRadarScenes and kNuScenes read those data sets' own files (radarscenes_reader.cpp,
/// nuscenes_reader.cpp): the scans, their times, the mount and the reference trajectory.
enum class ReaderKind { kRosbag, kFolder, kRadarScenes, kNuScenes };
enum class TrajectoryFormat { kTum, kKitti, kPaperCsv };
/// kNuScenesCanBus: the nuScenes CAN bus expansion's `SCENE_ms_imu.json` (nutonomy/nuscenes-devkit,
/// can_bus): a list of {utime [us], linear_accel [m/s^2], rotation_rate [rad/s], q}, 100 Hz.
enum class ImuFileFormat { kNuScenesCanBus };

struct RosbagSource {
    std::string path;                                     ///< the .bag file
    std::string radar_topic = "/hugin_raf_1/radar_data";  ///< PointCloud2 or PointCloud
    std::string imu_topic;                                ///< sensor_msgs/Imu; empty = none
    std::string
        ground_truth_topic;  ///< nav_msgs/Odometry or geometry_msgs/PoseStamped; empty = none
    /// std_msgs/Header published when the radar starts a frame (ROS1 bags only; empty = none). Each
    /// scan is stamped with the newest trigger recorded before it plus radar_trigger_offset_s,
    /// instead of its own header stamp: for drivers that leave the header stamp zero (the
    /// ti_mmwave_rospkg's) or stamp it on another clock than the IMU.
    std::string radar_trigger_topic;
    /// Added to the trigger stamp [s]: half the radar frame (its mid-exposure) is a good choice.
    double radar_trigger_offset_s = 0.0;
};

struct FolderSource {
    std::string scans_dir;           ///< one file per scan, taken in lexicographic order
    std::string extension = ".bin";  ///< ".bin" (raw little-endian columns) or ".pcd"
    std::string timestamps_file;     ///< one time [s] per line, one line per scan file
    /// For .bin: one name per column, each column a float32 ("_" = ignored), e.g. View-of-Delft
    /// [x, y, z, power, doppler, _, _]. The names are those of the field map.
    std::vector<std::string> columns;
};

/// RadarScenes (radar-scenes.com): one sequence, the scans of its four radars (or of one). Points
/// from range_sc, azimuth_sc (z = 0), Doppler from vr (raw), power from rcs; times = timestamp
/// [us]. The mounts are sensors.json's (extrinsics.T_base_radar, when given, the one radar's); the
/// reference trajectory is the h5 file's `odometry` (x_seq, y_seq, yaw_seq) unless
/// ground_truth.path is given. With sensor_id 0 every radar of sensors.json is in `radars:`
/// (radar_1 ... radar_4).
struct RadarScenesSource {
    std::string sequence_dir;  ///< holds radar_data.h5 and scenes.json; sensors.json here or above
    int sensor_id = 0;         ///< 1..4: that radar alone; 0: every radar
};

/// nuScenes: one scene's sweeps of its radar channels (or of one), binary PCD v0.7, indexed by the
/// JSON tables (scene, sample, sample_data, sensor, calibrated_sensor, ego_pose). Doppler = (x vx +
/// y vy) / hypot(x, y) from the uncompensated vx, vy; power from rcs. The mounts are
/// calibrated_sensor's (extrinsics.T_base_radar, when given, the one radar's); the reference
/// trajectory is the scene's ego poses; the IMU is DATAROOT/can_bus/SCENE_ms_imu.json (the CAN bus
/// expansion) when imu.path is not given and that file exists. With channel empty every RADAR_*
/// channel of the scene is in `radars:`, named by its channel.
struct NuScenesSource {
    std::string dataroot;  ///< holds samples/ and sweeps/ (sample_data.filename is relative to it)
    std::string version;   ///< the folder of the JSON tables under dataroot, e.g. v1.0-mini
    std::string scene;     ///< the scene's name, e.g. scene-0061
    std::string channel;   ///< one radar's channel, e.g. RADAR_FRONT; empty: every radar
};

/// One of several radars on the vehicle (the `radars:` list, reader folder): its scan files, laid
/// out as `folder:` says (extension, columns), and its mount. Read by `dorado twist` (the joint
/// twist of every radar's Doppler); `folder:` and `extrinsics:` stay the single radar that
/// `dorado odometry` and `dorado map` read. Readers radarscenes and nuscenes fill the list from the
/// data set's own files (never from YAML): each radar's sensor_id or channel, and its mount.
struct RadarStream {
    std::string name;             ///< for messages and reports, e.g. "front"
    std::string scans_dir;        ///< as folder.scans_dir
    std::string timestamps_file;  ///< as folder.timestamps_file
    Eigen::Isometry3d T_base_radar = Eigen::Isometry3d::Identity();
    int radarscenes_sensor_id = 0;  ///< reader radarscenes: the radar's sensor_id (not a key)
    std::string nuscenes_channel;   ///< reader nuscenes: the radar's channel (not a key)
};

/// What the command line chooses in a data set's own layout, over the description's keys, before
/// the data set's radars and mounts are read (`--scene`, `--sequence`). Empty: the description's.
struct DatasetChoice {
    std::string scene;     ///< reader nuscenes: a scene's name, e.g. scene-0103 (nuscenes.scene)
    std::string sequence;  ///< reader radarscenes: "105" or "sequence_105", the folder beside
                           ///< radarscenes.sequence_dir's
};

/// The IMU's samples in a file beside the scans (the `imu:` section; readers folder, radarscenes
/// and nuscenes: a recording's IMU is rosbag.imu_topic). Its mount is extrinsics.T_base_imu.
struct ImuFile {
    std::string path;  ///< empty = none
    ImuFileFormat format = ImuFileFormat::kNuScenesCanBus;
};

struct GroundTruthFile {
    std::string path;  ///< empty = none
    TrajectoryFormat format = TrajectoryFormat::kTum;
    std::string kitti_times_path;  ///< for KITTI: one time [s] per line
};

/// Where a description's relative paths were taken from (LoadDatasetConfig): --data DIR, else
/// the description's data_dir: (relative to the description's folder), else its folder.
enum class PathBase { kDescriptionFolder, kDataDirKey, kDataOption };

/// A file or folder the description names (a path key), for messages about a missing one.
struct DatasetInput {
    std::string key;      ///< dotted, e.g. folder.scans_dir, radars[1].timestamps_file
    std::string written;  ///< as the description wrote it
    std::string path;     ///< as resolved (the member's value)
};

/// Where a description's radar mount (extrinsics.T_base_radar) comes from.
enum class MountSource {
    kGiven,           ///< the description's extrinsics.T_base_radar (or its radars: list)
    kDataSet,         ///< the data set's own calibration files (readers radarscenes, nuscenes)
    kHuginDefault,    ///< a recording without a description: the paper's Hugin launch file
    kIdentityAssumed  ///< no key: the radar at the base origin, unrotated
};

struct DatasetConfig {
    std::string name;         ///< for messages and reports
    std::string config_path;  ///< the YAML file it came from (empty when built in code)
    /// The description's data_dir: (resolved; empty: none). --data DIR replaces it.
    std::string data_dir;
    PathBase path_base = PathBase::kDescriptionFolder;
    std::string path_base_dir;         ///< the folder the relative paths were taken from
    std::vector<DatasetInput> inputs;  ///< every path the description names, not a key
    ReaderKind reader = ReaderKind::kRosbag;
    RosbagSource rosbag;
    FolderSource folder;
    RadarScenesSource radarscenes;
    NuScenesSource nuscenes;
    GroundTruthFile ground_truth;
    ImuFile imu;
    FieldMap fields;
    Extrinsics extrinsics;
    VehicleGeometry vehicle;
    /// The radar's noise and Doppler ambiguity (the `radar:` section; all 0 = unknown/none).
    RadarSensorModel radar;
    /// Several radars on one vehicle (empty: one radar, `folder:` + `extrinsics:`).
    std::vector<RadarStream> radars;
    /// Where extrinsics.T_base_radar came from, for the commands to say when it was assumed.
    MountSource mount_source = MountSource::kGiven;
};

/// The description with `folder:` and `extrinsics.T_base_radar` set to radars[index]'s (to read
/// that radar's scans with OpenDataset). Throws std::out_of_range for a bad index.
[[nodiscard]] DatasetConfig ForRadar(const DatasetConfig &config, std::size_t index);

/// Reads and validates a dataset description. Relative paths are taken from @p data_dir when it
/// is given (the command line's --data DIR), else from the description's data_dir: key (itself
/// relative to the YAML file), else from the YAML file's folder. @p choice (--scene, --sequence)
/// then replaces the description's scene or sequence: a sequence is looked for beside
/// radarscenes.sequence_dir as resolved. Unknown keys (named before any missing one), wrong types,
/// out-of-range values and a choice the reader has no use for throw ConfigError naming file and
/// key. The files the paths name are not opened (but the data set's own layout files, for readers
/// radarscenes and nuscenes): RequireInputs checks them.
[[nodiscard]] DatasetConfig LoadDatasetConfig(const std::string &yaml_path,
                                              const std::string &data_dir = "",
                                              const DatasetChoice &choice = {});
/// Same, the paths resolved without --data.
[[nodiscard]] inline DatasetConfig LoadDatasetConfig(const std::string &yaml_path,
                                                     const DatasetChoice &choice) {
    return LoadDatasetConfig(yaml_path, "", choice);
}

/// The dataset a command-line argument names: a .yaml/.yml description (relative paths taken as
/// LoadDatasetConfig says, @p choice applied, every input checked by RequireInputs), or a .bag
/// read with the paper's Hugin defaults. @p data_dir: --data DIR, only for a description. Throws
/// ConfigError (also for a choice the reader has no use for).
[[nodiscard]] DatasetConfig ResolveDataset(const std::string &argument,
                                           const std::string &data_dir = "",
                                           const DatasetChoice &choice = {});
/// Same, the paths resolved without --data.
[[nodiscard]] inline DatasetConfig ResolveDataset(const std::string &argument,
                                                  const DatasetChoice &choice) {
    return ResolveDataset(argument, "", choice);
}

/// Throws ConfigError for the first input of @p config that does not exist, naming the
/// description, the key, the path as written and as resolved, the folder it was taken from (and
/// why that one), and how to change it (--data DIR or an absolute path).
void RequireInputs(const DatasetConfig &config);

/// How the description's relative paths resolve, in words ("taken from --data /x").
[[nodiscard]] std::string DescribePathBase(const DatasetConfig &config);

/// The description as YAML text (what LoadDatasetConfig reads back): the field list's keys
/// (dataset_fields.hpp) but the sections of other readers, each with its doc, and `radars:`.
[[nodiscard]] std::string DatasetConfigToYaml(const DatasetConfig &config);

/// Every key of a description with its built-in default and doc (`radars[].` a radar's).
[[nodiscard]] std::vector<FieldRow> DatasetConfigFields();

}  // namespace dorado::io
