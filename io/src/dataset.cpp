#include "dorado/io/dataset.hpp"

#include "dorado/io/trajectory_io.hpp"
#include "readers.hpp"
#include "rosbag2_storage.hpp"

namespace dorado::io {

std::unique_ptr<DatasetReader> OpenRecordingReader(const DatasetConfig &config) {
    if (DetectBagFormat(config.rosbag.path) == BagFormat::kRos1) return OpenBagReader(config);
    return OpenRosbag2Reader(config);
}

std::unique_ptr<DatasetReader> OpenDataset(const DatasetConfig &config) {
    switch (config.reader) {
        case ReaderKind::kRosbag:
            return OpenRecordingReader(config);
        case ReaderKind::kFolder:
            return OpenFolderReader(config);
    }
    throw DatasetError(config.config_path + ": unknown reader");
}

std::vector<TopicSummary> ListTopics(const DatasetConfig &config) {
    if (config.reader == ReaderKind::kRosbag) {
        if (DetectBagFormat(config.rosbag.path) == BagFormat::kRos1) return ListBagTopics(config);
        return ListRosbag2Topics(config);
    }
    auto reader = OpenFolderReader(config);  // validates the folder and the timestamps file
    TopicSummary summary;
    summary.topic = config.folder.scans_dir;
    summary.type = "*" + config.folder.extension + " scan files";
    DatasetEvent event;
    while (reader->Next(event)) {
        if (summary.messages++ == 0) summary.first_ns = event.stamp_ns;
        summary.last_ns = event.stamp_ns;
    }
    for (const auto &c : config.folder.columns)
        summary.fields += (summary.fields.empty() ? "" : ", ") + c;
    return {summary};
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
