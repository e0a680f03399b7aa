#pragma once
/// @file atomic_file.hpp
/// Writing result files so that an interrupted run never leaves a truncated file that looks
/// complete.

#include <functional>
#include <ostream>
#include <string>

namespace dorado::io {

/// Writes through `write` into `path + ".tmp"`, flushes, then renames over `path`.
/// Throws std::runtime_error naming the file when it cannot be written.
void WriteFileAtomically(const std::string &path, const std::function<void(std::ostream &)> &write);

/// Renames the finished `tmp` over `path` (removing `tmp` and throwing std::runtime_error naming
/// `path` when it cannot).
void RenameIntoPlace(const std::string &tmp, const std::string &path);

/// Creates the directory (and its parents); throws std::runtime_error naming it on failure.
void MakeDirectories(const std::string &path);

}  // namespace dorado::io
