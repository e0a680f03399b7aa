// A rosbag2 recording's storage files merged into one log-time-ordered stream holding one
// message per file.
#include "dorado/io/recorded_messages.hpp"

#include <map>

#include "readers.hpp"
#include "rosbag2_storage.hpp"

namespace dorado::io {
namespace {

std::unique_ptr<Rosbag2Storage> OpenStorage(const std::string &file,
                                            const std::set<std::string> &selected) {
    switch (DetectBagFormat(file)) {
        case BagFormat::kSqlite3:
            return OpenSqliteStorage(file, selected);
        case BagFormat::kMcap:
            return OpenMcapStorage(file, selected);
        default:
            throw DatasetError(file + ": not a rosbag2 storage file (.db3 or .mcap)");
    }
}

class MergedStorages final : public RecordedMessages {
  public:
    explicit MergedStorages(std::vector<std::unique_ptr<Rosbag2Storage>> storages)
        : storages_(std::move(storages)), heads_(storages_.size()), live_(storages_.size()) {
        std::map<std::string, std::string> present;
        for (const auto &storage : storages_)
            for (const auto &t : storage->topics()) present.emplace(t.name, t.type);
        for (const auto &[name, type] : present) topics_.push_back({name, type});
        for (std::size_t i = 0; i < storages_.size(); ++i) Advance(i);
    }

    [[nodiscard]] const std::vector<RecordedTopic> &topics() const override { return topics_; }

    bool Next(RecordedMessage &message) override {
        // The earliest head (a problem goes first; ties go to the earlier file).
        std::size_t best = storages_.size();
        for (std::size_t i = 0; i < storages_.size(); ++i) {
            if (!live_[i]) continue;
            if (!heads_[i].problem.empty()) {
                best = i;
                break;
            }
            if (best == storages_.size() || heads_[i].log_time_ns < heads_[best].log_time_ns)
                best = i;
        }
        if (best == storages_.size()) return false;
        message = std::move(heads_[best]);
        Advance(best);
        return true;
    }

  private:
    void Advance(std::size_t i) { live_[i] = storages_[i]->Next(heads_[i]); }

    std::vector<std::unique_ptr<Rosbag2Storage>> storages_;
    std::vector<Rosbag2Message> heads_;
    std::vector<bool> live_;
    std::vector<RecordedTopic> topics_;
};

}  // namespace

std::vector<std::unique_ptr<Rosbag2Storage>> OpenRosbag2Storages(
    const std::string &path, const std::set<std::string> &selected) {
    std::vector<std::unique_ptr<Rosbag2Storage>> storages;
    for (const auto &file : Rosbag2Files(path, DetectBagFormat(path)))
        storages.push_back(OpenStorage(file, selected));
    return storages;
}

std::unique_ptr<RecordedMessages> OpenRecordedMessages(const std::string &path,
                                                       const std::set<std::string> &selected) {
    if (DetectBagFormat(path) == BagFormat::kRos1)
        throw DatasetError(path +
                           ": a ROS1 bag; only rosbag2 recordings (a folder with "
                           "metadata.yaml, .db3, .mcap) are read as ROS 2 messages");
    return std::make_unique<MergedStorages>(OpenRosbag2Storages(path, selected));
}

}  // namespace dorado::io
