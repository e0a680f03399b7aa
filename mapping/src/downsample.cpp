// PCL's voxel grid, alone in this TU (its headers are heavy).
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "registration.hpp"

namespace dorado::mapping {

Eigen::Matrix3Xd VoxelDownsample(const Eigen::Matrix3Xd &points, double voxel_m) {
    if (points.cols() == 0) return points;
    // PCL filters in float: work relative to the first point to keep the precision.
    const Eigen::Vector3d origin = points.col(0);
    pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
    cloud->reserve(points.cols());
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
        const Eigen::Vector3f p = (points.col(i) - origin).cast<float>();
        cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
    }
    pcl::VoxelGrid<pcl::PointXYZ> grid;
    grid.setInputCloud(cloud);
    const float leaf = static_cast<float>(voxel_m);
    grid.setLeafSize(leaf, leaf, leaf);
    pcl::PointCloud<pcl::PointXYZ> filtered;
    grid.filter(filtered);
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(filtered.size()));
    for (std::size_t i = 0; i < filtered.size(); ++i)
        out.col(static_cast<Eigen::Index>(i)) =
            filtered[i].getVector3fMap().cast<double>() + origin;
    return out;
}

}  // namespace dorado::mapping
