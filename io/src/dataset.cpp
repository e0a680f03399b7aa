#include "dorado/io/dataset.hpp"

#include "dorado/io/trajectory_io.hpp"
#include "readers.hpp"
#include "rosbag2_storage.hpp"

namespace dorado::io {

std::unique_ptr<DatasetReader> OpenRecordingReader(const DatasetConfig &config) {
    if (DetectBagFormat(config.rosbag.path) == BagFormat::kRos1) return OpenBagReader(config);
    return OpenRosbag2Reader(config);
}

namespace {

std::unique_ptr<DatasetReader> OpenScanReader(const DatasetConfig &config) {
    switch (config.reader) {
        case ReaderKind::kRosbag:
            return OpenRecordingReader(config);
        case ReaderKind::kFolder:
            return OpenFolderReader(config);
        case ReaderKind::kRadarScenes:
            return OpenRadarScenesReader(config, {OneRadarScenesSensor(config)});
        case ReaderKind::kNuScenes:
            return OpenNuScenesReader(config, {OneNuScenesChannel(config)});
    }
    throw DatasetError(config.config_path + ": unknown reader");
}

}  // namespace

std::unique_ptr<DatasetReader> OpenDataset(const DatasetConfig &config) {
    auto reader = OpenScanReader(config);
    if (config.imu.path.empty()) return reader;
    return WithImuFile(std::move(reader), config.imu);  // a bag's IMU is a topic (refused here)
}

std::vector<TopicSummary> ListTopics(const DatasetConfig &config) {
    if (config.reader == ReaderKind::kRosbag) {
        if (DetectBagFormat(config.rosbag.path) == BagFormat::kRos1) return ListBagTopics(config);
        return ListRosbag2Topics(config);
    }
    // One stream of scans: a folder (this validates it and its timestamps file) or a data set's own
    // files, counted by reading them; and the IMU file, when there is one.
    auto reader = OpenScanReader(config);
    TopicSummary summary;
    summary.topic = reader->source();
    switch (config.reader) {
        case ReaderKind::kRadarScenes:
            summary.type = "RadarScenes radar_data.h5";
            summary.fields = "range_sc, azimuth_sc, rcs, vr";
            break;
        case ReaderKind::kNuScenes:
            summary.type = "nuScenes radar PCD sweeps";
            summary.fields = "x, y, z, rcs, vx, vy (Doppler from vx, vy)";
            break;
        default:
            summary.type = "*" + config.folder.extension + " scan files";
            for (const auto &c : config.folder.columns)
                summary.fields += (summary.fields.empty() ? "" : ", ") + c;
    }
    DatasetEvent event;
    while (reader->Next(event)) {
        if (summary.messages++ == 0) summary.first_ns = event.stamp_ns;
        summary.last_ns = event.stamp_ns;
    }
    if (config.imu.path.empty()) return {summary};
    const std::vector<ImuSample> imu = ReadImuFile(config.imu);
    TopicSummary imu_summary;
    imu_summary.topic = config.imu.path;
    imu_summary.type = "nuScenes CAN bus ms_imu";
    imu_summary.messages = imu.size();
    imu_summary.first_ns = imu.front().stamp_ns;
    imu_summary.last_ns = imu.back().stamp_ns;
    return {summary, imu_summary};
}

std::optional<Trajectory> LoadGroundTruth(const DatasetConfig &config) {
    const GroundTruthFile &gt = config.ground_truth;
    if (!gt.path.empty()) {
        switch (gt.format) {
            case TrajectoryFormat::kTum:
                return ReadTum(gt.path);
            case TrajectoryFormat::kKitti:
                return ReadKitti(gt.path, gt.kitti_times_path);
            case TrajectoryFormat::kPaperCsv:
                return ReadPaperCsv(gt.path);
        }
    }
    if (config.reader == ReaderKind::kRadarScenes) return LoadRadarScenesOdometry(config);
    if (config.reader == ReaderKind::kNuScenes) return LoadNuScenesEgoPoses(config);
    if (config.reader != ReaderKind::kRosbag || config.rosbag.ground_truth_topic.empty())
        return std::nullopt;
    // Ground truth recorded in the bag: read only that topic.
    DatasetConfig only_gt = config;
    only_gt.rosbag.imu_topic.clear();
    auto reader = OpenRecordingReader(only_gt);
    std::vector<StampedPose> poses;
    DatasetEvent event;
    while (reader->Next(event)) {
        if (event.kind == DatasetEvent::Kind::kGroundTruth) poses.push_back(event.ground_truth);
    }
    if (poses.empty()) return std::nullopt;
    try {
        return Trajectory(std::move(poses));
    } catch (const std::invalid_argument &e) {
        throw DatasetError(config.rosbag.path + ": ground truth topic " +
                           config.rosbag.ground_truth_topic + ": " + e.what());
    }
}

}  // namespace dorado::io
