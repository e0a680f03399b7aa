// Folders of per-scan files: raw float32 columns (.bin, as View-of-Delft and ColoRadar) or PCD
// files, with a timestamps file holding one time per scan.
#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "readers.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

std::vector<int64_t> ReadTimestamps(const std::string &path) {
    std::ifstream in(path);
    if (!in) throw DatasetError(path + ": cannot open the timestamps file");
    std::vector<int64_t> stamps;
    std::string line;
    for (std::size_t n = 1; std::getline(in, line); ++n) {
        line.erase(0, line.find_first_not_of(" \t"));
        line.erase(line.find_last_not_of(" \t\r") + 1);
        if (line.empty() || line[0] == '#') continue;
        int64_t ns = 0;
        if (!ParseSecondsToNanos(line, ns)) {
            throw DatasetError(path + ":" + std::to_string(n) + ": not a time in seconds: '" +
                               line + "'");
        }
        stamps.push_back(ns);
    }
    return stamps;
}

class FolderReader final : public DatasetReader {
  public:
    explicit FolderReader(const DatasetConfig &config)
        : config_(config),
          files_(ListScanFiles(config.folder)),
          stamps_(ReadTimestamps(config.folder.timestamps_file)) {
        if (files_.size() != stamps_.size()) {
            throw DatasetError(config.folder.timestamps_file + ": " +
                               std::to_string(stamps_.size()) + " timestamps for " +
                               std::to_string(files_.size()) + " scan files in " +
                               config.folder.scans_dir);
        }
        // Before any scan is used: a layout that most files do not fit is refused as a whole.
        if (const auto problem = CheckFolderFiles(config, files_))
            throw DatasetError(problem->message);
    }

    bool Next(DatasetEvent &event) override {
        if (next_ >= files_.size()) return false;
        event = DatasetEvent{};
        event.scan_index = next_;
        event.stamp_ns = stamps_[next_];
        const std::string &file = files_[next_++];
        try {
            event.scan = config_.folder.extension == ".pcd" ? ReadPcd(file) : ReadBin(file);
        } catch (const DecodeError &e) {
            event.kind = DatasetEvent::Kind::kBadScan;
            event.problem = file + " (scan " + std::to_string(event.scan_index) + "): " + e.what();
            return true;
        }
        event.kind = DatasetEvent::Kind::kRadarScan;
        event.scan.stamp_ns = event.stamp_ns;
        event.scan.frame_id = "radar";
        event.removed_nonfinite_points = RemoveNonFinitePoints(event.scan);
        return true;
    }

    [[nodiscard]] std::string source() const override { return config_.folder.scans_dir; }

  private:
    RadarScan ReadBin(const std::string &file) const {
        std::ifstream in(file, std::ios::binary);
        if (!in) throw DecodeError("cannot open");
        const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
        return DecodeFloat32Columns(bytes.data(), bytes.size(), config_.folder.columns,
                                    config_.fields);
    }

    RadarScan ReadPcd(const std::string &file) const {
        pcl::PCLPointCloud2 cloud;
        pcl::PCDReader reader;
        if (reader.read(file, cloud) < 0) throw DecodeError("not a readable PCD file");
        CloudBufferView view;
        view.height = cloud.height;
        view.width = cloud.width;
        view.point_step = cloud.point_step;
        view.row_step = cloud.row_step;
        view.is_bigendian = cloud.is_bigendian != 0;
        view.data = cloud.data.data();
        view.data_size = cloud.data.size();
        for (const auto &f : cloud.fields)
            view.fields.push_back({f.name, f.offset, f.datatype, f.count});
        return DecodePointCloud(view, config_.fields);
    }

    DatasetConfig config_;
    std::vector<std::string> files_;
    std::vector<int64_t> stamps_;
    std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<DatasetReader> OpenFolderReader(const DatasetConfig &config) {
    return std::make_unique<FolderReader>(config);
}

}  // namespace dorado::io
