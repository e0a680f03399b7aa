// libFuzzer target: the PointCloud2 decoder on arbitrary layouts and bytes.
#include <cstdint>
#include <vector>

#include "dorado/io/pointcloud_decoder.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    dorado::fuzz::Input in(data, size);
    dorado::io::CloudBufferView view;
    view.height = in.Take<uint8_t>() % 4;
    view.width = in.Take<uint16_t>() % 512;
    view.point_step = in.Take<uint8_t>();
    view.row_step = in.Take<uint16_t>();
    view.is_bigendian = in.Take<uint8_t>() & 1;
    static const char *kNames[] = {"x", "y", "z", "range", "azimuth", "elevation", "power", "doppler", "other"};
    const int fields = in.Take<uint8_t>() % 10;
    for (int f = 0; f < fields; ++f) {
        view.fields.push_back({kNames[in.Take<uint8_t>() % 9], in.Take<uint8_t>(), static_cast<uint8_t>(in.Take<uint8_t>() % 10),
                               static_cast<uint32_t>(in.Take<uint8_t>() % 3)});
    }
    const std::vector<uint8_t> rest = in.Rest();
    view.data = rest.data();
    view.data_size = rest.size();
    try {
        dorado::RadarScan scan = dorado::io::DecodePointCloud(view, dorado::io::FieldMap{});
        (void)dorado::io::RemoveNonFinitePoints(scan);
    } catch (const dorado::io::DecodeError &) {
    }
    return 0;
}
