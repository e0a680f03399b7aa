#pragma once
/// @file point_cloud_files.hpp
/// Point clouds to PCD (binary, PCL's writer) and PLY (ASCII), written atomically.

#include <Eigen/Core>
#include <string>

namespace dorado::io {

/// Writes x y z (float) columns as a binary PCD v0.7 file. Throws std::runtime_error naming the
/// file.
void WritePcd(const std::string &path, const Eigen::Matrix3Xd &points);

/// Writes x y z (float) vertices as an ASCII PLY file. Throws std::runtime_error naming the file.
void WritePly(const std::string &path, const Eigen::Matrix3Xd &points);

}  // namespace dorado::io
