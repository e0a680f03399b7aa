#include "dorado/io/point_cloud_files.hpp"

#include "dorado/io/atomic_file.hpp"

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdio>
#include <stdexcept>

namespace dorado::io {
namespace {

pcl::PointCloud<pcl::PointXYZ> ToPcl(const Eigen::Matrix3Xd &points) {
    pcl::PointCloud<pcl::PointXYZ> cloud;
    cloud.resize(static_cast<std::size_t>(points.cols()));
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
        cloud[static_cast<std::size_t>(i)].getVector3fMap() = points.col(i).cast<float>();
    }
    cloud.width = static_cast<std::uint32_t>(points.cols());
    cloud.height = 1;
    cloud.is_dense = true;
    return cloud;
}

// PCL writes to a path: write a temporary file next to it, then rename it into place.
template <typename Write>
void WriteAtomically(const std::string &path, Write write) {
    const std::string tmp = path + ".tmp";
    if (write(tmp) != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error(path + ": cannot write the point cloud");
    }
    RenameIntoPlace(tmp, path);
}

}  // namespace

void WritePcd(const std::string &path, const Eigen::Matrix3Xd &points) {
    const auto cloud = ToPcl(points);
    WriteAtomically(path, [&](const std::string &tmp) {
        // PCL refuses an empty cloud in binary mode: an empty map is a valid ASCII PCD.
        return cloud.empty() ? pcl::io::savePCDFileASCII(tmp, cloud)
                             : pcl::io::savePCDFileBinary(tmp, cloud);
    });
}

void WritePly(const std::string &path, const Eigen::Matrix3Xd &points) {
    const auto cloud = ToPcl(points);
    WriteAtomically(path, [&](const std::string &tmp) {
        pcl::PLYWriter writer;
        return writer.write(tmp, cloud, /*binary=*/false, /*use_camera=*/false);
    });
}

}  // namespace dorado::io
