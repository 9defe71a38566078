// Small fixed-size math used throughout ffdaabb: float 3-vectors, 3x3 matrices, quaternions and
// axis-aligned boxes. Plain aggregates so that arrays of them are flat and copyable with memcpy.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ffd {

/// The larger of a and b, the other one when either is NaN: std::fmax's result, but inlined
/// (std::fmax is a library call on x86-64 unless NaNs are ruled out).
constexpr float maxNum(float a, float b) {
    return a >= b || b != b ? a : b;
}
/// The smaller of a and b, the other one when either is NaN (std::fmin's result, inlined).
constexpr float minNum(float a, float b) {
    return a <= b || b != b ? a : b;
}

struct Vec3 {
    float x = 0, y = 0, z = 0;

    constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3& operator+=(const Vec3& b) {
        x += b.x, y += b.y, z += b.z;
        return *this;
    }
    constexpr Vec3& operator-=(const Vec3& b) {
        x -= b.x, y -= b.y, z -= b.z;
        return *this;
    }
    constexpr Vec3& operator*=(float s) {
        x *= s, y *= s, z *= s;
        return *this;
    }
    friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

constexpr Vec3 operator+(Vec3 a, Vec3 b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
constexpr Vec3 operator-(Vec3 a, Vec3 b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
constexpr Vec3 operator-(Vec3 a) {
    return {-a.x, -a.y, -a.z};
}
constexpr Vec3 operator*(Vec3 a, float s) {
    return {a.x * s, a.y * s, a.z * s};
}
constexpr Vec3 operator*(float s, Vec3 a) {
    return {a.x * s, a.y * s, a.z * s};
}
constexpr Vec3 operator/(Vec3 a, float s) {
    return {a.x / s, a.y / s, a.z / s};
}
constexpr Vec3 mul(Vec3 a, Vec3 b) {
    return {a.x * b.x, a.y * b.y, a.z * b.z};
}
constexpr float dot(Vec3 a, Vec3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr float lengthSquared(Vec3 a) {
    return dot(a, a);
}
inline float length(Vec3 a) {
    return std::sqrt(dot(a, a));
}
inline Vec3 normalize(Vec3 a) {
    float l = length(a);
    return l > 0 ? a / l : Vec3{};
}
constexpr Vec3 min(Vec3 a, Vec3 b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
constexpr Vec3 max(Vec3 a, Vec3 b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
constexpr float minComponent(Vec3 a) {
    return std::min(a.x, std::min(a.y, a.z));
}
constexpr float maxComponent(Vec3 a) {
    return std::max(a.x, std::max(a.y, a.z));
}
inline bool isFinite(Vec3 a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

/// Row-major 3x3 matrix: m[row][col].
struct Mat3 {
    float m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};

    static constexpr Mat3 identity() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }
    static constexpr Mat3 diagonal(Vec3 d) { return {{{d.x, 0, 0}, {0, d.y, 0}, {0, 0, d.z}}}; }
    /// Matrix whose columns are a, b, c.
    static constexpr Mat3 fromColumns(Vec3 a, Vec3 b, Vec3 c) {
        return {{{a.x, b.x, c.x}, {a.y, b.y, c.y}, {a.z, b.z, c.z}}};
    }
    constexpr Vec3 column(int c) const { return {m[0][c], m[1][c], m[2][c]}; }
    constexpr Vec3 row(int r) const { return {m[r][0], m[r][1], m[r][2]}; }
    friend constexpr bool operator==(const Mat3&, const Mat3&) = default;
};

constexpr Vec3 operator*(const Mat3& a, Vec3 v) {
    return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
            a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
            a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
constexpr Mat3 operator*(const Mat3& a, const Mat3& b) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}
constexpr Mat3 operator+(const Mat3& a, const Mat3& b) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][j] + b.m[i][j];
    return r;
}
constexpr Mat3 operator*(const Mat3& a, float s) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][j] * s;
    return r;
}
constexpr Mat3 transpose(const Mat3& a) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[j][i];
    return r;
}
constexpr float determinant(const Mat3& a) {
    return dot(a.column(0), cross(a.column(1), a.column(2)));
}
/// Outer product a b^T.
constexpr Mat3 outer(Vec3 a, Vec3 b) {
    return {{{a.x * b.x, a.x * b.y, a.x * b.z},
             {a.y * b.x, a.y * b.y, a.y * b.z},
             {a.z * b.x, a.z * b.y, a.z * b.z}}};
}
/// Inverse of a; returns false (and leaves out untouched) when |det| <= eps.
inline bool inverse(const Mat3& a, Mat3& out, float eps = 0.0f) {
    Vec3 c0 = a.column(0), c1 = a.column(1), c2 = a.column(2);
    Vec3 r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
    float det = dot(c0, r0);
    if (!(std::fabs(det) > eps)) return false;
    float inv = 1.0f / det;
    out = {{{r0.x * inv, r0.y * inv, r0.z * inv},
            {r1.x * inv, r1.y * inv, r1.z * inv},
            {r2.x * inv, r2.y * inv, r2.z * inv}}};
    return true;
}

/// Unit quaternion (w + xi + yj + zk) for rotations.
struct Quat {
    float w = 1, x = 0, y = 0, z = 0;

    static Quat fromAxisAngle(Vec3 axis, float radians) {
        Vec3 n = normalize(axis);
        float s = std::sin(0.5f * radians);
        return {std::cos(0.5f * radians), n.x * s, n.y * s, n.z * s};
    }
    friend constexpr bool operator==(const Quat&, const Quat&) = default;
};

constexpr Quat operator*(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
inline Quat normalize(const Quat& q) {
    float l = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return l > 0 ? Quat{q.w / l, q.x / l, q.y / l, q.z / l} : Quat{};
}
constexpr Mat3 toMat3(const Quat& q) {
    float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    return {{{1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy)},
             {2 * (xy + wz), 1 - 2 * (xx + zz), 2 * (yz - wx)},
             {2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy)}}};
}
constexpr Vec3 rotate(const Quat& q, Vec3 v) {
    return toMat3(q) * v;
}

/// Axis-aligned box; an empty box has lo > hi.
struct Aabb {
    Vec3 lo{1e30f, 1e30f, 1e30f};
    Vec3 hi{-1e30f, -1e30f, -1e30f};

    constexpr bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    constexpr void add(Vec3 p) { lo = ffd::min(lo, p), hi = ffd::max(hi, p); }
    constexpr void add(const Aabb& b) { lo = ffd::min(lo, b.lo), hi = ffd::max(hi, b.hi); }
    constexpr Vec3 centre() const { return (lo + hi) * 0.5f; }
    constexpr Vec3 extent() const { return hi - lo; }
    constexpr bool contains(Vec3 p, float tol = 0) const {
        return p.x >= lo.x - tol && p.y >= lo.y - tol && p.z >= lo.z - tol && p.x <= hi.x + tol &&
               p.y <= hi.y + tol && p.z <= hi.z + tol;
    }
    constexpr bool overlaps(const Aabb& b) const {
        return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y &&
               lo.z <= b.hi.z && b.lo.z <= hi.z;
    }
};

/// Trilinear weights of local coordinates (s,t,u) in [0,1]^3 for the 8 corners of a cell,
/// corner index c = i + 2 j + 4 k with (i,j,k) in {0,1}^3 (i along x, j along y, k along z).
inline void trilinearWeights(Vec3 stu, float outWeights[8]) {
    float s = stu.x, t = stu.y, u = stu.z;
    float s0 = 1 - s, t0 = 1 - t, u0 = 1 - u;
    outWeights[0] = s0 * t0 * u0;
    outWeights[1] = s * t0 * u0;
    outWeights[2] = s0 * t * u0;
    outWeights[3] = s * t * u0;
    outWeights[4] = s0 * t0 * u;
    outWeights[5] = s * t0 * u;
    outWeights[6] = s0 * t * u;
    outWeights[7] = s * t * u;
}

} // namespace ffd
