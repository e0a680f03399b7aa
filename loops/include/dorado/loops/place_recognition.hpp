#pragma once
/// @file place_recognition.hpp
/// Place recognition for sparse radar on accumulated submaps (after MapClosures, Gupta et al.
/// 2024, as kiss-slam uses it): a submap's static points become a bird's-eye density image (points
/// per cell, log-scaled and blurred), ORB finds and describes its corners, and two places match
/// when their descriptors agree and a RANSAC rigid motion in the plane
/// (cv::estimateAffinePartial2D, scale checked ~1) explains enough of the matches. The motion
/// found is the starting guess of the verification's registration. No OpenCV type in this header.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace dorado::loops {

struct PlaceConfig {
    double image_cell_m = 0.5;     ///< bird's-eye image resolution
    double image_radius_m = 60.0;  ///< half the image's side, around the submap's points' centre
    int max_features = 400;        ///< ORB corners per image
    double ratio_test = 0.85;      ///< Lowe's ratio: best match's Hamming distance / second best
    double ransac_threshold_m = 1.5;
    int min_inliers = 10;          ///< RANSAC inliers for a descriptor match
    double max_scale_error = 0.1;  ///< |scale - 1| of the RANSAC similarity
    void Validate() const;
};

/// A submap's bird's-eye features, in its anchor's frame (x, y in metres).
struct PlaceDescriptor {
    std::vector<Eigen::Vector2f> keypoints_anchor;
    std::vector<uint8_t> descriptors;  ///< 32 bytes per keypoint (ORB)
    [[nodiscard]] int size() const { return static_cast<int>(keypoints_anchor.size()); }
};

/// Two places' descriptors compared.
struct PlaceMatch {
    bool found = false;  ///< enough RANSAC inliers with a scale near 1
    /// The query submap's anchor in the candidate's, in the plane: x, y [m] and yaw [rad].
    Eigen::Vector3d xy_yaw_candidate_query = Eigen::Vector3d::Zero();
    int matches = 0;  ///< descriptor matches that passed the ratio test
    int inliers = 0;  ///< of which RANSAC's inliers
    /// Mean Hamming distance of the inliers (bits of 256; of all matches without inliers; 256
    /// without matches): the descriptor distance loops.csv reports.
    double descriptor_distance = 256.0;
    double scale = 0.0;
};

/// The descriptor of a submap's points (anchor frame).
[[nodiscard]] PlaceDescriptor DescribePlace(const Eigen::Matrix3Xf &points_anchor,
                                            const PlaceConfig &config);

/// Matches a query place against a candidate (RANSAC seeded for reproducibility).
[[nodiscard]] PlaceMatch MatchPlaces(const PlaceDescriptor &query, const PlaceDescriptor &candidate,
                                     const PlaceConfig &config);

}  // namespace dorado::loops
