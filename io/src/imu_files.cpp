// The IMU's samples from a file beside the scans (dataset_config.hpp: ImuFile), merged into a scan
// reader's stream in time order.
//
// nuScenes CAN bus expansion (nutonomy/nuscenes-devkit, can_bus/README): `SCENE_ms_imu.json` is a
// list of records {utime [us], linear_accel [3, m/s^2], rotation_rate [3, rad/s], q [4]} at 100 Hz
// in the IMU's frame (x forward, z up, gravity +9.8 on z at rest: a specific force). q (the
// attitude) is not read: dorado integrates its own.
#include <nlohmann/json.hpp>

#include <cmath>
#include <deque>
#include <fstream>

#include "readers.hpp"

namespace dorado::io {

namespace {

constexpr int64_t kNanosPerMicro = 1000;

Eigen::Vector3d Vector3(const nlohmann::json &record, const char *key) {
    const auto v = record.at(key).get<std::vector<double>>();
    if (v.size() != 3)
        throw std::invalid_argument(std::string(key) + " needs 3 values, got " +
                                    std::to_string(v.size()));
    return {v[0], v[1], v[2]};
}

std::vector<ImuSample> ReadNuScenesCanBusImu(const std::string &path) {
    std::ifstream in(path);
    if (!in) throw DatasetError(path + ": cannot open the IMU file (imu.path)");
    nlohmann::json records;
    try {
        records = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception &e) {
        throw DatasetError(path + ": not valid JSON (a truncated file?): " + e.what());
    }
    if (!records.is_array())
        throw DatasetError(path + ": not a list of ms_imu records (nuScenes CAN bus layout)");
    std::vector<ImuSample> samples;
    samples.reserve(records.size());
    for (std::size_t i = 0; i < records.size(); ++i) {
        const std::string where = path + ": record " + std::to_string(i);
        ImuSample sample;
        try {
            sample.stamp_ns = records[i].at("utime").get<int64_t>() * kNanosPerMicro;
            sample.omega_imu_radps = Vector3(records[i], "rotation_rate");
            sample.accel_imu_mps2 = Vector3(records[i], "linear_accel");
        } catch (const nlohmann::json::exception &e) {
            throw DatasetError(where + ": " + e.what());
        } catch (const std::invalid_argument &e) {
            throw DatasetError(where + ": " + e.what());
        }
        if (!samples.empty() && sample.stamp_ns <= samples.back().stamp_ns) {
            throw DatasetError(where + ": utime " + std::to_string(sample.stamp_ns / 1000) +
                               " us is not after the previous record's " +
                               std::to_string(samples.back().stamp_ns / 1000) +
                               " us (records must be in time order)");
        }
        samples.push_back(sample);
    }
    if (samples.empty()) throw DatasetError(path + ": no IMU record");
    return samples;
}

// The scan reader's events with the file's IMU samples between them: each sample goes out before
// the first scan stamped after it (the order a recording would have).
class ImuMergingReader final : public DatasetReader {
  public:
    ImuMergingReader(std::unique_ptr<DatasetReader> scans, std::vector<ImuSample> imu)
        : scans_(std::move(scans)), imu_(imu.begin(), imu.end()) {}

    bool Next(DatasetEvent &event) override {
        if (!pending_ && !scans_done_) {
            pending_.emplace();
            if (!scans_->Next(*pending_)) {
                pending_.reset();
                scans_done_ = true;
            }
        }
        // A bad scan has no trustworthy stamp: it goes out as it comes.
        const bool scan_first =
            pending_ && (imu_.empty() || pending_->kind == DatasetEvent::Kind::kBadScan ||
                         pending_->stamp_ns < imu_.front().stamp_ns);
        if (scan_first) {
            event = std::move(*pending_);
            pending_.reset();
            return true;
        }
        if (imu_.empty()) return false;
        event = DatasetEvent{};
        event.kind = DatasetEvent::Kind::kImu;
        event.imu = imu_.front();
        event.stamp_ns = event.imu.stamp_ns;
        imu_.pop_front();
        return true;
    }

    [[nodiscard]] std::string source() const override { return scans_->source(); }

  private:
    std::unique_ptr<DatasetReader> scans_;
    std::deque<ImuSample> imu_;
    std::optional<DatasetEvent> pending_;
    bool scans_done_ = false;
};

}  // namespace

std::vector<ImuSample> ReadImuFile(const ImuFile &file) {
    switch (file.format) {
        case ImuFileFormat::kNuScenesCanBus:
            return ReadNuScenesCanBusImu(file.path);
    }
    throw DatasetError(file.path + ": unknown IMU file format");
}

std::unique_ptr<DatasetReader> WithImuFile(std::unique_ptr<DatasetReader> scans,
                                           const ImuFile &file) {
    return std::make_unique<ImuMergingReader>(std::move(scans), ReadImuFile(file));
}

}  // namespace dorado::io
