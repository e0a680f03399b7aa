// The mover rules (movers.hpp) against brute force and hand-placed cells, and LocalMap::Remove.
#include <gtest/gtest.h>

#include <random>

#include "dorado/mapping/local_map.hpp"
#include "dorado/mapping/movers.hpp"

namespace dorado::mapping {
namespace {

TEST(Movers, NearAnyMatchesBruteForce) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-10.0, 10.0);
    Eigen::Matrix3Xd points(3, 300), moving(3, 40);
    for (Eigen::Index i = 0; i < points.cols(); ++i) points.col(i) << u(rng), u(rng), u(rng) / 5;
    for (Eigen::Index i = 0; i < moving.cols(); ++i) moving.col(i) << u(rng), u(rng), u(rng) / 5;
    const double radius = 1.5;
    const std::vector<bool> near = NearAny(points, moving, radius);
    int count = 0;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
        bool expected = false;
        for (Eigen::Index j = 0; j < moving.cols(); ++j)
            expected =
                expected || std::hypot(points(0, i) - moving(0, j), points(1, i) - moving(1, j),
                                       points(2, i) - moving(2, j)) <= radius;
        EXPECT_EQ(near[static_cast<std::size_t>(i)], expected) << "point " << i;
        count += expected ? 1 : 0;
    }
    EXPECT_GT(count, 10);  // the case is not trivial
    EXPECT_LT(count, 290);
    for (bool b : NearAny(points, moving, 0.0)) EXPECT_FALSE(b);
    for (bool b : NearAny(points, Eigen::Matrix3Xd(3, 0), radius)) EXPECT_FALSE(b);
}

TEST(Movers, ClusteredKeepsThePointsWithEnoughNeighbours) {
    Eigen::Matrix3Xd moving(3, 5);
    moving << 0.0, 0.5, 0.9, 5.0, 20.0,  //
        0.0, 0.0, 0.0, 0.0, 0.0,         //
        0.0, 0.0, 0.0, 0.0, 0.0;
    // Radius 1: the three near the origin see each other (0.9 apart at most); 5 and 20 are alone.
    EXPECT_EQ(Clustered(moving, 1.0, 2).cols(), 3);
    EXPECT_EQ(Clustered(moving, 1.0, 3).cols(), 3);
    EXPECT_EQ(Clustered(moving, 1.0, 4).cols(), 0);
    EXPECT_EQ(Clustered(moving, 0.45, 2).cols(), 2);  // 0.0-0.5 no, 0.5-0.9 yes
    EXPECT_EQ(Clustered(moving, 1.0, 1).cols(), 5);
    EXPECT_EQ(Clustered(moving, 0.0, 2).cols(), 5);
}

TEST(Movers, MemoryMarksCellsAndForgetsThemAfterItsTime) {
    MoverConfig config;
    config.memory_s = 2.0;
    MoverMemory memory(config, 1.0);
    Eigen::Matrix3Xd seen(3, 2);
    seen << 0.5, 10.2, 0.5, 3.7, 0.5, 0.1;
    EXPECT_EQ(memory.Observe(seen, 0.0).size(), 2u);
    EXPECT_TRUE(memory.Moving({0.9, 0.1, 0.9}));   // same 1 m cell as (0.5, 0.5, 0.5)
    EXPECT_FALSE(memory.Moving({1.1, 0.5, 0.5}));  // the next cell
    EXPECT_TRUE(memory.Moving({10.0, 3.5, 0.0}));
    Eigen::Matrix3Xd later(3, 1);
    later << 10.5, 3.5, 0.5;
    memory.Observe(later, 1.5);  // the second cell seen again, the first not
    EXPECT_TRUE(memory.Moving({0.5, 0.5, 0.5}));
    memory.Observe(Eigen::Matrix3Xd(3, 0), 2.5);  // 2.5 s after the first: forgotten
    EXPECT_FALSE(memory.Moving({0.5, 0.5, 0.5}));
    EXPECT_TRUE(memory.Moving({10.5, 3.5, 0.5}));  // 1.0 s after its last sighting
    memory.Observe(Eigen::Matrix3Xd(3, 0), 3.6);
    EXPECT_EQ(memory.size(), 0u);

    config.memory_s = 0.0;
    MoverMemory off(config, 1.0);
    EXPECT_TRUE(off.Observe(seen, 0.0).empty());
    EXPECT_FALSE(off.Moving({0.5, 0.5, 0.5}));
}

TEST(Movers, BadConfigNamesTheKey) {
    MoverConfig config;
    config.memory_s = -1.0;
    try {
        config.Validate();
        FAIL() << "a negative memory was accepted";
    } catch (const std::invalid_argument &e) {
        EXPECT_NE(std::string(e.what()).find("mapper.movers.memory_s"), std::string::npos);
    }
}

TEST(LocalMap, RemoveDropsTheVoxelsAndTheirPoints) {
    LocalMapConfig config;
    config.voxel_size_m = 1.0;
    config.max_points_per_voxel = 2;
    config.max_distance_m = 100.0;
    LocalMap map(config);
    Eigen::Matrix3Xd points(3, 4);
    points << 0.2, 0.7, 5.5, 9.5,  //
        0.2, 0.3, 0.5, 0.5,        //
        0.2, 0.1, 0.5, 0.5;
    map.Update(points, Eigen::Vector3d::Zero());
    ASSERT_EQ(map.size(), 4u);
    EXPECT_EQ(map.Remove({VoxelKey{0, 0, 0}, VoxelKey{3, 3, 3}}), 2u);  // one voxel held two
    EXPECT_EQ(map.size(), 2u);
    EXPECT_EQ(map.Nearest({0.3, 0.3, 0.3}, 3.0).index, -1);
    EXPECT_GE(map.Nearest({5.0, 0.5, 0.5}, 3.0).index, 0);
    // The freed voxel takes new points again.
    map.Update(points.leftCols(1), Eigen::Vector3d::Zero());
    EXPECT_EQ(map.size(), 3u);
    EXPECT_GE(map.Nearest({0.3, 0.3, 0.3}, 1.0).index, 0);
}

}  // namespace
}  // namespace dorado::mapping
