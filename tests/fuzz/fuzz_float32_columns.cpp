// libFuzzer target: raw float32 scan files (View-of-Delft / ColoRadar layout).
#include "dorado/io/pointcloud_decoder.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    dorado::fuzz::Input in(data, size);
    const int layout = in.Take<uint8_t>() % 3;
    const std::vector<std::string> columns =
        layout == 0 ? std::vector<std::string>{"x", "y", "z", "power", "doppler", "_", "_"}
        : layout == 1 ? std::vector<std::string>{"x", "y", "z", "power", "doppler"}
                      : std::vector<std::string>{"x", "y", "z", "doppler"};
    dorado::io::FieldMap map;
    map.range = map.azimuth = map.elevation = "";
    if (layout == 2) map.power = "";
    const std::vector<uint8_t> rest = in.Rest();
    try {
        dorado::RadarScan scan = dorado::io::DecodeFloat32Columns(rest.data(), rest.size(), columns, map);
        (void)dorado::io::RemoveNonFinitePoints(scan);
    } catch (const dorado::io::DecodeError &) {
    }
    return 0;
}
