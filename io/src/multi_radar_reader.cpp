// OpenRadars: the `radars:` list's scans as one stream in time order: a folder reader per radar,
// merged here; the data sets' own readers (radarscenes, nuscenes) read every radar from one index.
#include <cmath>
#include <cstdio>
#include <limits>

#include "dorado/core/time.hpp"
#include "dorado/io/dataset.hpp"
#include "readers.hpp"

namespace dorado::io {
namespace {

// One radar's reader with its next event held back until it is the oldest of all.
struct PendingStream {
    std::unique_ptr<DatasetReader> reader;
    std::string name;
    DatasetEvent next;
    bool has_next = false;
};

class MultiRadarReader final : public DatasetReader {
  public:
    explicit MultiRadarReader(const DatasetConfig &config) {
        for (std::size_t k = 0; k < config.radars.size(); ++k) {
            DatasetConfig one = ForRadar(config, k);
            if (k > 0) one.imu.path.clear();  // the IMU's samples once, with the first radar
            PendingStream stream{OpenDataset(one), config.radars[k].name, {}, false};
            streams_.push_back(std::move(stream));
            Advance(k);
        }
        CheckTimeBases(config);
    }

    bool Next(DatasetEvent &event) override {
        std::size_t oldest = streams_.size();
        int64_t oldest_stamp = std::numeric_limits<int64_t>::max();
        for (std::size_t k = 0; k < streams_.size(); ++k) {
            if (!streams_[k].has_next) continue;
            const DatasetEvent &e = streams_[k].next;
            // A bad scan has no trustworthy stamp: report it at once.
            const int64_t stamp = e.kind == DatasetEvent::Kind::kBadScan
                                      ? std::numeric_limits<int64_t>::min()
                                      : e.stamp_ns;
            if (stamp < oldest_stamp) {
                oldest_stamp = stamp;
                oldest = k;
            }
        }
        if (oldest == streams_.size()) return false;
        event = std::move(streams_[oldest].next);
        event.radar = oldest;
        Advance(oldest);
        return true;
    }

    [[nodiscard]] std::string source() const override {
        std::string names;
        for (const PendingStream &s : streams_)
            names += (names.empty() ? "" : ", ") + s.reader->source();
        return names;
    }

  private:
    void Advance(std::size_t k) {
        PendingStream &s = streams_[k];
        s.has_next = s.reader->Next(s.next);
        // The other radars' own ground-truth events repeat the first's.
        while (s.has_next && k > 0 && s.next.kind == DatasetEvent::Kind::kGroundTruth)
            s.has_next = s.reader->Next(s.next);
    }

    // Each radar's first scan against the first radar's: another clock is refused by name.
    void CheckTimeBases(const DatasetConfig &config) const {
        const auto first_scan_stamp = [](const PendingStream &s) -> std::optional<int64_t> {
            if (s.has_next && s.next.kind == DatasetEvent::Kind::kRadarScan) return s.next.stamp_ns;
            return std::nullopt;
        };
        const std::optional<int64_t> reference = first_scan_stamp(streams_.front());
        if (!reference) return;
        for (std::size_t k = 1; k < streams_.size(); ++k) {
            const std::optional<int64_t> stamp = first_scan_stamp(streams_[k]);
            if (!stamp) continue;
            const double offset_s = NanosToSeconds(*stamp - *reference);
            if (std::abs(offset_s) > kMaxRadarClockOffsetS) {
                char numbers[160];
                std::snprintf(numbers, sizeof(numbers),
                              "its first scan is %.6g s from radar '%s''s first scan (more than "
                              "%.0f s: another time base?)",
                              offset_s, config.radars.front().name.c_str(), kMaxRadarClockOffsetS);
                throw DatasetError(config.config_path + ": key 'radars': radar '" +
                                   config.radars[k].name + "' (" + streams_[k].reader->source() +
                                   "): " + numbers);
            }
        }
    }

    std::vector<PendingStream> streams_;
};

// The data set's own reader over every radar of the list (one clock: no time-base check).
std::unique_ptr<DatasetReader> OpenFormatRadars(const DatasetConfig &config) {
    std::unique_ptr<DatasetReader> reader;
    if (config.reader == ReaderKind::kRadarScenes) {
        std::vector<int> sensor_ids;
        for (const RadarStream &radar : config.radars)
            sensor_ids.push_back(radar.radarscenes_sensor_id);
        reader = OpenRadarScenesReader(config, sensor_ids);
    } else {
        std::vector<std::string> channels;
        for (const RadarStream &radar : config.radars) channels.push_back(radar.nuscenes_channel);
        reader = OpenNuScenesReader(config, channels);
    }
    if (config.imu.path.empty()) return reader;
    return WithImuFile(std::move(reader), config.imu);
}

}  // namespace

std::unique_ptr<DatasetReader> OpenRadars(const DatasetConfig &config) {
    if (config.radars.size() < 2) return OpenDataset(config);
    if (config.reader == ReaderKind::kRadarScenes || config.reader == ReaderKind::kNuScenes)
        return OpenFormatRadars(config);
    return std::make_unique<MultiRadarReader>(config);
}

}  // namespace dorado::io
