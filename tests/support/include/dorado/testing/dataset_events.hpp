#pragma once
/// Every event of a dataset, read the way the apps read it (OpenDataset, then Next until the end).

#include <string>
#include <vector>

#include "dorado/io/dataset.hpp"

namespace dorado::testing {

inline std::vector<io::DatasetEvent> ReadAllEvents(const io::DatasetConfig &config) {
    auto reader = io::OpenDataset(config);
    std::vector<io::DatasetEvent> events;
    io::DatasetEvent event;
    while (reader->Next(event)) events.push_back(event);
    return events;
}

/// The message of the DatasetError that opening or reading the whole stream throws ("" when none).
inline std::string ReadAllEventsError(const io::DatasetConfig &config) {
    try {
        (void)ReadAllEvents(config);
    } catch (const io::DatasetError &e) {
        return e.what();
    }
    return "";
}

}  // namespace dorado::testing
