// The local map's voxel hash against brute force: the nearest point within a distance, the cached
// local shapes after updates and crops, a memory that does not grow with the drive; and the
// output map's voxel thinning.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "dorado/mapping/local_map.hpp"
#include "dorado/mapping/voxel_cloud.hpp"
#include "local_map_impl.hpp"

namespace dorado::mapping {
namespace {

Eigen::Matrix3Xd RandomPoints(std::mt19937 &rng, int n, const Eigen::Vector3d &centre,
                              double half_width) {
    std::uniform_real_distribution<double> u(-half_width, half_width);
    Eigen::Matrix3Xd points(3, n);
    for (int i = 0; i < n; ++i) points.col(i) = centre + Eigen::Vector3d(u(rng), u(rng), u(rng));
    return points;
}

// Squared distance to the nearest column, by brute force.
double BruteNearest(const Eigen::Matrix3Xd &points, const Eigen::Vector3d &q) {
    double best = INFINITY;
    for (Eigen::Index i = 0; i < points.cols(); ++i)
        best = std::min(best, (points.col(i) - q).squaredNorm());
    return best;
}

TEST(LocalMap, NearestWithinADistanceIsExact) {
    std::mt19937 rng(7);
    for (const double voxel : {1.0, 0.7}) {
        LocalMapConfig config;
        config.voxel_size_m = voxel;
        config.max_points_per_voxel = 3;
        config.max_distance_m = INFINITY;
        LocalMap map(config);
        // Straddles the origin, so negative voxel indices are exercised too.
        map.Update(RandomPoints(rng, 3000, Eigen::Vector3d(-3.0, 2.0, 0.5), 15.0),
                   Eigen::Vector3d::Zero());
        const Eigen::Matrix3Xd points = map.Points();
        std::uniform_real_distribution<double> distance(0.2, 3.5);
        int found = 0, missed = 0;
        for (int k = 0; k < 3000; ++k) {
            const Eigen::Vector3d q =
                RandomPoints(rng, 1, Eigen::Vector3d(-3.0, 2.0, 0.5), 18.0).col(0);
            const double d = distance(rng);
            const double truth = BruteNearest(points, q);
            const LocalMap::Neighbour nn = map.Nearest(q, d);
            if (truth < d * d) {
                ASSERT_GE(nn.index, 0) << "voxel " << voxel << " query " << q.transpose();
                EXPECT_NEAR(nn.distance_squared, truth, 1e-12);
                EXPECT_NEAR((map.impl().points_world[nn.index] - q).squaredNorm(), truth, 1e-12);
                ++found;
            } else {
                EXPECT_EQ(nn.index, -1) << "nearest at " << std::sqrt(truth) << " > " << d;
                ++missed;
            }
        }
        EXPECT_GT(found, 500);  // both branches are really exercised
        EXPECT_GT(missed, 500);
    }
    LocalMap empty;
    EXPECT_EQ(empty.Nearest(Eigen::Vector3d::Zero(), 2.0).index, -1);
}

// The unit normal of the k nearest map points (a k-d tree's answer).
Eigen::Vector3d BruteNormal(const Eigen::Matrix3Xd &points, const Eigen::Vector3d &p, int k) {
    std::vector<std::pair<double, Eigen::Index>> candidates;
    for (Eigen::Index i = 0; i < points.cols(); ++i)
        candidates.emplace_back((points.col(i) - p).squaredNorm(), i);
    std::sort(candidates.begin(), candidates.end());
    candidates.resize(std::min<std::size_t>(candidates.size(), static_cast<std::size_t>(k)));
    if (candidates.size() < 3) return Eigen::Vector3d::Zero();  // no surface: no normal
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto &[d2, i] : candidates) mean += points.col(i);
    mean /= static_cast<double>(candidates.size());
    Eigen::Matrix3d sample = Eigen::Matrix3d::Zero();
    for (const auto &[d2, i] : candidates)
        sample += (points.col(i) - mean) * (points.col(i) - mean).transpose();
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(sample).eigenvectors().col(0);
}

TEST(LocalMap, CachedShapesFollowUpdatesAndCrops) {
    // Dense, and sparse enough that the 10 nearest reach several voxels away.
    for (const int points_per_update : {400, 40}) {
        std::mt19937 rng(3);
        LocalMapConfig config;
        config.voxel_size_m = 1.0;
        config.max_points_per_voxel = 2;
        config.max_distance_m = 12.0;
        LocalMap map(config);
        LocalMap::Impl &m = map.impl();
        m.SetCovarianceModel(10, 0.1);
        // A drive along x: each update adds points around the vehicle and crops behind it; the
        // shapes are read (and cached) between updates, so stale caches would show.
        for (int step = 0; step < 12; ++step) {
            const Eigen::Vector3d position(1.5 * step, 0.0, 0.0);
            map.Update(RandomPoints(rng, points_per_update,
                                    position + Eigen::Vector3d(4.0, 0.0, 0.0), 6.0),
                       position);
            m.ComputeAllCovariances();
        }
        const Eigen::Matrix3Xd points = map.Points();
        int checked = 0, far = 0;
        m.ForEachSlot([&](int32_t s) {
            const Eigen::Vector3d truth = BruteNormal(points, m.points_world[s], 10);
            const Eigen::Vector3d &normal = m.Normal(s);
            EXPECT_NEAR(std::abs(normal.dot(truth)), 1.0, 1e-6) << "slot " << s;
            far += m.fitted_rings[s] > 2;
            ++checked;
        });
        EXPECT_GT(checked, points_per_update);
        if (points_per_update < 100) {
            EXPECT_GT(far, checked / 4);  // the shells really grew
        }
    }
}

TEST(LocalMap, MemoryDoesNotGrowWithTheDrive) {
    std::mt19937 rng(11);
    LocalMapConfig config;
    config.max_distance_m = 40.0;
    LocalMap map(config);
    LocalMapConfig unbounded = config;
    unbounded.max_distance_m = INFINITY;
    LocalMap whole_run(unbounded);
    std::size_t capacity_at_500m = 0, voxels_at_500m = 0;
    for (int step = 0; step <= 2000; ++step) {  // 2 km, one update per metre
        const Eigen::Vector3d position(step, 0.0, 0.0);
        const Eigen::Matrix3Xd scan = RandomPoints(rng, 300, position, 30.0);
        map.Update(scan, position);
        whole_run.Update(scan, position);
        if (step % 100 == 0) map.impl().ComputeAllCovariances();  // the shape caches too
        if (step == 500) {
            capacity_at_500m = map.capacity();
            voxels_at_500m = map.voxel_count();
        }
    }
    // The crop keeps about the voxels within 40 m; freed blocks are reused.
    EXPECT_LE(map.capacity(), capacity_at_500m * 11 / 10);
    EXPECT_LE(map.voxel_count(), voxels_at_500m * 11 / 10);
    EXPECT_EQ(map.impl().covariances.size(), map.capacity());
    EXPECT_LE(map.impl().blocks.size(), 2 * map.voxel_count());
    // The whole-run map grows with the drive (and never allocates the shape caches).
    EXPECT_GT(whole_run.size(), 2 * map.size());
    EXPECT_TRUE(whole_run.impl().covariances.empty());
}

}  // namespace
}  // namespace dorado::mapping

namespace dorado::mapping {
namespace {

TEST(VoxelCloud, KeepsTheFirstFinitePointOfEachVoxel) {
    std::mt19937 rng(5);
    const double voxel = 0.3;
    // Far from the origin (precision of the float offsets) and across negative coordinates.
    Eigen::Matrix3Xd points = RandomPoints(rng, 4000, Eigen::Vector3d(5000.0, -3000.0, 2.0), 4.0);
    points.col(10).setConstant(NAN);
    points(0, 20) = INFINITY;
    VoxelCloud cloud(voxel);
    cloud.Add(points.leftCols(2000));
    cloud.Add(points.rightCols(2000));
    // Brute force: the first finite point of each voxel, in order.
    std::vector<Eigen::Vector3d> truth;
    std::vector<Eigen::Vector3d> keys;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
        if (!points.col(i).allFinite()) continue;
        const Eigen::Vector3d key = (points.col(i) / voxel).array().floor();
        if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
        keys.push_back(key);
        truth.push_back(points.col(i));
    }
    ASSERT_EQ(cloud.size(), truth.size());
    ASSERT_LT(truth.size(), 3990u);  // some voxels really are shared
    const Eigen::Matrix3Xd kept = cloud.Points();
    for (std::size_t i = 0; i < truth.size(); ++i)
        EXPECT_LT((kept.col(static_cast<Eigen::Index>(i)) - truth[i]).norm(), 1e-5) << i;
    EXPECT_THROW(VoxelCloud(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::mapping
