// The exported map is the mapper's map: `dorado map`'s map.pcd (MapOutputs) holds exactly the
// points the mapper added to its own map, where it placed them. On a drive short enough that the
// map is never cropped, map.pcd equals the mapper's internal map point for point (the points of
// every written pose, the last ones written by Finish). And covariance.csv (CovarianceTable) has
// one row per written pose whose status says what it is.
#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "covariance_table.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/testing/street_scene.hpp"
#include "map_outputs.hpp"

namespace dorado::apps {
namespace {

using testing::MakeDrive;
using testing::MakeStreetWorld;
using testing::RadarSimOptions;
using testing::SimulateScan;
using testing::TruthSample;

Extrinsics Mount() {
    Extrinsics e;
    e.T_base_radar.translation() = Eigen::Vector3d(1.8, 0.1, 1.2);
    e.T_base_radar.linear() = ExpSO3(Eigen::Vector3d(0.0, 0.0, 0.15));
    return e;
}

// The points as float triples (PCD's precision), sorted, for a point-for-point comparison.
std::vector<std::array<float, 3>> Sorted(const Eigen::Matrix3Xd &points) {
    std::vector<std::array<float, 3>> out;
    for (Eigen::Index i = 0; i < points.cols(); ++i)
        out.push_back({static_cast<float>(points(0, i)), static_cast<float>(points(1, i)),
                       static_cast<float>(points(2, i))});
    std::sort(out.begin(), out.end());
    return out;
}

// Runs the street drive through the front end and MapOutputs; returns map.pcd and the mapper's map.
void RunDrive(Eigen::Matrix3Xd &pcd_points, Eigen::Matrix3Xd &mapper_points) {
    frontend::FrontEndConfig config;
    config.mapper.map.max_distance_m = 1e6;  // never cropped: the whole run is still in the map
    config.mapper.movers.memory_s = 2.0;     // cells emptied by the mover memory leave map.pcd too
    VehicleGeometry geometry;
    geometry.half_wheelbase_m = 1.4;
    frontend::RadarFrontEnd front_end(config, Mount(), geometry);
    const Eigen::Matrix3Xd world = MakeStreetWorld(3);
    const std::vector<TruthSample> truth = MakeDrive(60, 0.1);
    std::mt19937 rng(7);
    RadarSimOptions sim;
    sim.points_per_scan = 1500;
    MapOutputs outputs(config.mapper.map.voxel_size_m);
    int fallbacks = 0;
    for (int k = 0; k < 60; ++k) {
        RadarScan scan = SimulateScan(world, truth[k].T_world_base, Mount().T_base_radar,
                                      truth[k].v_base, truth[k].omega_base, Eigen::Matrix3Xd(3, 0),
                                      Eigen::Vector3d::Zero(), sim, rng, nullptr);
        scan.stamp_ns = 1'000'000'000 + k * 100'000'000LL;
        const frontend::FrontEndResult result = front_end.Process(scan);
        ASSERT_TRUE(result.accepted);
        fallbacks += result.registration.fallback() ? 1 : 0;
        outputs.Add(result);
    }
    EXPECT_LT(fallbacks, 6);  // a registered drive
    // The poses still in the smoother: written, their points into both maps.
    const std::vector<mapping::WrittenPose> last = front_end.Finish();
    EXPECT_FALSE(last.empty());
    outputs.AddWritten(last);
    EXPECT_EQ(front_end.trajectory().size(), 60u);
    const std::string dir =
        (std::filesystem::temp_directory_path() / "dorado_map_outputs").string();
    std::filesystem::create_directories(dir);
    outputs.Write(dir, front_end.trajectory());
    pcl::PointCloud<pcl::PointXYZ> cloud;
    ASSERT_EQ(pcl::io::loadPCDFile(dir + "/map.pcd", cloud), 0);
    pcd_points.resize(3, static_cast<Eigen::Index>(cloud.size()));
    for (std::size_t i = 0; i < cloud.size(); ++i)
        pcd_points.col(static_cast<Eigen::Index>(i)) = cloud[i].getVector3fMap().cast<double>();
    mapper_points = front_end.local_map()->Points();
    std::filesystem::remove_all(dir);
}

TEST(MapOutputs, MapPcdIsTheMappersMapPointForPoint) {
    Eigen::Matrix3Xd pcd, mapper;
    RunDrive(pcd, mapper);
    ASSERT_GT(mapper.cols(), 500);
    std::printf("map.pcd %ld points, the mapper's %ld\n", static_cast<long>(pcd.cols()),
                static_cast<long>(mapper.cols()));
    EXPECT_EQ(Sorted(pcd), Sorted(mapper));
}

}  // namespace
}  // namespace dorado::apps

namespace dorado::apps {
namespace {

// covariance.csv, one row per written pose: the status says what the pose is (first_scan, fused:
// the registration joined the smoother, fallback: it did not), the `fused` block carries the
// written pose and the covariance of its motion from the previous one, `registration` the
// registration's covariance (empty without one), `prior` the motion prior's (empty on the first
// scan).
TEST(CovarianceTable, EachWrittenPoseIsARowWithItsInputs) {
    mapping::WrittenPose first;
    first.stamp_ns = 1'000'000'000;
    first.first_scan = true;
    mapping::WrittenPose fallback;
    fallback.stamp_ns = 2'000'000'000;
    fallback.T_world_base.translation() << 3.0, 0.0, 0.0;
    fallback.covariance = 0.04 * Matrix6d::Identity();
    fallback.prior.covariance = 0.09 * Matrix6d::Identity();
    fallback.registered.valid = false;
    mapping::WrittenPose fused = fallback;
    fused.stamp_ns = 2'500'000'000;
    fused.registered.valid = true;
    fused.registered.covariance = 0.01 * Matrix6d::Identity();
    CovarianceTable table;
    for (const mapping::WrittenPose &w : {first, fallback, fused}) table.Add(w);
    std::vector<std::string> lines;
    std::string line;
    std::istringstream text(table.csv());
    while (std::getline(text, line)) lines.push_back(line);
    ASSERT_EQ(lines.size(), 4u);
    EXPECT_EQ(lines[1].rfind("1.000000000,first_scan,", 0), 0u) << lines[1];
    EXPECT_EQ(lines[2].rfind("2.000000000,fallback,", 0), 0u) << lines[2];
    EXPECT_EQ(lines[3].rfind("2.500000000,fused,", 0), 0u) << lines[3];
    // Fields: t, status, then 28 (pose 7 + covariance 21) each for fused, registration, prior.
    const auto field = [](const std::string &row, int index) {
        std::istringstream cells(row);
        std::string cell;
        for (int i = 0; i <= index; ++i) std::getline(cells, cell, ',');
        return cell;
    };
    EXPECT_EQ(field(lines[1], 2 + 56), "");  // the first scan has no prior
    EXPECT_EQ(field(lines[1], 2 + 28), "");  // nor a registration
    EXPECT_EQ(field(lines[2], 2), "3");      // the written pose's x
    EXPECT_EQ(field(lines[2], 2 + 7), "0.04");
    EXPECT_EQ(field(lines[2], 2 + 28), "");
    EXPECT_EQ(field(lines[2], 2 + 56 + 7), "0.09");
    EXPECT_EQ(field(lines[3], 2 + 7), "0.04");
    EXPECT_EQ(field(lines[3], 2 + 28 + 7), "0.01");
    EXPECT_EQ(field(lines[3], 2 + 56 + 7), "0.09");
}

}  // namespace
}  // namespace dorado::apps
