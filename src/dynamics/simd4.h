// Four-lane float arithmetic through GCC/Clang vector extensions (SSE on x86-64, NEON on
// AArch64), for the per-region and per-body loops that do the same work on many independent
// items. Lanes never mix, so a lane's result does not depend on what the other lanes hold.
#pragma once

#include <cmath>
#include <cstdint>

namespace ffd::detail {

typedef float F4 __attribute__((vector_size(16)));
typedef int32_t I4 __attribute__((vector_size(16)));

inline F4 splat(float v) {
    return F4{v, v, v, v};
}
/// mask ? a : b, lane by lane (mask lanes all ones or all zeros).
inline F4 select(I4 mask, F4 a, F4 b) {
    return reinterpret_cast<F4>((reinterpret_cast<I4>(a) & mask) |
                                (reinterpret_cast<I4>(b) & ~mask));
}
inline F4 sqrt4(F4 v) {
    F4 r;
    for (int k = 0; k < 4; ++k) r[k] = std::sqrt(v[k]);
    return r;
}
inline F4 abs4(F4 v) {
    return reinterpret_cast<F4>(reinterpret_cast<I4>(v) &
                                I4{0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff});
}
inline bool any(I4 m) {
    return (m[0] | m[1] | m[2] | m[3]) != 0;
}

/// Transposes the 4x4 matrix whose rows are r0..r3 (in place: r_i becomes column i).
inline void transpose(F4& r0, F4& r1, F4& r2, F4& r3) {
    const F4 t0 = __builtin_shufflevector(r0, r1, 0, 4, 1, 5);
    const F4 t1 = __builtin_shufflevector(r0, r1, 2, 6, 3, 7);
    const F4 t2 = __builtin_shufflevector(r2, r3, 0, 4, 1, 5);
    const F4 t3 = __builtin_shufflevector(r2, r3, 2, 6, 3, 7);
    r0 = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
    r1 = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
    r2 = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
    r3 = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
}

/// Four floats from p (any alignment).
inline F4 load4(const float* p) {
    F4 v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
/// Three floats from p into lanes 0..2 (lane 3 zero), reading nothing past them.
inline F4 load3(const float* p) {
    F4 v{};
    __builtin_memcpy(&v, p, 3 * sizeof(float));
    return v;
}
inline void store4(float* p, F4 v) {
    __builtin_memcpy(p, &v, sizeof v);
}
inline void store3(float* p, F4 v) {
    __builtin_memcpy(p, &v, 3 * sizeof(float));
}

/// Four quaternions, one per lane.
struct Q4 {
    F4 w, x, y, z;
};

/// Hamilton products a b, lane by lane.
inline Q4 operator*(const Q4& a, const Q4& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
inline Q4 conjugate(const Q4& q) {
    return {q.w, -q.x, -q.y, -q.z};
}
inline Q4 normalize(const Q4& q) {
    const F4 inv = splat(1.0f) / sqrt4(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return {q.w * inv, q.x * inv, q.y * inv, q.z * inv};
}
/// normalize for quaternions already unit to within rounding (products of unit quaternions):
/// one Newton step for 1/sqrt(n) at n = 1, (3 - n) / 2, without a division.
inline Q4 renormalize(const Q4& q) {
    const F4 inv = (splat(3.0f) - (q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z)) * splat(0.5f);
    return {q.w * inv, q.x * inv, q.y * inv, q.z * inv};
}

/// Four 3-vectors, one per lane.
struct V4 {
    F4 x, y, z;
};

inline V4 operator+(const V4& a, const V4& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline V4 operator-(const V4& a, const V4& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline V4 operator*(const V4& a, F4 s) {
    return {a.x * s, a.y * s, a.z * s};
}
inline F4 dot(const V4& a, const V4& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline V4 cross(const V4& a, const V4& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

} // namespace ffd::detail
