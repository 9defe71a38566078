// 4x4 matrices for the renderer's camera and shadows, column-major as OpenGL takes them.
#pragma once

#include "ffdaabb/math.h"

#include <cmath>

namespace ffd::render::detail {

struct Vec4 {
    float x = 0, y = 0, z = 0, w = 0;
};

/// Column-major: element (row r, column c) is m[c * 4 + r].
struct Mat4 {
    float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

    float& at(int row, int col) { return m[col * 4 + row]; }
    float at(int row, int col) const { return m[col * 4 + row]; }
};

inline Mat4 operator*(const Mat4& a, const Mat4& b) {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            float s = 0;
            for (int k = 0; k < 4; ++k) s += a.at(i, k) * b.at(k, j);
            r.at(i, j) = s;
        }
    return r;
}

inline Vec4 operator*(const Mat4& a, Vec4 v) {
    const float in[4] = {v.x, v.y, v.z, v.w};
    float out[4];
    for (int i = 0; i < 4; ++i)
        out[i] = a.at(i, 0) * in[0] + a.at(i, 1) * in[1] + a.at(i, 2) * in[2] + a.at(i, 3) * in[3];
    return {out[0], out[1], out[2], out[3]};
}

/// gluLookAt: the view matrix of an eye looking at target.
inline Mat4 lookAt(Vec3 eye, Vec3 target, Vec3 up) {
    const Vec3 f = normalize(target - eye);
    Vec3 s = cross(f, up);
    // Looking straight along `up`: any perpendicular will do.
    if (lengthSquared(s) < 1e-12f)
        s = cross(f, std::fabs(f.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 0, 1});
    s = normalize(s);
    const Vec3 u = cross(s, f);
    Mat4 r;
    r.at(0, 0) = s.x, r.at(0, 1) = s.y, r.at(0, 2) = s.z, r.at(0, 3) = -dot(s, eye);
    r.at(1, 0) = u.x, r.at(1, 1) = u.y, r.at(1, 2) = u.z, r.at(1, 3) = -dot(u, eye);
    r.at(2, 0) = -f.x, r.at(2, 1) = -f.y, r.at(2, 2) = -f.z, r.at(2, 3) = dot(f, eye);
    return r;
}

/// gluPerspective.
inline Mat4 perspective(float fovYRadians, float aspect, float zNear, float zFar) {
    const float f = 1.0f / std::tan(0.5f * fovYRadians);
    Mat4 r;
    r.at(0, 0) = f / aspect;
    r.at(1, 1) = f;
    r.at(2, 2) = (zFar + zNear) / (zNear - zFar);
    r.at(2, 3) = 2 * zFar * zNear / (zNear - zFar);
    r.at(3, 2) = -1;
    r.at(3, 3) = 0;
    return r;
}

/// Projection onto the plane y = height along the direction -toLight (a directional light):
/// p -> p - toLight * (p.y - height) / toLight.y.
inline Mat4 planarShadow(Vec3 toLight, float height) {
    Mat4 r;
    const float iy = 1.0f / toLight.y;
    r.at(0, 1) = -toLight.x * iy, r.at(0, 3) = toLight.x * iy * height;
    r.at(1, 1) = 0, r.at(1, 3) = height;
    r.at(2, 1) = -toLight.z * iy, r.at(2, 3) = toLight.z * iy * height;
    return r;
}

} // namespace ffd::render::detail
