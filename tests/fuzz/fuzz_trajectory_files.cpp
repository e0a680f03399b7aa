// libFuzzer target: TUM, KITTI and paper-CSV trajectory readers on arbitrary text.
#include "dorado/io/trajectory_io.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    dorado::fuzz::Input in(data, size);
    const int format = in.Take<uint8_t>() % 3;
    const std::string text = in.RestAsString();
    try {
        if (format == 0) {
            (void)dorado::io::ReadTum(dorado::fuzz::WriteTempFile("t.tum", text));
        } else if (format == 1) {
            (void)dorado::io::ReadPaperCsv(dorado::fuzz::WriteTempFile("t.csv", text));
        } else {
            const std::size_t half = text.find('|');
            const std::string poses = text.substr(0, half);
            const std::string times = half == std::string::npos ? "" : text.substr(half + 1);
            (void)dorado::io::ReadKitti(dorado::fuzz::WriteTempFile("p.txt", poses),
                                        dorado::fuzz::WriteTempFile("t.txt", times));
        }
    } catch (const dorado::io::TrajectoryFileError &) {
    }
    return 0;
}
