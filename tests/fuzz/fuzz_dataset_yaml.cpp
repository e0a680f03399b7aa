// libFuzzer target: the dataset description parser on arbitrary YAML.
#include "dorado/io/dataset_config.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string text(reinterpret_cast<const char *>(data), size);
    try {
        (void)dorado::io::LoadDatasetConfig(dorado::fuzz::WriteTempFile("d.yaml", text));
    } catch (const dorado::io::ConfigError &) {
    }
    return 0;
}
