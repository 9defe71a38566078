// References: Mueller, Bender, Chentanez, Macklin, "A Robust Method to Extract the Rotational
// Part of Deformations", MIG 2016; Horn, "Closed-form solution of absolute orientation using
// unit quaternions", JOSA A 4(4), 1987.
#include "dynamics/polar.h"

#include <cmath>

namespace ffd::detail {

namespace {

// Rotation of q by the world-frame rotation vector omega (angle |omega|, at most pi).
Quat turn(const Quat& q, Vec3 omega, float angle) {
    const float half = 0.5f * std::fmin(angle, 3.14159265f);
    float s, c;
    if (half < 0.03f) {
        // Taylor series: exact to float precision here and much cheaper than sin/cos.
        const float h2 = half * half;
        s = 0.5f * (1.0f - h2 * (1.0f / 6.0f)) * (2.0f * half / angle);
        c = 1.0f - h2 * (0.5f - h2 * (1.0f / 24.0f));
    } else {
        s = std::sin(half) / angle;
        c = std::cos(half);
    }
    return normalize(Quat{c, omega.x * s, omega.y * s, omega.z * s} * q);
}

} // namespace

float refineRotation(const Mat3& A, Quat& q, int maxIterations, float tolerance) {
    float angle = 0;
    for (int it = 0; it < maxIterations; ++it) {
        const Mat3 R = toMat3(q);
        const Mat3 M = transpose(R) * A;
        const Vec3 g{M.m[2][1] - M.m[1][2], M.m[0][2] - M.m[2][0], M.m[1][0] - M.m[0][1]};
        const float tr = M.m[0][0] + M.m[1][1] + M.m[2][2];
        // H = tr(M) I - sym(M); Newton when it is positive definite (leading minors > 0).
        const float sxy = 0.5f * (M.m[0][1] + M.m[1][0]), sxz = 0.5f * (M.m[0][2] + M.m[2][0]),
                    syz = 0.5f * (M.m[1][2] + M.m[2][1]);
        const Mat3 H{{{tr - M.m[0][0], -sxy, -sxz},
                      {-sxy, tr - M.m[1][1], -syz},
                      {-sxz, -syz, tr - M.m[2][2]}}};
        const float m1 = H.m[0][0], m2 = H.m[0][0] * H.m[1][1] - sxy * sxy, m3 = determinant(H);
        Vec3 local;
        Mat3 Hinv;
        const float scale = std::fabs(tr) + 1e-30f;
        if (m1 > 1e-6f * scale && m2 > 1e-6f * scale * scale &&
            m3 > 1e-6f * scale * scale * scale && inverse(H, Hinv))
            local = Hinv * g;
        else
            local = g / (std::fabs(tr) + 1e-9f);
        const Vec3 omega = R * local;
        angle = length(omega);
        if (!(angle > tolerance)) break; // also stops on NaN
        q = turn(q, omega, angle);
    }
    return angle;
}

Quat closestRotation(const Mat3& A) {
    const auto& a = A.m;
    // q^T N q = tr(R(q)^T A) for q = (w, x, y, z).
    double N[4][4] = {
        {a[0][0] + a[1][1] + a[2][2], a[2][1] - a[1][2], a[0][2] - a[2][0], a[1][0] - a[0][1]},
        {a[2][1] - a[1][2], a[0][0] - a[1][1] - a[2][2], a[0][1] + a[1][0], a[0][2] + a[2][0]},
        {a[0][2] - a[2][0], a[0][1] + a[1][0], -a[0][0] + a[1][1] - a[2][2], a[1][2] + a[2][1]},
        {a[1][0] - a[0][1], a[0][2] + a[2][0], a[1][2] + a[2][1], -a[0][0] - a[1][1] + a[2][2]}};
    double V[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    // Cyclic Jacobi: rotate away the off-diagonal entries; N becomes diagonal, V its
    // eigenvectors (columns).
    for (int sweep = 0; sweep < 30; ++sweep) {
        double off = 0;
        for (int p = 0; p < 4; ++p)
            for (int r = p + 1; r < 4; ++r) off += N[p][r] * N[p][r];
        if (off < 1e-30) break;
        for (int p = 0; p < 4; ++p)
            for (int r = p + 1; r < 4; ++r) {
                if (std::fabs(N[p][r]) < 1e-300) continue;
                const double theta = (N[r][r] - N[p][p]) / (2 * N[p][r]);
                const double t =
                    (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 4; ++k) {
                    const double nkp = N[k][p], nkr = N[k][r];
                    N[k][p] = c * nkp - s * nkr;
                    N[k][r] = s * nkp + c * nkr;
                }
                for (int k = 0; k < 4; ++k) {
                    const double npk = N[p][k], nrk = N[r][k];
                    N[p][k] = c * npk - s * nrk;
                    N[r][k] = s * npk + c * nrk;
                }
                for (int k = 0; k < 4; ++k) {
                    const double vkp = V[k][p], vkr = V[k][r];
                    V[k][p] = c * vkp - s * vkr;
                    V[k][r] = s * vkp + c * vkr;
                }
            }
    }
    int best = 0;
    for (int k = 1; k < 4; ++k)
        if (N[k][k] > N[best][best]) best = k;
    const Quat q{float(V[0][best]), float(V[1][best]), float(V[2][best]), float(V[3][best])};
    return normalize(q);
}

void extractRotation(const Mat3& A, Quat& q, int maxIterations) {
    // One Newton step from the warm start; a second only when the first moved the rotation
    // noticeably (Newton's error after it is about the square of that step).
    float angle = refineRotation(A, q, 1);
    if (angle > 2e-3f && maxIterations > 1) angle = refineRotation(A, q, maxIterations - 1);
    // A step still this large means the warm start was far off (a teleport, a cold start, a
    // violent deformation): solve exactly instead.
    if (angle > 1e-2f) {
        q = closestRotation(A);
        refineRotation(A, q, 2);
    }
}

} // namespace ffd::detail
