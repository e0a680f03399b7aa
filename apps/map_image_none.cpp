// map.png without OpenCV (DORADO_WITH_OPENCV=OFF or libopencv-dev absent): say so, write nothing.
#include <iostream>

#include "map_image.hpp"

namespace dorado::apps {

void WriteBirdsEyeImage(const std::string &path, const Eigen::Matrix3Xd &,
                        const std::vector<Eigen::Vector3d> &, const std::vector<Eigen::Vector3d> &,
                        const std::vector<LoopEdge> &, int) {
    std::cerr << "warning: " << path << " not written: dorado was built without OpenCV\n";
}

}  // namespace dorado::apps
