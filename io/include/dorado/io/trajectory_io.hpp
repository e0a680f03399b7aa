#pragma once
/// @file trajectory_io.hpp
/// Trajectory files: TUM (`t x y z qx qy qz qw`), KITTI (3x4 row-major per line, times in a
/// separate file) and the paper dataset's CSV (`sec,nsec,x,y,z,qx,qy,qz,qw`). Written files are
/// readable by evo unchanged; every write is atomic (temporary file, then rename).

#include <stdexcept>
#include <string>

#include "dorado/core/trajectory.hpp"

namespace dorado::io {

/// A malformed trajectory file: the message names the file and the line.
class TrajectoryFileError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

[[nodiscard]] Trajectory ReadTum(const std::string &path);
void WriteTum(const std::string &path, const Trajectory &trajectory);

[[nodiscard]] Trajectory ReadKitti(const std::string &poses_path, const std::string &times_path);
void WriteKitti(const std::string &poses_path, const std::string &times_path,
                const Trajectory &trajectory);

[[nodiscard]] Trajectory ReadPaperCsv(const std::string &path);
void WritePaperCsv(const std::string &path, const Trajectory &trajectory);

}  // namespace dorado::io
