// rosbag2's sqlite3 storage (.db3, the default up to ROS 2 Humble) through Debian's libsqlite3.
// Schema (rosbag2_storage_default_plugins): topics(id, name, type, serialization_format, ...),
// messages(id, topic_id, timestamp, data). Messages are streamed one row at a time in timestamp
// order (the recorder's timestamp_idx makes that an index walk, not a sort).
#include <sqlite3.h>

#include <map>

#include "dorado/io/dataset.hpp"
#include "rosbag2_storage.hpp"

namespace dorado::io {

namespace {

class SqliteStorage final : public Rosbag2Storage {
  public:
    SqliteStorage(const std::string &path, const std::set<std::string> &selected) : path_(path) {
        if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
            Fail("cannot open as sqlite3");
        }
        // A recording cut off (disk full, power loss) is shorter than its header says, which
        // sqlite refuses as "malformed" unless the schema is writable; the connection stays
        // read-only, so this only lets the pages that survive be read.
        sqlite3_exec(db_, "PRAGMA writable_schema=ON", nullptr, nullptr, nullptr);
        ReadTopics();
        std::string ids;
        for (const auto &[id, topic] : topic_of_id_) {
            if (!selected.empty() && !selected.count(topic)) continue;
            ids += (ids.empty() ? "" : ",") + std::to_string(id);
        }
        const std::string sql =
            "SELECT topic_id, timestamp, data FROM messages WHERE topic_id IN (" + ids +
            ") ORDER BY timestamp, id";
        if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &messages_, nullptr) != SQLITE_OK)
            Fail("no readable messages table in the");
    }

    ~SqliteStorage() override {
        sqlite3_finalize(messages_);
        sqlite3_close(db_);
    }

    [[nodiscard]] const std::vector<Rosbag2Topic> &topics() const override { return topics_; }

    bool Next(Rosbag2Message &message) override {
        if (done_) return false;
        message = Rosbag2Message{};
        const int rc = sqlite3_step(messages_);
        if (rc == SQLITE_DONE) {
            done_ = true;
            return false;
        }
        if (rc != SQLITE_ROW) {
            // A damaged or cut-off database: what was read so far stays used.
            done_ = true;
            message.problem = path_ + ": sqlite3 error after " + std::to_string(count_) +
                              " messages (" + sqlite3_errmsg(db_) +
                              "; truncated or corrupt?); the rest of this file is skipped";
            return true;
        }
        ++count_;
        const auto topic = topic_of_id_.find(sqlite3_column_int64(messages_, 0));
        message.topic = topic == topic_of_id_.end() ? std::string("?") : topic->second;
        message.log_time_ns = sqlite3_column_int64(messages_, 1);
        const auto *blob = static_cast<const uint8_t *>(sqlite3_column_blob(messages_, 2));
        const int size = sqlite3_column_bytes(messages_, 2);
        if (blob != nullptr && size > 0) message.data.assign(blob, blob + size);
        return true;
    }

  private:
    /// Only called from the constructor: closes what it opened (no destructor runs), then throws.
    [[noreturn]] void Fail(const std::string &what) {
        const std::string message = path_ + ": " + what + " rosbag2 storage (" +
                                    (db_ ? sqlite3_errmsg(db_) : "out of memory") +
                                    "; truncated or not a .db3?)";
        sqlite3_finalize(messages_);
        sqlite3_close(db_);
        db_ = nullptr;
        messages_ = nullptr;
        throw DatasetError(message);
    }

    void ReadTopics() {
        sqlite3_stmt *stmt = nullptr;
        if (sqlite3_prepare_v2(db_, "SELECT id, name, type FROM topics ORDER BY id", -1, &stmt,
                               nullptr) != SQLITE_OK) {
            Fail("no readable topics table in the");
        }
        int rc = SQLITE_ROW;
        while ((rc = sqlite3_step(stmt)) == SQLITE_ROW) {
            const auto *name = sqlite3_column_text(stmt, 1);
            const auto *type = sqlite3_column_text(stmt, 2);
            Rosbag2Topic topic{name ? reinterpret_cast<const char *>(name) : "",
                               type ? reinterpret_cast<const char *>(type) : ""};
            topic_of_id_[sqlite3_column_int64(stmt, 0)] = topic.name;
            topics_.push_back(std::move(topic));
        }
        sqlite3_finalize(stmt);
        if (rc != SQLITE_DONE) Fail("unreadable topics table in the");
    }

    std::string path_;
    sqlite3 *db_ = nullptr;
    sqlite3_stmt *messages_ = nullptr;
    std::vector<Rosbag2Topic> topics_;
    std::map<int64_t, std::string> topic_of_id_;
    bool done_ = false;
    std::size_t count_ = 0;
};

}  // namespace

std::unique_ptr<Rosbag2Storage> OpenSqliteStorage(const std::string &path,
                                                  const std::set<std::string> &selected) {
    return std::make_unique<SqliteStorage>(path, selected);
}

}  // namespace dorado::io
