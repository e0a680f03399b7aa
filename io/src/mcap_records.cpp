// MCAP chunk decompression: libzstd (one-shot) and liblz4's frame API; CRC-32 from zlib (the
// checksum MCAP specifies is zlib's crc32).
#include "mcap_records.hpp"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

namespace dorado::io {

namespace {

/// Chunks larger than this are refused rather than allocated (rosbag2 writes ~1 MB chunks; a
/// corrupt size field must not become a multi-gigabyte allocation).
constexpr uint64_t kMaxChunkBytes = 512ull << 20;

void Lz4Decompress(const uint8_t *in, std::size_t in_size, std::vector<uint8_t> &out) {
    LZ4F_dctx *ctx = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
        throw McapError("lz4: cannot create a decompression context");
    std::size_t in_pos = 0;
    std::size_t out_pos = 0;
    std::string error;
    while (error.empty()) {
        std::size_t src = in_size - in_pos;
        std::size_t dst = out.size() - out_pos;
        const std::size_t rc =
            LZ4F_decompress(ctx, out.data() + out_pos, &dst, in + in_pos, &src, nullptr);
        if (LZ4F_isError(rc)) error = std::string("lz4: ") + LZ4F_getErrorName(rc);
        in_pos += src;
        out_pos += dst;
        if (rc == 0) break;  // the frame is complete
        if (error.empty() && src == 0 && dst == 0) error = "lz4: frame ends early";
    }
    LZ4F_freeDecompressionContext(ctx);
    if (!error.empty()) throw McapError(error);
    if (out_pos != out.size()) {
        throw McapError("lz4: " + std::to_string(out_pos) + " bytes decompressed, the chunk says " +
                        std::to_string(out.size()));
    }
}

}  // namespace

std::vector<uint8_t> DecompressChunk(const std::string &compression, const uint8_t *records,
                                     std::size_t size, uint64_t uncompressed_size) {
    if (compression != "" && compression != "zstd" && compression != "lz4") {
        throw McapError("compression '" + compression +
                        "' is not supported (zstd, lz4 or none are)");
    }
    if (uncompressed_size > kMaxChunkBytes) {
        throw McapError("uncompressed size " + std::to_string(uncompressed_size) +
                        " bytes is over the reader's limit");
    }
    std::vector<uint8_t> out;
    if (compression.empty()) {
        if (uncompressed_size != size) throw McapError("stored chunk size does not match");
        out.assign(records, records + size);
    } else if (compression == "zstd") {
        // The frame says its size (the MCAP writers and zstd's own tools write it): checked before
        // anything is allocated.
        const unsigned long long frame = ZSTD_getFrameContentSize(records, size);
        if (frame == ZSTD_CONTENTSIZE_ERROR) throw McapError("zstd: not a zstd frame");
        if (frame != ZSTD_CONTENTSIZE_UNKNOWN && frame != uncompressed_size)
            throw McapError("zstd: the frame holds " + std::to_string(frame) +
                            " bytes, the chunk says " + std::to_string(uncompressed_size));
        out.resize(uncompressed_size);
        const std::size_t rc = ZSTD_decompress(out.data(), out.size(), records, size);
        if (ZSTD_isError(rc)) throw McapError(std::string("zstd: ") + ZSTD_getErrorName(rc));
        if (rc != out.size()) throw McapError("zstd: fewer bytes than the chunk says");
    } else {
        if (uncompressed_size > 256 * static_cast<uint64_t>(size) + 64)  // above lz4's ratio
            throw McapError("lz4: the chunk's uncompressed size cannot come from its bytes");
        out.resize(uncompressed_size);
        Lz4Decompress(records, size, out);
    }
    return out;
}

uint32_t McapCrc32(const std::vector<uint8_t> &bytes) {
    return static_cast<uint32_t>(crc32(0L, bytes.data(), static_cast<uInt>(bytes.size())));
}

}  // namespace dorado::io
