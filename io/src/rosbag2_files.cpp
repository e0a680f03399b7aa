// Which format a recording is (from its bytes), and the storage files of a rosbag2 folder (from
// its metadata.yaml, through yaml-cpp).
#include <yaml-cpp/yaml.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "dorado/io/dataset.hpp"
#include "rosbag2_storage.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

BagFormat DetectBagFormat(const std::string &path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        if (fs::exists(fs::path(path) / "metadata.yaml", ec)) return BagFormat::kRosbag2Folder;
        throw DatasetError(path +
                           ": a folder without metadata.yaml is not a rosbag2 recording (`ros2 bag "
                           "reindex` rebuilds it; or name one .db3 or .mcap file in it)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw DatasetError(path + ": cannot open");
    char head[16] = {};
    in.read(head, sizeof(head));
    const auto n = static_cast<std::size_t>(in.gcount());
    auto starts = [&](const char *magic, std::size_t size) {
        return n >= size && std::memcmp(head, magic, size) == 0;
    };
    if (starts("#ROSBAG V2.0", 12)) return BagFormat::kRos1;
    if (starts("SQLite format 3\0", 16)) return BagFormat::kSqlite3;
    if (starts("\x89MCAP0\r\n", 8)) return BagFormat::kMcap;
    throw DatasetError(path + (n == 0 ? ": the file is empty" : ": unrecognised first bytes") +
                       "; expected a ROS1 bag, a rosbag2 .db3 (sqlite3) or an .mcap");
}

std::vector<std::string> Rosbag2Files(const std::string &path, BagFormat format) {
    if (format != BagFormat::kRosbag2Folder) return {path};
    const std::string metadata = (fs::path(path) / "metadata.yaml").string();
    std::vector<std::string> files;
    try {
        const YAML::Node list =
            YAML::LoadFile(metadata)["rosbag2_bagfile_information"]["relative_file_paths"];
        if (!list || !list.IsSequence() || list.size() == 0)
            throw DatasetError(metadata + ": no rosbag2_bagfile_information.relative_file_paths");
        for (const auto &entry : list) {
            fs::path file = fs::path(path) / entry.as<std::string>();
            // Some ROS 2 releases wrote the paths with the folder's own name in front.
            const fs::path beside = fs::path(path).parent_path() / entry.as<std::string>();
            std::error_code ec;
            if (!fs::exists(file, ec) && fs::exists(beside, ec)) file = beside;
            if (!fs::exists(file, ec))
                throw DatasetError(metadata + ": lists " + entry.as<std::string>() +
                                   ", which is not in the folder");
            files.push_back(file.lexically_normal().string());
        }
    } catch (const YAML::Exception &e) {
        throw DatasetError(metadata + ": unreadable: " + e.what());
    }
    return files;
}

}  // namespace dorado::io
