#include "dorado/io/trajectory_io.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "dorado/core/time.hpp"
#include "dorado/io/atomic_file.hpp"
#include "readers.hpp"

namespace dorado::io {

namespace {

constexpr int64_t kNanos = kNanosPerSecond;

[[noreturn]] void Fail(const std::string &path, std::size_t line, const std::string &what) {
    throw TrajectoryFileError(path + ":" + std::to_string(line) + ": " + what);
}

/// Splits on whitespace and commas.
std::vector<std::string> Tokens(const std::string &line) {
    std::vector<std::string> out;
    std::string current;
    for (const char c : line) {
        if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
            if (!current.empty()) out.push_back(std::move(current));
            current.clear();
        } else {
            current.push_back(c);
        }
    }
    if (!current.empty()) out.push_back(std::move(current));
    return out;
}

bool ParseDouble(const std::string &token, double &value) {
    char *end = nullptr;
    value = std::strtod(token.c_str(), &end);
    return end != token.c_str() && *end == '\0' && std::isfinite(value);
}

std::string FormatNanosAsSeconds(int64_t ns) {
    char buffer[48];
    const char *sign = ns < 0 ? "-" : "";
    const uint64_t magnitude = ns < 0 ? static_cast<uint64_t>(-(ns + 1)) + 1 : ns;
    std::snprintf(buffer, sizeof(buffer), "%s%llu.%09llu", sign,
                  static_cast<unsigned long long>(magnitude / kNanos),
                  static_cast<unsigned long long>(magnitude % kNanos));
    return buffer;
}

/// Nine decimals: sub-nanometre and 1e-9 rad, far below any sensor's accuracy, and coarse enough
/// that the ~1e-16 noise of a quaternion -> matrix -> quaternion trip never changes the text, so a
/// file read and written again is identical.
std::string FormatDouble(double v) {
    char buffer[40];
    std::snprintf(buffer, sizeof(buffer), "%.9f", v);
    if (std::strcmp(buffer, "-0.000000000") == 0) return "0.000000000";
    return buffer;
}

Eigen::Isometry3d PoseFromTranslationQuaternion(const std::string &path, std::size_t line,
                                                const double *t, const double *q_xyzw) {
    Eigen::Quaterniond q(q_xyzw[3], q_xyzw[0], q_xyzw[1], q_xyzw[2]);
    const double norm = q.norm();
    if (!(norm > 0.5 && norm < 1.5)) {
        Fail(path, line, "quaternion norm " + std::to_string(norm) + " is not close to 1");
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() << t[0], t[1], t[2];
    return T;
}

/// Reads the non-empty, non-comment lines of a file.
std::vector<std::pair<std::size_t, std::string>> DataLines(const std::string &path) {
    std::ifstream in(path);
    if (!in) throw TrajectoryFileError(path + ": cannot open");
    std::vector<std::pair<std::size_t, std::string>> lines;
    std::string line;
    for (std::size_t n = 1; std::getline(in, line); ++n) {
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        lines.emplace_back(n, line);
    }
    return lines;
}

Trajectory BuildTrajectory(const std::string &path, std::vector<StampedPose> poses,
                           const std::vector<std::size_t> &line_numbers) {
    for (std::size_t i = 1; i < poses.size(); ++i) {
        if (poses[i].stamp_ns <= poses[i - 1].stamp_ns) {
            Fail(path, line_numbers[i],
                 "time " + FormatNanosAsSeconds(poses[i].stamp_ns) + " s does not come after " +
                     FormatNanosAsSeconds(poses[i - 1].stamp_ns) + " s");
        }
    }
    if (poses.empty()) throw TrajectoryFileError(path + ": no poses in the file");
    return Trajectory(std::move(poses));
}

void WriteQuaternionPose(std::ostream &out, const Eigen::Isometry3d &T, char sep) {
    Eigen::Quaterniond q(T.linear());
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one sign for one rotation: stable text
    const Eigen::Vector3d t = T.translation();
    out << FormatDouble(t.x()) << sep << FormatDouble(t.y()) << sep << FormatDouble(t.z()) << sep
        << FormatDouble(q.x()) << sep << FormatDouble(q.y()) << sep << FormatDouble(q.z()) << sep
        << FormatDouble(q.w()) << "\n";
}

}  // namespace

/// Seconds written in decimal ("1690000000.123456789") to integer nanoseconds without going through
/// a double, so that nanosecond stamps survive the round trip exactly.
bool ParseSecondsToNanos(const std::string &token, int64_t &ns) {
    std::size_t i = 0;
    bool negative = false;
    if (i < token.size() && (token[i] == '-' || token[i] == '+')) negative = token[i++] == '-';
    int64_t whole = 0;
    std::size_t digits = 0;
    for (; i < token.size() && std::isdigit(static_cast<unsigned char>(token[i])); ++i, ++digits) {
        if (whole > INT64_MAX / kNanos / 10) return false;  // would overflow
        whole = whole * 10 + (token[i] - '0');
    }
    int64_t fraction = 0;
    int64_t scale = kNanos;
    if (i < token.size() && token[i] == '.') {
        ++i;
        for (; i < token.size() && std::isdigit(static_cast<unsigned char>(token[i])); ++i) {
            ++digits;
            if (scale > 1) {
                scale /= 10;
                fraction += (token[i] - '0') * scale;
            }
        }
    }
    if (digits == 0) return false;
    if (i != token.size()) {
        // Exponent notation: fall back to double precision.
        double value = 0.0;
        if (!ParseDouble(token, value) || std::fabs(value) > 9e9) return false;
        ns = SecondsToNanos(value);
        return true;
    }
    ns = whole * kNanos + fraction;
    if (negative) ns = -ns;
    return true;
}

Trajectory ReadTum(const std::string &path) {
    std::vector<StampedPose> poses;
    std::vector<std::size_t> numbers;
    for (const auto &[n, line] : DataLines(path)) {
        const auto tokens = Tokens(line);
        if (tokens.size() != 8) {
            Fail(path, n,
                 "expected 8 values 't x y z qx qy qz qw', found " + std::to_string(tokens.size()));
        }
        StampedPose pose;
        if (!ParseSecondsToNanos(tokens[0], pose.stamp_ns))
            Fail(path, n, "bad time '" + tokens[0] + "'");
        double v[7];
        for (int k = 0; k < 7; ++k) {
            if (!ParseDouble(tokens[k + 1], v[k]))
                Fail(path, n, "bad number '" + tokens[k + 1] + "'");
        }
        pose.T_world_body = PoseFromTranslationQuaternion(path, n, v, v + 3);
        poses.push_back(pose);
        numbers.push_back(n);
    }
    return BuildTrajectory(path, std::move(poses), numbers);
}

void WriteTum(const std::string &path, const Trajectory &trajectory) {
    WriteFileAtomically(path, [&](std::ostream &out) {
        out << "# timestamp tx ty tz qx qy qz qw\n";
        for (const auto &pose : trajectory.poses()) {
            out << FormatNanosAsSeconds(pose.stamp_ns) << ' ';
            WriteQuaternionPose(out, pose.T_world_body, ' ');
        }
    });
}

Trajectory ReadKitti(const std::string &poses_path, const std::string &times_path) {
    const auto pose_lines = DataLines(poses_path);
    const auto time_lines = DataLines(times_path);
    if (pose_lines.size() != time_lines.size()) {
        throw TrajectoryFileError(poses_path + ": " + std::to_string(pose_lines.size()) +
                                  " poses but " + times_path + " has " +
                                  std::to_string(time_lines.size()) + " times");
    }
    std::vector<StampedPose> poses;
    std::vector<std::size_t> numbers;
    for (std::size_t i = 0; i < pose_lines.size(); ++i) {
        const auto &[n, line] = pose_lines[i];
        const auto tokens = Tokens(line);
        if (tokens.size() != 12) {
            Fail(poses_path, n,
                 "expected 12 values (3x4 row-major), found " + std::to_string(tokens.size()));
        }
        Eigen::Matrix<double, 3, 4> M;
        for (int k = 0; k < 12; ++k) {
            if (!ParseDouble(tokens[k], M(k / 4, k % 4)))
                Fail(poses_path, n, "bad number '" + tokens[k] + "'");
        }
        const Eigen::Matrix3d R = M.leftCols<3>();
        if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-3 ||
            R.determinant() < 0) {
            Fail(poses_path, n, "the 3x3 block is not a rotation matrix");
        }
        StampedPose pose;
        const auto time_tokens = Tokens(time_lines[i].second);
        if (time_tokens.size() != 1 || !ParseSecondsToNanos(time_tokens[0], pose.stamp_ns)) {
            Fail(times_path, time_lines[i].first, "expected one time in seconds");
        }
        // Re-orthonormalise the printed rotation (KITTI files carry ~1e-9 rounding).
        pose.T_world_body.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
        pose.T_world_body.translation() = M.col(3);
        poses.push_back(pose);
        numbers.push_back(n);
    }
    return BuildTrajectory(poses_path, std::move(poses), numbers);
}

void WriteKitti(const std::string &poses_path, const std::string &times_path,
                const Trajectory &trajectory) {
    WriteFileAtomically(poses_path, [&](std::ostream &out) {
        for (const auto &pose : trajectory.poses()) {
            const Eigen::Matrix<double, 3, 4> M = pose.T_world_body.matrix().topRows<3>();
            for (int k = 0; k < 12; ++k)
                out << FormatDouble(M(k / 4, k % 4)) << (k == 11 ? '\n' : ' ');
        }
    });
    WriteFileAtomically(times_path, [&](std::ostream &out) {
        for (const auto &pose : trajectory.poses())
            out << FormatNanosAsSeconds(pose.stamp_ns) << "\n";
    });
}

Trajectory ReadPaperCsv(const std::string &path) {
    std::vector<StampedPose> poses;
    std::vector<std::size_t> numbers;
    for (const auto &[n, line] : DataLines(path)) {
        const auto tokens = Tokens(line);
        double probe = 0.0;
        if (poses.empty() && numbers.empty() && !tokens.empty() && !ParseDouble(tokens[0], probe)) {
            numbers.push_back(0);  // a header line: skip it once
            continue;
        }
        if (tokens.size() != 9) {
            Fail(path, n,
                 "expected 9 values 'sec,nsec,x,y,z,qx,qy,qz,qw', found " +
                     std::to_string(tokens.size()));
        }
        double v[9];
        for (int k = 0; k < 9; ++k) {
            if (!ParseDouble(tokens[k], v[k])) Fail(path, n, "bad number '" + tokens[k] + "'");
        }
        if (v[1] < 0 || v[1] >= 1e9 || v[0] != std::floor(v[0]) || v[1] != std::floor(v[1])) {
            Fail(path, n, "sec and nsec must be integers with 0 <= nsec < 1e9");
        }
        StampedPose pose;
        pose.stamp_ns = static_cast<int64_t>(v[0]) * kNanos + static_cast<int64_t>(v[1]);
        pose.T_world_body = PoseFromTranslationQuaternion(path, n, v + 2, v + 5);
        if (!numbers.empty() && numbers.front() == 0 && poses.empty()) numbers.clear();
        poses.push_back(pose);
        numbers.push_back(n);
    }
    return BuildTrajectory(path, std::move(poses), numbers);
}

void WritePaperCsv(const std::string &path, const Trajectory &trajectory) {
    WriteFileAtomically(path, [&](std::ostream &out) {
        out << "sec,nsec,x,y,z,qx,qy,qz,qw\n";
        for (const auto &pose : trajectory.poses()) {
            const int64_t sec = pose.stamp_ns >= 0 ? pose.stamp_ns / kNanos
                                                   : -((-pose.stamp_ns + kNanos - 1) / kNanos);
            out << sec << ',' << (pose.stamp_ns - sec * kNanos) << ',';
            WriteQuaternionPose(out, pose.T_world_body, ',');
        }
    });
}

}  // namespace dorado::io
