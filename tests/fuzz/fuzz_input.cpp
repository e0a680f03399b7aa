#include "fuzz_input.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace dorado::fuzz {

std::string WriteTempFile(const std::string &name, const std::string &text) {
    static const std::filesystem::path dir = [] {
        const auto base = std::filesystem::exists("/dev/shm") ? std::filesystem::path("/dev/shm")
                                                              : std::filesystem::temp_directory_path();
        auto d = base / ("dorado_fuzz_" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    const std::string path = (dir / name).string();
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    return path;
}

}  // namespace dorado::fuzz
