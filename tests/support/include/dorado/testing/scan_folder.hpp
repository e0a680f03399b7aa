#pragma once
// A radar's scan folder for the command-line tests: DIR/scans/NNNNN.bin (float32 rows x, y, z, rcs,
// v_r) and DIR/times.txt (10 Hz from t = 10 s), every scan the same points.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace dorado::testing {

/// `row(i, values)` fills point i's five values.
inline void WriteScanFolder(const std::filesystem::path &dir, int scans, int points,
                            const std::function<void(int, float *)> &row) {
    std::filesystem::create_directories(dir / "scans");
    std::ofstream times(dir / "times.txt");
    for (int k = 0; k < scans; ++k) {
        char name[32];
        std::snprintf(name, sizeof(name), "%05d.bin", k);
        std::ofstream scan(dir / "scans" / name, std::ios::binary);
        for (int i = 0; i < points; ++i) {
            float values[5];
            row(i, values);
            scan.write(reinterpret_cast<const char *>(values), sizeof(values));
        }
        times << 10.0 + 0.1 * k << "\n";
    }
}

/// A description's reader, folder (front/scans, front/times.txt, five float32 columns) and field
/// map for WriteScanFolder's files; the test adds its radars: list and the rest.
inline constexpr const char *kFrontFolderKeys =
    "reader: folder\nfolder:\n  scans_dir: front/scans\n  extension: .bin\n"
    "  timestamps_file: front/times.txt\n  columns: [x, y, z, rcs, v_r]\n"
    "fields: {x: x, y: y, z: z, range: \"\", azimuth: \"\", elevation: \"\", power: rcs, "
    "doppler: v_r}\n";

/// "did you mean" and the other messages: whether @p text holds @p part.
inline bool Contains(const std::string &text, const std::string &part) {
    return text.find(part) != std::string::npos;
}

}  // namespace dorado::testing
