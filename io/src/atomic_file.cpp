#include "dorado/io/atomic_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace dorado::io {

void WriteFileAtomically(const std::string &path,
                         const std::function<void(std::ostream &)> &write) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error(path + ": cannot open for writing");
        write(out);
        out.flush();
        if (!out) {
            std::remove(tmp.c_str());
            throw std::runtime_error(path + ": write failed (disk full?)");
        }
    }
    RenameIntoPlace(tmp, path);
}

void RenameIntoPlace(const std::string &tmp, const std::string &path) {
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw std::runtime_error(path +
                                 ": cannot rename the finished file into place: " + ec.message());
    }
}

void MakeDirectories(const std::string &path) {
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (ec) throw std::runtime_error(path + ": cannot create directory: " + ec.message());
}

}  // namespace dorado::io
