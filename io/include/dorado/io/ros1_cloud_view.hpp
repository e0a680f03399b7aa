#pragma once
/// @file ros1_cloud_view.hpp
/// A ROS1 sensor_msgs/PointCloud2 seen as a CloudBufferView (no copy of the data), for the ROS1
/// bag reader and the live node. Header-only so that dorado_io's other users need no ROS headers.

#include <sensor_msgs/PointCloud2.h>

#include "dorado/io/pointcloud_decoder.hpp"

namespace dorado::io {

/// The view borrows msg.data: keep msg alive while the view is used.
[[nodiscard]] inline CloudBufferView ViewOf(const sensor_msgs::PointCloud2 &msg) {
    CloudBufferView view;
    view.height = msg.height;
    view.width = msg.width;
    view.point_step = msg.point_step;
    view.row_step = msg.row_step;
    view.is_bigendian = msg.is_bigendian;
    view.data = msg.data.data();
    view.data_size = msg.data.size();
    for (const auto &f : msg.fields) view.fields.push_back({f.name, f.offset, f.datatype, f.count});
    return view;
}

}  // namespace dorado::io
