#pragma once
/// @file folder_layout.hpp
/// Checks a scan folder's configured layout against the whole folder before any scan is used:
/// `.bin` files by their sizes (from the directory listing, nothing read), `.pcd` files by the
/// FIELDS line of their headers.
///
/// The rule: a folder's layout is verified when at most AllowedMisfits(files) of its files do not
/// fit it (one in a hundred, at least one). Those few are skipped one by one as unreadable scans.
/// More misfits mean that the files which do fit most likely fit by chance (a .bin of 6 float32
/// columns read as 5 fits whenever its point count is a multiple of 5): the folder is refused.
/// It is refused too when any file misfits and another count of 3 or more columns fits every
/// file: radars with a fixed point count per scan (nuScenes' 125) fit a wrong count in all but a
/// few files.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dorado/io/dataset_config.hpp"

namespace dorado::io {

/// Why a folder's files do not fit its description, and what to change.
struct FolderLayoutProblem {
    std::string message;  ///< one line: the folder, the configured layout, what fits instead
    std::string fix;      ///< e.g. "folder.columns has 5 entries; every file fits 6"
};

/// How many files of a folder may not fit its layout before the folder is refused.
[[nodiscard]] std::size_t AllowedMisfits(std::size_t files);

/// The float32 column counts in [2, 32] that every non-empty file size is a whole number of rows
/// of, largest first. Empty when no count fits or every file is empty.
[[nodiscard]] std::vector<std::size_t> ColumnCountsFittingEvery(
    const std::vector<std::uintmax_t> &sizes_bytes);

/// The .bin check on sizes alone: `names[i]` has `sizes_bytes[i]` bytes; `columns` configured.
[[nodiscard]] std::optional<FolderLayoutProblem> CheckBinColumns(
    const std::string &folder, const std::vector<std::string> &names,
    const std::vector<std::uintmax_t> &sizes_bytes, std::size_t columns);

/// The check for a folder dataset (nothing for other readers). Throws DatasetError when the folder
/// cannot be listed.
[[nodiscard]] std::optional<FolderLayoutProblem> CheckFolderLayout(const DatasetConfig &config);

}  // namespace dorado::io
