#include "map_image.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace dorado::apps {

namespace {

double Quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
    return v[k];
}

/// The 256 colours of an OpenCV colormap, computed once per colormap (applyColorMap builds its
/// table on every call: far too slow per point).
const cv::Mat3b &ColormapTable(int colormap) {
    static std::map<int, cv::Mat3b> tables;
    auto it = tables.find(colormap);
    if (it == tables.end()) {
        cv::Mat1b ramp(256, 1);
        for (int i = 0; i < 256; ++i) ramp(i, 0) = static_cast<uchar>(i);
        cv::Mat3b table;
        cv::applyColorMap(ramp, table, colormap);
        it = tables.emplace(colormap, table).first;
    }
    return it->second;
}

cv::Vec3b ColourOf(double t, int colormap) {  // t in [0, 1]
    const double clamped = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
    return ColormapTable(colormap)(static_cast<int>(clamped * 255.0), 0);
}

cv::Scalar ScalarOf(const cv::Vec3b &c) {
    return cv::Scalar(c[0], c[1], c[2]);
}

/// A polyline drawn dashed (kDashPx on, kDashPx off along its length), so that a path under it
/// stays visible.
void DrawDashed(cv::Mat3b &image, const std::vector<cv::Point> &points, const cv::Scalar &colour) {
    constexpr double kDashPx = 10.0, kStepPx = 2.0;
    double along = 0.0;
    for (std::size_t k = 1; k < points.size(); ++k) {
        const cv::Point2d a = points[k - 1], b = points[k];
        const double length = cv::norm(b - a);
        const int steps = std::max(1, static_cast<int>(std::ceil(length / kStepPx)));
        for (int s = 0; s < steps; ++s) {
            const double f0 = static_cast<double>(s) / steps,
                         f1 = static_cast<double>(s + 1) / steps;
            if (static_cast<long>((along + f0 * length) / kDashPx) % 2 == 0)
                cv::line(image, a + f0 * (b - a), a + f1 * (b - a), colour, 2, cv::LINE_AA);
        }
        along += length;
    }
}

/// A colour ramp of @p colormap over [0, span] as a horizontal bar at @p at.
void DrawRamp(cv::Mat3b &image, cv::Point at, int width, int height, int colormap, double span) {
    for (int x = 0; x < width; ++x) {
        const cv::Vec3b c = ColourOf(span * x / std::max(1, width - 1), colormap);
        cv::line(image, at + cv::Point(x, 0), at + cv::Point(x, height - 1), ScalarOf(c));
    }
}

const cv::Scalar kLoopColour(0, 0, 230);  // red (BGR)

/// The legend, top left: what each colour and line is.
void DrawLegend(cv::Mat3b &image, bool with_reference, bool with_loops, double colour_span,
                double z_lo, double z_hi) {
    char heights[96];
    std::snprintf(heights, sizeof(heights), "map points, colour: height %.1f .. %.1f m", z_lo,
                  z_hi);
    std::vector<std::string> rows{"estimate, colour: time (start .. end)"};
    if (with_reference) rows.emplace_back("reference: the dataset's ground truth");
    rows.emplace_back(heights);
    if (with_loops) rows.emplace_back("loop closures: the places each accepted loop joins");
    constexpr int kRow = 26, kSwatch = 40, kPad = 10;
    const double font = 0.55;
    int text_width = 0;
    for (const auto &row : rows) {
        int baseline = 0;
        text_width = std::max(
            text_width, cv::getTextSize(row, cv::FONT_HERSHEY_SIMPLEX, font, 1, &baseline).width);
    }
    const cv::Rect box(kPad, kPad, 3 * kPad + kSwatch + text_width,
                       kPad + static_cast<int>(rows.size()) * kRow);
    cv::rectangle(image, box, cv::Scalar(255, 255, 255), cv::FILLED);
    cv::rectangle(image, box, cv::Scalar(0, 0, 0), 1);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const cv::Point swatch(2 * kPad, 2 * kPad + static_cast<int>(i) * kRow);
        if (i == 0) {
            DrawRamp(image, swatch + cv::Point(0, 4), kSwatch, 4, cv::COLORMAP_PLASMA, 1.0);
        } else if (with_reference && i == 1) {
            DrawDashed(image, {swatch + cv::Point(0, 5), swatch + cv::Point(kSwatch, 5)},
                       cv::Scalar(0, 0, 0));
        } else if (with_loops && i + 1 == rows.size()) {
            cv::line(image, swatch + cv::Point(0, 5), swatch + cv::Point(kSwatch, 5), kLoopColour,
                     2, cv::LINE_AA);
        } else {
            DrawRamp(image, swatch, kSwatch, 10, cv::COLORMAP_VIRIDIS, colour_span);
        }
        cv::putText(image, rows[i], swatch + cv::Point(kSwatch + kPad, 10),
                    cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
}

}  // namespace

void WriteBirdsEyeImage(const std::string &path, const Eigen::Matrix3Xd &map_points_world,
                        const std::vector<Eigen::Vector3d> &trajectory_world,
                        const std::vector<Eigen::Vector3d> &reference_world,
                        const std::vector<LoopEdge> &loop_edges_world, int max_side_px) {
    Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
    auto grow = [&](const Eigen::Vector3d &p) {
        lo = lo.cwiseMin(p.head<2>());
        hi = hi.cwiseMax(p.head<2>());
    };
    for (Eigen::Index i = 0; i < map_points_world.cols(); ++i) grow(map_points_world.col(i));
    for (const auto &p : trajectory_world) grow(p);
    for (const auto &p : reference_world) grow(p);
    if (!lo.allFinite()) lo = hi = Eigen::Vector2d::Zero();
    const double margin_m = 5.0;
    lo.array() -= margin_m;
    hi.array() += margin_m;
    const double px_per_m = max_side_px / std::max(hi.x() - lo.x(), hi.y() - lo.y());
    const int width = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) * px_per_m)));
    const int height = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) * px_per_m)));
    cv::Mat3b image(height, width, cv::Vec3b(255, 255, 255));
    auto pixel = [&](const Eigen::Vector3d &p) {  // world +Y up in the picture
        return cv::Point(static_cast<int>((p.x() - lo.x()) * px_per_m),
                         static_cast<int>((hi.y() - p.y()) * px_per_m));
    };

    // Points coloured by height, the 2-98 % range of z spread over the colour map.
    std::vector<double> z(map_points_world.cols());
    for (Eigen::Index i = 0; i < map_points_world.cols(); ++i) z[i] = map_points_world(2, i);
    const double z_lo = Quantile(z, 0.02), z_hi = std::max(Quantile(z, 0.98), z_lo + 1e-3);
    // Low points first, so that walls and poles stay visible over the ground.
    std::vector<Eigen::Index> order(map_points_world.cols());
    for (Eigen::Index i = 0; i < map_points_world.cols(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return z[a] < z[b]; });
    // A sparse map (a real radar's few thousand points) as discs, so that it stays legible; a dense
    // one (>= kDensePoints) point by point as before. The colours' dark half for contrast on white.
    constexpr Eigen::Index kDensePoints = 20000;
    const Eigen::Index n = map_points_world.cols();
    const int radius = n >= kDensePoints ? 0 : n >= 5000 ? 1 : 2;
    const double colour_span = radius == 0 ? 1.0 : 0.6;
    for (const auto i : order) {
        const cv::Point q = pixel(map_points_world.col(i));
        if (q.x < 0 || q.y < 0 || q.x >= width || q.y >= height) continue;
        const cv::Vec3b c =
            ColourOf(colour_span * (z[i] - z_lo) / (z_hi - z_lo), cv::COLORMAP_VIRIDIS);
        if (radius == 0)
            image(q) = c;
        else
            cv::circle(image, q, radius, cv::Scalar(c[0], c[1], c[2]), cv::FILLED);
    }
    // Trajectory coloured by time.
    for (std::size_t k = 1; k < trajectory_world.size(); ++k) {
        const double t = static_cast<double>(k) / static_cast<double>(trajectory_world.size());
        const cv::Vec3b c = ColourOf(t, cv::COLORMAP_PLASMA);
        cv::line(image, pixel(trajectory_world[k - 1]), pixel(trajectory_world[k]),
                 cv::Scalar(c[0], c[1], c[2]), 3, cv::LINE_AA);
    }
    // The reference on top, dashed: the estimate shows between its dashes.
    std::vector<cv::Point> reference_px;
    for (const auto &p : reference_world) reference_px.push_back(pixel(p));
    DrawDashed(image, reference_px, cv::Scalar(0, 0, 0));
    // The loop closures: a line between the two places each joins, a ring at each end.
    for (const LoopEdge &edge : loop_edges_world) {
        cv::line(image, pixel(edge.from_world), pixel(edge.to_world), kLoopColour, 2, cv::LINE_AA);
        cv::circle(image, pixel(edge.from_world), 6, kLoopColour, 2, cv::LINE_AA);
        cv::circle(image, pixel(edge.to_world), 6, kLoopColour, 2, cv::LINE_AA);
    }
    DrawLegend(image, !reference_world.empty(), !loop_edges_world.empty(), colour_span, z_lo, z_hi);
    // Scale bar: a round length near a fifth of the width.
    const double target_m = 0.2 * width / px_per_m;
    const double bar_m = std::pow(10.0, std::floor(std::log10(std::max(target_m, 1e-3))));
    const cv::Point a(20, height - 20), b(20 + static_cast<int>(bar_m * px_per_m), height - 20);
    cv::line(image, a, b, cv::Scalar(0, 0, 0), 3);
    cv::putText(image, std::to_string(static_cast<long>(bar_m)) + " m", a + cv::Point(0, -10),
                cv::FONT_HERSHEY_SIMPLEX, 0.7, cv::Scalar(0, 0, 0), 2);
    // Atomically: a temporary file, then a rename.
    const std::string tmp = path + ".tmp.png";
    bool ok = false;
    try {
        ok = cv::imwrite(tmp, image);
    } catch (const cv::Exception &e) {
        throw std::runtime_error(path + ": cannot write the map picture: " + e.what());
    }
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0)
        throw std::runtime_error(path + ": cannot write the map picture");
}

}  // namespace dorado::apps
