#pragma once
// Private to dorado_io: the little-endian primitives of the MCAP format (https://mcap.dev/spec),
// read with bounds checks, and chunk decompression through Debian's libzstd and liblz4.

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace dorado::io {

/// A record that does not fit its bytes, or a chunk that cannot be decompressed or checked.
class McapError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// MCAP record opcodes dorado reads (the others are skipped by their length).
enum class McapOp : uint8_t {
    kHeader = 0x01,
    kFooter = 0x02,
    kSchema = 0x03,
    kChannel = 0x04,
    kMessage = 0x05,
    kChunk = 0x06,
    kDataEnd = 0x0F
};

/// Reads MCAP's little-endian integers, uint32-prefixed strings and byte arrays from a buffer.
class McapCursor {
  public:
    McapCursor(const uint8_t *data, std::size_t size) : data_(data), size_(size) {}

    uint64_t Uint(int bytes) {
        const uint8_t *p = Take(static_cast<std::size_t>(bytes));
        uint64_t v = 0;
        for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
        return v;
    }
    uint16_t U16() { return static_cast<uint16_t>(Uint(2)); }
    uint32_t U32() { return static_cast<uint32_t>(Uint(4)); }
    uint64_t U64() { return Uint(8); }
    std::string String() {
        const uint32_t n = U32();
        const uint8_t *p = Take(n);
        return {reinterpret_cast<const char *>(p), n};
    }
    const uint8_t *Take(uint64_t n) {
        if (n > size_ - pos_) {
            throw McapError("record field of " + std::to_string(n) + " bytes runs past its end (" +
                            std::to_string(size_ - pos_) + " left)");
        }
        const uint8_t *p = data_ + pos_;
        pos_ += static_cast<std::size_t>(n);
        return p;
    }
    [[nodiscard]] std::size_t remaining() const { return size_ - pos_; }
    [[nodiscard]] const uint8_t *here() const { return data_ + pos_; }

  private:
    const uint8_t *data_;
    std::size_t size_;
    std::size_t pos_ = 0;
};

/// The records of a chunk, decompressed ("" = stored, "zstd", "lz4" frame). Throws McapError
/// saying what failed (an unsupported compression, a size that does not match).
[[nodiscard]] std::vector<uint8_t> DecompressChunk(const std::string &compression,
                                                   const uint8_t *records, std::size_t size,
                                                   uint64_t uncompressed_size);

/// zlib's CRC-32, the checksum MCAP specifies for chunks and the data section.
[[nodiscard]] uint32_t McapCrc32(const std::vector<uint8_t> &bytes);

}  // namespace dorado::io
