// Bird's-eye density images, ORB and RANSAC (place_recognition.hpp).
#include "dorado/loops/place_recognition.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dorado/core/require.hpp"

namespace dorado::loops {

void PlaceConfig::Validate() const {
    const std::string k = "loop_closure.place_";
    Require(image_cell_m > 0.0 && std::isfinite(image_cell_m), k + "image_cell_m", "must be > 0");
    Require(image_radius_m > 0.0 && image_radius_m / image_cell_m <= 2000.0, k + "image_radius_m",
            "must be > 0 and at most 2000 place_image_cell_m (4000 pixels a side)");
    Require(max_features >= 10, k + "max_features", "must be >= 10");
    Require(ratio_test > 0.0 && ratio_test <= 1.0, k + "ratio_test", "must be in (0, 1]");
    Require(ransac_threshold_m > 0.0 && std::isfinite(ransac_threshold_m), k + "ransac_threshold_m",
            "must be > 0");
    Require(min_inliers >= 3, k + "min_inliers", "must be >= 3");
    Require(max_scale_error > 0.0 && std::isfinite(max_scale_error), k + "max_scale_error",
            "must be > 0");
}

namespace {

// The density image: points per cell around the points' centre (x right, y up as rows grow
// downward: row = (centre_y + radius - y) / cell), log-scaled to 8 bits and blurred by one cell
// so that ORB's corners sit on structures, not on single returns.
cv::Mat DensityImage(const Eigen::Matrix3Xf &points_anchor, const Eigen::Vector2f &origin_anchor,
                     const PlaceConfig &config) {
    const int side = static_cast<int>(std::ceil(2.0 * config.image_radius_m / config.image_cell_m));
    cv::Mat counts = cv::Mat::zeros(side, side, CV_32F);
    const float inv_cell = static_cast<float>(1.0 / config.image_cell_m);
    for (Eigen::Index i = 0; i < points_anchor.cols(); ++i) {
        const int col =
            static_cast<int>(std::floor((points_anchor(0, i) - origin_anchor.x()) * inv_cell));
        const int row =
            static_cast<int>(std::floor((origin_anchor.y() - points_anchor(1, i)) * inv_cell));
        if (col >= 0 && col < side && row >= 0 && row < side) counts.at<float>(row, col) += 1.0f;
    }
    cv::Mat log_counts;
    cv::log(counts + 1.0f, log_counts);
    double max_value = 0.0;
    cv::minMaxLoc(log_counts, nullptr, &max_value);
    cv::Mat image;
    log_counts.convertTo(image, CV_8U, max_value > 0.0 ? 255.0 / max_value : 0.0);
    cv::GaussianBlur(image, image, cv::Size(3, 3), 0.0);
    return image;
}

cv::Mat DescriptorMat(const PlaceDescriptor &place) {
    return cv::Mat(place.size(), 32, CV_8U, const_cast<uint8_t *>(place.descriptors.data()));
}

}  // namespace

PlaceDescriptor DescribePlace(const Eigen::Matrix3Xf &points_anchor, const PlaceConfig &config) {
    PlaceDescriptor place;
    if (points_anchor.cols() == 0) return place;
    const Eigen::Vector2f centre = points_anchor.topRows<2>().rowwise().mean();
    const float radius = static_cast<float>(config.image_radius_m);
    const Eigen::Vector2f origin(centre.x() - radius, centre.y() + radius);  // the image's top-left
    const cv::Mat image = DensityImage(points_anchor, origin, config);
    cv::Ptr<cv::ORB> orb =
        cv::ORB::create(config.max_features, 1.2f, 4, 15, 0, 2, cv::ORB::HARRIS_SCORE, 15, 10);
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
    orb->detectAndCompute(image, cv::noArray(), keypoints, descriptors);
    if (descriptors.empty()) return place;
    place.descriptors.assign(descriptors.data, descriptors.data + descriptors.total());
    const auto cell = static_cast<float>(config.image_cell_m);
    for (const cv::KeyPoint &k : keypoints)
        place.keypoints_anchor.emplace_back(origin.x() + (k.pt.x + 0.5f) * cell,
                                            origin.y() - (k.pt.y + 0.5f) * cell);
    return place;
}

PlaceMatch MatchPlaces(const PlaceDescriptor &query, const PlaceDescriptor &candidate,
                       const PlaceConfig &config) {
    PlaceMatch match;
    if (query.size() < 2 || candidate.size() < 2) return match;
    cv::BFMatcher matcher(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> knn;
    matcher.knnMatch(DescriptorMat(query), DescriptorMat(candidate), knn, 2);
    std::vector<cv::Point2f> from, to;
    std::vector<float> distances;
    for (const auto &pair : knn) {
        if (pair.size() < 2 || pair[0].distance > config.ratio_test * pair[1].distance) continue;
        const Eigen::Vector2f &q = query.keypoints_anchor[pair[0].queryIdx];
        const Eigen::Vector2f &c = candidate.keypoints_anchor[pair[0].trainIdx];
        from.emplace_back(q.x(), q.y());
        to.emplace_back(c.x(), c.y());
        distances.push_back(pair[0].distance);
    }
    match.matches = static_cast<int>(from.size());
    if (match.matches == 0) return match;
    double all_distance = 0.0;
    for (float d : distances) all_distance += d;
    match.descriptor_distance = all_distance / match.matches;
    if (match.matches < config.min_inliers) return match;
    cv::setRNGSeed(1);  // estimateAffinePartial2D samples with OpenCV's global generator
    std::vector<uchar> inlier_mask;
    const cv::Mat A = cv::estimateAffinePartial2D(from, to, inlier_mask, cv::RANSAC,
                                                  config.ransac_threshold_m, 2000, 0.99, 10);
    if (A.empty()) return match;
    double inlier_distance = 0.0;
    for (std::size_t i = 0; i < inlier_mask.size(); ++i)
        if (inlier_mask[i] != 0) {
            ++match.inliers;
            inlier_distance += distances[i];
        }
    if (match.inliers > 0) match.descriptor_distance = inlier_distance / match.inliers;
    // A = [s cos, -s sin, tx; s sin, s cos, ty]: the query's points in the candidate's frame.
    const double a = A.at<double>(0, 0), b = A.at<double>(1, 0);
    match.scale = std::hypot(a, b);
    match.xy_yaw_candidate_query = {A.at<double>(0, 2), A.at<double>(1, 2), std::atan2(b, a)};
    match.found = match.inliers >= config.min_inliers &&
                  std::abs(match.scale - 1.0) <= config.max_scale_error;
    return match;
}

}  // namespace dorado::loops
