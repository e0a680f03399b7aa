#pragma once
// Splits a fuzzer's bytes into typed values (zero once the bytes run out) and a remainder.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace dorado::fuzz {

class Input {
public:
    Input(const uint8_t *data, size_t size) : data_(data), size_(size) {}

    template <typename T>
    T Take() {
        T value{};
        const size_t n = std::min(sizeof(T), size_ - pos_);
        std::memcpy(&value, data_ + pos_, n);
        pos_ += n;
        return value;
    }

    std::vector<uint8_t> Rest() const { return {data_ + pos_, data_ + size_}; }
    std::string RestAsString() const { return {reinterpret_cast<const char *>(data_ + pos_), size_ - pos_}; }

private:
    const uint8_t *data_;
    size_t size_;
    size_t pos_ = 0;
};

/// Writes text to a file in a private temporary folder and returns its path.
std::string WriteTempFile(const std::string &name, const std::string &text);

}  // namespace dorado::fuzz
