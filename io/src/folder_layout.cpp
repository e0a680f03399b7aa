#include "dorado/io/folder_layout.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dorado/io/dataset.hpp"
#include "readers.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMinColumns = 2, kMaxColumns = 32;

std::string FileName(const std::string &path) {
    return fs::path(path).filename().string();
}

// "6", "6 or 3", "6, 3 or 2"
std::string JoinCounts(const std::vector<std::size_t> &counts) {
    std::string text;
    for (std::size_t i = 0; i < counts.size(); ++i) {
        if (i > 0) text += i + 1 == counts.size() ? " or " : ", ";
        text += std::to_string(counts[i]);
    }
    return text;
}

// The FIELDS of a PCD header (empty when the file has no FIELDS line before DATA).
std::vector<std::string> PcdHeaderFields(const std::string &path) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    for (int n = 0; n < 64 && std::getline(in, line); ++n) {
        std::istringstream tokens(line);
        std::string key;
        tokens >> key;
        if (key == "DATA") break;
        if (key != "FIELDS") continue;
        std::vector<std::string> fields;
        for (std::string f; tokens >> f;) fields.push_back(f);
        return fields;
    }
    return {};
}

// The field map's names a PCD must hold, with their keys.
std::vector<std::pair<std::string, std::string>> RequiredFields(const FieldMap &map) {
    std::vector<std::pair<std::string, std::string>> named;
    for (const auto &[key, name] : {std::pair<const char *, const std::string &>{"x", map.x},
                                    {"y", map.y},
                                    {"z", map.z},
                                    {"doppler", map.doppler},
                                    {"power", map.power},
                                    {"range", map.range},
                                    {"azimuth", map.azimuth},
                                    {"elevation", map.elevation}}) {
        if (!name.empty()) named.emplace_back(std::string("fields.") + key, name);
    }
    return named;
}

std::optional<FolderLayoutProblem> CheckPcdFields(const std::string &folder,
                                                  const std::vector<std::string> &files,
                                                  const FieldMap &map) {
    std::vector<std::vector<std::string>> headers;
    headers.reserve(files.size());
    for (const auto &file : files) headers.push_back(PcdHeaderFields(file));
    for (const auto &[key, name] : RequiredFields(map)) {
        std::size_t missing = 0, example = 0;
        for (std::size_t i = 0; i < files.size(); ++i) {
            const auto &h = headers[i];
            if (std::find(h.begin(), h.end(), name) != h.end()) continue;
            if (missing++ == 0) example = i;
        }
        if (missing <= AllowedMisfits(files.size())) continue;
        std::string present;
        for (const auto &f : headers[example]) present += (present.empty() ? "" : " ") + f;
        if (present.empty()) present = "no FIELDS line";
        FolderLayoutProblem problem;
        problem.message = folder + ": " + key + " names '" + name + "', missing in " +
                          std::to_string(missing) + " of " + std::to_string(files.size()) +
                          " *.pcd files (e.g. " + FileName(files[example]) + ": " + present + ")";
        problem.fix = key + " is '" + name + "'; " + FileName(files[example]) + " has " + present;
        return problem;
    }
    return std::nullopt;
}

}  // namespace

std::size_t AllowedMisfits(std::size_t files) {
    return std::max<std::size_t>(1, files / 100);
}

std::vector<std::size_t> ColumnCountsFittingEvery(const std::vector<std::uintmax_t> &sizes_bytes) {
    std::vector<std::size_t> counts;
    if (std::all_of(sizes_bytes.begin(), sizes_bytes.end(), [](auto s) { return s == 0; }))
        return counts;
    for (std::size_t c = kMaxColumns; c >= kMinColumns; --c) {
        if (std::all_of(sizes_bytes.begin(), sizes_bytes.end(),
                        [c](std::uintmax_t s) { return s % (4 * c) == 0; }))
            counts.push_back(c);
    }
    return counts;
}

std::optional<FolderLayoutProblem> CheckBinColumns(const std::string &folder,
                                                   const std::vector<std::string> &names,
                                                   const std::vector<std::uintmax_t> &sizes_bytes,
                                                   std::size_t columns) {
    const std::uintmax_t row_bytes = 4 * columns;
    std::size_t misfits = 0, example = 0;
    for (std::size_t i = 0; i < sizes_bytes.size(); ++i) {
        if (columns > 0 && sizes_bytes[i] % row_bytes == 0) continue;
        if (misfits++ == 0) example = i;
    }
    const std::vector<std::size_t> fitting = ColumnCountsFittingEvery(sizes_bytes);
    // A few odd files are damaged ones (counted skips), unless another count of 3 or more (x, y,
    // Doppler at least) fits every file: then the count is wrong, however few files show it.
    const bool other_count_fits = std::any_of(
        fitting.begin(), fitting.end(), [&](std::size_t c) { return c >= 3 && c != columns; });
    if (misfits <= AllowedMisfits(sizes_bytes.size()) && columns > 0 &&
        !(misfits > 0 && other_count_fits))
        return std::nullopt;
    const std::string entries = "folder.columns has " + std::to_string(columns) + " entries";
    FolderLayoutProblem problem;
    problem.message = folder + ": " + entries + " but " + std::to_string(misfits) + " of " +
                      std::to_string(sizes_bytes.size()) + " *.bin files are not a whole number " +
                      "of " + std::to_string(columns) + " float32 columns (e.g. " +
                      FileName(names[example]) + ", " + std::to_string(sizes_bytes[example]) +
                      " bytes); ";
    if (fitting.empty()) {
        problem.message += "no count from 2 to 32 fits every file";
        problem.fix = entries + "; no column count fits every file (are they float32 rows?)";
    } else {
        problem.message += "every file fits " + JoinCounts(fitting) + " columns";
        problem.fix = entries + "; every file fits " + std::to_string(fitting.front());
        if (fitting.size() > 1) {
            const std::vector<std::size_t> others(fitting.begin() + 1, fitting.end());
            problem.fix += " (or " + JoinCounts(others) + ")";
        }
    }
    return problem;
}

std::vector<std::string> ListScanFiles(const FolderSource &folder) {
    std::error_code ec;
    if (!fs::is_directory(folder.scans_dir, ec))
        throw DatasetError(folder.scans_dir + ": no such folder");
    std::vector<std::string> files;
    for (const auto &entry : fs::directory_iterator(folder.scans_dir)) {
        if (entry.is_regular_file() && entry.path().extension() == folder.extension) {
            files.push_back(entry.path().string());
        }
    }
    std::sort(files.begin(), files.end());
    if (files.empty())
        throw DatasetError(folder.scans_dir + ": no *" + folder.extension + " files");
    return files;
}

std::optional<FolderLayoutProblem> CheckFolderFiles(const DatasetConfig &config,
                                                    const std::vector<std::string> &files) {
    if (config.folder.extension == ".pcd")
        return CheckPcdFields(config.folder.scans_dir, files, config.fields);
    std::vector<std::uintmax_t> sizes;
    sizes.reserve(files.size());
    for (const auto &file : files) {
        std::error_code ec;
        const std::uintmax_t size = fs::file_size(file, ec);
        if (ec) throw DatasetError(file + ": cannot read its size: " + ec.message());
        sizes.push_back(size);
    }
    return CheckBinColumns(config.folder.scans_dir, files, sizes, config.folder.columns.size());
}

std::optional<FolderLayoutProblem> CheckFolderLayout(const DatasetConfig &config) {
    if (config.reader != ReaderKind::kFolder) return std::nullopt;
    return CheckFolderFiles(config, ListScanFiles(config.folder));
}

}  // namespace dorado::io
