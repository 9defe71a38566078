// Reference: Mueller, Bender, Chentanez, Macklin, "A Robust Method to Extract the Rotational
// Part of Deformations", MIG 2016.
#include "dynamics/polar.h"

#include <cmath>

namespace ffd::detail {

int extractRotation(const Mat3& A, Quat& q, int maxIterations, float tolerance) {
    const Vec3 a0 = A.column(0), a1 = A.column(1), a2 = A.column(2);
    int it = 0;
    for (; it < maxIterations; ++it) {
        const Mat3 R = toMat3(q);
        const Vec3 r0 = R.column(0), r1 = R.column(1), r2 = R.column(2);
        const Vec3 torque = cross(r0, a0) + cross(r1, a1) + cross(r2, a2);
        const float alignment = std::fabs(dot(r0, a0) + dot(r1, a1) + dot(r2, a2));
        const Vec3 omega = torque * (1.0f / (alignment + 1e-9f));
        const float angle = length(omega);
        if (!(angle > tolerance)) break; // also stops on NaN input
        // Rotation by `angle` about omega. Small angles are the common (warm-started) case:
        // there the Taylor series is exact to float precision and much cheaper than sin/cos;
        // large ones (a cold start, a reflection) take the real functions.
        const float half = 0.5f * std::fmin(angle, 3.14159265f);
        float s, c;
        if (half < 0.03f) {
            const float h2 = half * half;
            s = 0.5f * (1.0f - h2 * (1.0f / 6.0f)) * (half * 2.0f / angle);
            c = 1.0f - h2 * (0.5f - h2 * (1.0f / 24.0f));
        } else {
            s = std::sin(half) / angle;
            c = std::cos(half);
        }
        const Quat turn{c, omega.x * s, omega.y * s, omega.z * s};
        q = normalize(turn * q);
    }
    return it;
}

} // namespace ffd::detail
