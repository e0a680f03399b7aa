// libFuzzer target: the rosbag2 reader (MCAP records, chunks, CDR messages; sqlite3 .db3 files) on
// arbitrary bytes, through OpenDataset and ListTopics as the commands call them. ROS1 bags are
// left out: their parser is librosbag-storage's.
#include <cstring>

#include "dorado/io/dataset.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string bytes(reinterpret_cast<const char *>(data), size);
    if (bytes.rfind("#ROSBAG", 0) == 0) return 0;
    dorado::io::DatasetConfig config;
    config.rosbag.path = dorado::fuzz::WriteTempFile("recording", bytes);
    config.rosbag.imu_topic = "/imu";
    try {
        (void)dorado::io::ListTopics(config);
        auto reader = dorado::io::OpenDataset(config);
        dorado::io::DatasetEvent event;
        while (reader->Next(event)) {
        }
    } catch (const dorado::io::DatasetError &) {
    }
    return 0;
}
