// rosbag2's MCAP storage (.mcap, the default since ROS 2 Iron), read from the public MCAP
// specification (https://mcap.dev/spec). Hand-written because Debian ships no MCAP library; the
// decompression (libzstd, liblz4) and the CRC (zlib) are Debian's. Records are read in file order,
// one chunk in memory at a time, and a chunk's messages are given in log-time order (rosbag2 writes
// chunks in time order; a file whose chunks overlap in time shows up as "time not increasing").
// A damaged chunk (CRC, compression, sizes) is skipped with one problem; a cut-off file ends the
// stream with one problem, keeping every message before the cut.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

#include "dorado/io/dataset.hpp"
#include "mcap_records.hpp"
#include "rosbag2_storage.hpp"

namespace dorado::io {

namespace {

constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr uint64_t kRecordHead = 9;         // opcode + uint64 length
constexpr uint64_t kFooterRecord = 9 + 20;  // summary_start, summary_offset_start, summary_crc

struct McapChannel {
    std::string topic;
    uint16_t schema_id = 0;
};

class McapStorage final : public Rosbag2Storage {
  public:
    McapStorage(const std::string &path, const std::set<std::string> &selected)
        : path_(path), selected_(selected), file_(std::fopen(path.c_str(), "rb")) {
        std::error_code ec;
        size_ = std::filesystem::file_size(path, ec);
        uint8_t magic[8] = {};
        if (!file_ || ec || !ReadAt(0, magic, 8) || std::memcmp(magic, kMagic, 8) != 0) {
            if (file_) std::fclose(file_);
            throw DatasetError(path + ": cannot open as MCAP (no MCAP magic at the start)");
        }
        if (!ReadSummaryChannels()) ScanForChannels();
        std::map<std::string, std::string> types;
        for (const auto &[id, channel] : channels_) {
            const auto schema = schemas_.find(channel.schema_id);
            types.emplace(channel.topic, schema == schemas_.end() ? "" : schema->second);
        }
        for (const auto &[name, type] : types) topics_.push_back({name, type});
    }

    ~McapStorage() override {
        if (file_) std::fclose(file_);
    }

    [[nodiscard]] const std::vector<Rosbag2Topic> &topics() const override { return topics_; }

    bool Next(Rosbag2Message &message) override {
        while (true) {
            if (next_pending_ < pending_.size()) {
                message = std::move(pending_[next_pending_++]);
                return true;
            }
            if (ended_) return false;
            message = Rosbag2Message{};
            if (ReadRecord(message)) return true;
        }
    }

  private:
    bool ReadAt(uint64_t offset, uint8_t *out, uint64_t n) {
        if (offset > size_ || n > size_ - offset) return false;
        return fseeko(file_, static_cast<off_t>(offset), SEEK_SET) == 0 &&
               std::fread(out, 1, n, file_) == n;
    }

    /// Channels and schemas from the summary section, when the footer points to one.
    bool ReadSummaryChannels() {
        if (size_ < 8 + kFooterRecord + 8) return false;
        const uint64_t footer = size_ - 8 - kFooterRecord;
        std::vector<uint8_t> tail(kFooterRecord + 8);
        if (!ReadAt(footer, tail.data(), tail.size())) return false;
        if (tail[0] != static_cast<uint8_t>(McapOp::kFooter) ||
            std::memcmp(tail.data() + kFooterRecord, kMagic, 8) != 0)
            return false;
        McapCursor foot(tail.data() + kRecordHead, 20);
        const uint64_t summary_start = foot.U64();
        if (summary_start == 0 || summary_start < 8 || summary_start >= footer) return false;
        std::vector<uint8_t> summary(footer - summary_start);
        if (!ReadAt(summary_start, summary.data(), summary.size())) return false;
        try {
            McapCursor records(summary.data(), summary.size());
            while (records.remaining() > 0) {
                const auto op = static_cast<uint8_t>(records.Uint(1));
                const uint64_t length = records.U64();
                McapCursor body(records.Take(length), static_cast<std::size_t>(length));
                ReadDefinition(op, body);
            }
        } catch (const McapError &) {
            channels_.clear();
            return false;
        }
        return !channels_.empty();
    }

    /// Without a summary (a file cut off before its end), one pass collects the definitions.
    void ScanForChannels() {
        scanning_ = true;
        Rosbag2Message ignored;
        while (!ended_) ReadRecord(ignored);
        scanning_ = false;
        ended_ = false;
        offset_ = 8;
        pending_.clear();
        next_pending_ = 0;
    }

    /// A Schema or Channel record; true if it was one.
    bool ReadDefinition(uint8_t op, McapCursor &body) {
        if (op == static_cast<uint8_t>(McapOp::kSchema)) {
            const uint16_t id = body.U16();
            schemas_[id] = body.String();
            return true;
        }
        if (op == static_cast<uint8_t>(McapOp::kChannel)) {
            McapChannel channel;
            const uint16_t id = body.U16();
            channel.schema_id = body.U16();
            channel.topic = body.String();
            channels_[id] = channel;
            return true;
        }
        return false;
    }

    /// Reads the record at offset_; true when it produced a message or a problem in `message`.
    bool ReadRecord(Rosbag2Message &message) {
        uint8_t head[kRecordHead];
        if (!ReadAt(offset_, head, kRecordHead)) return End(message, "before the footer");
        McapCursor h(head, kRecordHead);
        const auto op = static_cast<uint8_t>(h.Uint(1));
        const uint64_t length = h.U64();
        const uint64_t at = offset_;
        if (length > size_ - offset_ - kRecordHead)
            return End(message, "inside the record at byte " + std::to_string(offset_) + " (" +
                                    std::to_string(length) + " bytes long)");
        offset_ += kRecordHead + length;
        if (op == static_cast<uint8_t>(McapOp::kDataEnd) ||
            op == static_cast<uint8_t>(McapOp::kFooter)) {
            ended_ = true;
            return false;
        }
        const bool wanted = op == static_cast<uint8_t>(McapOp::kChunk) ||
                            op == static_cast<uint8_t>(McapOp::kSchema) ||
                            op == static_cast<uint8_t>(McapOp::kChannel) ||
                            (op == static_cast<uint8_t>(McapOp::kMessage) && !scanning_);
        if (!wanted) return false;
        record_.resize(length);
        if (!ReadAt(at + kRecordHead, record_.data(), length))
            return End(message, "with a read error");
        try {
            McapCursor body(record_.data(), record_.size());
            if (op == static_cast<uint8_t>(McapOp::kChunk)) return ReadChunk(body, at, message);
            if (ReadDefinition(op, body)) return false;
            return ReadMessage(body, message);
        } catch (const McapError &e) {
            if (scanning_) return false;
            message.problem = path_ + ": record at byte " + std::to_string(at) + " unreadable (" +
                              e.what() + "); skipped";
            return true;
        }
    }

    /// A Message record; true if it is on a selected topic.
    bool ReadMessage(McapCursor &body, Rosbag2Message &message) {
        const uint16_t channel_id = body.U16();
        body.U32();  // sequence
        message.log_time_ns = static_cast<int64_t>(body.U64());
        body.U64();  // publish_time
        const auto channel = channels_.find(channel_id);
        if (channel == channels_.end()) throw McapError("message on an undeclared channel");
        if (!selected_.empty() && !selected_.count(channel->second.topic)) return false;
        message.topic = channel->second.topic;
        const std::size_t n = body.remaining();
        const uint8_t *data = body.Take(n);
        message.data.assign(data, data + n);
        return true;
    }

    bool ReadChunk(McapCursor &body, uint64_t at, Rosbag2Message &problem) {
        body.U64();  // message_start_time
        body.U64();  // message_end_time
        const uint64_t uncompressed_size = body.U64();
        const uint32_t crc = body.U32();
        const std::string compression = body.String();
        const uint64_t size = body.U64();
        const uint8_t *records = body.Take(size);
        const std::string where = path_ + ": chunk at byte " + std::to_string(at) + ": ";
        std::vector<uint8_t> bytes;
        try {
            bytes = DecompressChunk(compression, records, size, uncompressed_size);
        } catch (const McapError &e) {
            if (scanning_) return false;
            problem.problem = where + e.what() + "; the messages in it are skipped";
            return true;
        }
        std::map<std::string, std::size_t> per_topic;
        pending_.clear();
        next_pending_ = 0;
        std::string damage;
        try {
            McapCursor inner(bytes.data(), bytes.size());
            while (inner.remaining() > 0) {
                const auto op = static_cast<uint8_t>(inner.Uint(1));
                const uint64_t length = inner.U64();
                McapCursor record(inner.Take(length), static_cast<std::size_t>(length));
                if (ReadDefinition(op, record) || scanning_) continue;
                if (op != static_cast<uint8_t>(McapOp::kMessage)) continue;
                Rosbag2Message m;
                if (ReadMessage(record, m)) {
                    ++per_topic[m.topic];
                    pending_.push_back(std::move(m));
                }
            }
        } catch (const McapError &e) {
            damage = e.what();
        }
        if (crc != 0 && McapCrc32(bytes) != crc) damage = "CRC mismatch";
        if (scanning_ || damage.empty()) {
            std::stable_sort(pending_.begin(), pending_.end(),
                             [](const Rosbag2Message &a, const Rosbag2Message &b) {
                                 return a.log_time_ns < b.log_time_ns;
                             });
            return false;
        }
        // A damaged chunk: none of its messages is trusted.
        std::string skipped;
        for (const auto &[topic, n] : per_topic)
            skipped += (skipped.empty() ? "" : ", ") + std::to_string(n) + " on " + topic;
        problem.problem = where + damage + "; its messages are skipped (" +
                          (skipped.empty() ? std::string("none readable") : skipped) + ")";
        pending_.clear();
        return true;
    }

    bool End(Rosbag2Message &message, const std::string &what) {
        ended_ = true;
        if (scanning_) return false;
        message.problem = path_ + ": the file ends at byte " + std::to_string(size_) + " " + what +
                          " (truncated?); the messages before that are kept";
        return true;
    }

    std::string path_;
    std::set<std::string> selected_;
    std::FILE *file_ = nullptr;
    uint64_t size_ = 0;
    uint64_t offset_ = 8;
    std::map<uint16_t, std::string> schemas_;
    std::map<uint16_t, McapChannel> channels_;
    std::vector<Rosbag2Topic> topics_;
    std::vector<uint8_t> record_;
    std::vector<Rosbag2Message> pending_;
    std::size_t next_pending_ = 0;
    bool scanning_ = false;
    bool ended_ = false;
};

}  // namespace

std::unique_ptr<Rosbag2Storage> OpenMcapStorage(const std::string &path,
                                                const std::set<std::string> &selected) {
    return std::make_unique<McapStorage>(path, selected);
}

}  // namespace dorado::io
