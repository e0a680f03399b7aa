// map.png draws the dataset's reference trajectory beside the estimate, put in the estimate's
// world by the pose at its first stamp, and a legend. The alignment is checked against a known
// transform between the two worlds; the picture by where its dark pixels are.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "map_image.hpp"
#include "reference_path.hpp"

namespace {

namespace fs = std::filesystem;
constexpr int64_t kSecond = 1'000'000'000;

// A drive along a gentle arc in the estimate's world, one pose per 0.1 s: poses k = first ..
// first + count - 1 at 10 s + 0.1 k s (k < 0 before the estimate's first scan).
dorado::Trajectory Arc(int first, int count) {
    dorado::Trajectory trajectory;
    for (int k = first; k < first + count; ++k) {
        const double t = 0.1 * k;
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = Eigen::AngleAxisd(0.05 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        T.translation() = Eigen::Vector3d(5.0 * t, 0.1 * t * t, 0.02 * t);
        trajectory.Append(10 * kSecond + k * kSecond / 10, T);
    }
    return trajectory;
}

TEST(ReferencePath, TheReferenceInAnotherWorldLandsOnTheEstimate) {
    const dorado::Trajectory estimate = Arc(0, 100);
    // The same drive recorded in another world, 2 s longer on each side.
    Eigen::Isometry3d T_ref_est = Eigen::Isometry3d::Identity();
    T_ref_est.linear() =
        Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.1, -0.2, 1.0).normalized()).toRotationMatrix();
    T_ref_est.translation() = Eigen::Vector3d(400.0, -250.0, 12.0);
    dorado::Trajectory reference;
    const dorado::Trajectory longer = Arc(-20, 140);
    for (const auto &pose : longer.poses())
        reference.Append(pose.stamp_ns, T_ref_est * pose.T_world_body);

    const auto path = dorado::apps::AlignedReferencePath(reference, estimate);
    ASSERT_EQ(path.size(), estimate.size());  // only the estimate's span
    for (std::size_t k = 0; k < path.size(); ++k)
        EXPECT_LT((path[k] - estimate[k].T_world_body.translation()).norm(), 1e-9) << k;
}

TEST(ReferencePath, NoOverlapGivesNoPath) {
    EXPECT_TRUE(dorado::apps::AlignedReferencePath(Arc(1000, 10), Arc(0, 10)).empty());
    EXPECT_TRUE(dorado::apps::AlignedReferencePath(dorado::Trajectory(), Arc(0, 10)).empty());
}

/// Pixels darker than mid-grey inside the rectangle.
int DarkPixels(const cv::Mat3b &image, const cv::Rect &rect) {
    int dark = 0;
    for (int y = rect.y; y < rect.y + rect.height; ++y) {
        for (int x = rect.x; x < rect.x + rect.width; ++x) {
            const cv::Vec3b &c = image(y, x);
            dark += c[0] + c[1] + c[2] < 3 * 100;
        }
    }
    return dark;
}

TEST(MapImage, TheReferenceIsDrawnWhereItIsAndTheLegendTopLeft) {
    const fs::path dir =
        fs::path(::testing::TempDir()) / ("dorado_map_image_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // The estimate along y = 0, the reference along y = 20 m, x from 0 to 100 m; no map points.
    std::vector<Eigen::Vector3d> estimate, reference;
    for (int k = 0; k <= 100; ++k) {
        estimate.emplace_back(k, 0.0, 0.0);
        reference.emplace_back(k, 20.0, 0.0);
    }
    const Eigen::Matrix3Xd no_points(3, 0);
    dorado::apps::WriteBirdsEyeImage((dir / "with.png").string(), no_points, estimate, reference);
    dorado::apps::WriteBirdsEyeImage((dir / "without.png").string(), no_points, estimate, {});
    const cv::Mat3b with = cv::imread((dir / "with.png").string());
    const cv::Mat3b without = cv::imread((dir / "without.png").string());
    ASSERT_FALSE(with.empty());
    // Both fit x -5..105 m, y -5..25 m at 1600 px across: 14.55 px/m, 437 px high.
    ASSERT_EQ(with.cols, 1600);
    const double px_per_m = 1600.0 / 110.0;
    const int reference_row = static_cast<int>((25.0 - 20.0) * px_per_m);
    // Right of the legend, a band around y = 20 m: the dashed reference, and nothing without it.
    const cv::Rect band(800, reference_row - 5, 700, 11);
    EXPECT_GT(DarkPixels(with, band), 200);
    EXPECT_EQ(DarkPixels(without, band), 0);
    // The legend's text and swatches in the top-left corner, in both.
    const cv::Rect legend(10, 10, 300, 40);
    EXPECT_GT(DarkPixels(with, legend), 100);
    EXPECT_GT(DarkPixels(without, legend), 100);
    fs::remove_all(dir);
}

}  // namespace
