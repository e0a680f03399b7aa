// Runs a fuzz target over files and folders of inputs (the checked-in corpus and crash
// regressions), so that every input a fuzzer ever found stays a test in the ordinary build.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv) {
    std::size_t inputs = 0;
    for (int a = 1; a < argc; ++a) {
        std::vector<std::filesystem::path> files;
        if (std::filesystem::is_directory(argv[a])) {
            for (const auto &e : std::filesystem::directory_iterator(argv[a])) files.push_back(e.path());
        } else {
            files.emplace_back(argv[a]);
        }
        for (const auto &f : files) {
            std::ifstream in(f, std::ios::binary);
            const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
            ++inputs;
        }
    }
    std::printf("replayed %zu inputs without a crash\n", inputs);
    return inputs > 0 ? 0 : 1;
}
