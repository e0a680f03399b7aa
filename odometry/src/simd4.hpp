#pragma once
// Internal to dorado_odometry: 4-wide double vectors (GCC/Clang vector extensions) for the
// per-point loops. A function marked DORADO_SIMD_CLONES is compiled twice, for AVX2 and for the
// default target, and picked at load time; both clones run the same 4 lanes with the same sums
// (the default one as two SSE2 registers), so results do not depend on the machine. No FMA in
// either: products and sums are rounded as the scalar expressions they replace.
#include <cstring>

// The helpers are inlined into their clones; their (AVX) ABI never crosses a call.
#pragma GCC diagnostic ignored "-Wpsabi"

#define DORADO_SIMD_CLONES __attribute__((target_clones("avx2", "default")))

namespace dorado::odometry::internal::simd {

typedef double Vec4 __attribute__((vector_size(32)));
typedef long long Mask4 __attribute__((vector_size(32)));
constexpr int kLanes = 4;

inline Vec4 Load(const double *p) {
    Vec4 v;
    std::memcpy(&v, p, sizeof v);  // an unaligned vector load
    return v;
}
inline void Store(double *p, Vec4 v) {
    std::memcpy(p, &v, sizeof v);
}
inline Vec4 Broadcast(double x) {
    return Vec4{x, x, x, x};
}
/// Lanes summed in a fixed order.
inline double Sum(Vec4 v) {
    return (v[0] + v[1]) + (v[2] + v[3]);
}
inline long long Sum(Mask4 v) {
    return (v[0] + v[1]) + (v[2] + v[3]);
}
/// 1.0 where the mask is set (all bits), 0.0 elsewhere.
inline Vec4 Select(Mask4 mask, Vec4 v) {
    return (Vec4)((Mask4)v & mask);
}

}  // namespace dorado::odometry::internal::simd
