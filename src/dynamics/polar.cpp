// References: Mueller, Bender, Chentanez, Macklin, "A Robust Method to Extract the Rotational
// Part of Deformations", MIG 2016; Horn, "Closed-form solution of absolute orientation using
// unit quaternions", JOSA A 4(4), 1987.
#include "dynamics/polar.h"

#include <cmath>
#include <cstring>

namespace ffd::detail {

namespace {

// Rotation of q by the world-frame rotation vector omega (angle |omega|, at most pi).
Quat turn(const Quat& q, Vec3 omega, float angle) {
    const float half = 0.5f * minNum(angle, 3.14159265f);
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

// ---- four rotations at a time ----------------------------------------------------------------

namespace ffd::detail {

namespace {

// One Newton step (Mueller's step where the Hessian is not positive definite) on four lanes.
// Lanes off in `active` keep their rotation. Returns the step angles.
F4 newtonStep(const F4 A[9], Q4& q, I4 active) {
    const F4 xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    const F4 xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    const F4 wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    const F4 one = splat(1), two = splat(2);
    const F4 R[9] = {one - two * (yy + zz), two * (xy - wz),       two * (xz + wy),
                     two * (xy + wz),       one - two * (xx + zz), two * (yz - wx),
                     two * (xz - wy),       two * (yz + wx),       one - two * (xx + yy)};
    F4 M[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            M[3 * i + j] = R[i] * A[j] + R[3 + i] * A[3 + j] + R[6 + i] * A[6 + j];
    const F4 g0 = M[7] - M[5], g1 = M[2] - M[6], g2 = M[3] - M[1];
    const F4 tr = M[0] + M[4] + M[8];
    const F4 half = splat(0.5f);
    const F4 s01 = half * (M[1] + M[3]), s02 = half * (M[2] + M[6]), s12 = half * (M[5] + M[7]);
    const F4 h00 = tr - M[0], h11 = tr - M[4], h22 = tr - M[8];
    const F4 h01 = -s01, h02 = -s02, h12 = -s12;
    const F4 a00 = h11 * h22 - h12 * h12, a01 = h02 * h12 - h01 * h22, a02 = h01 * h12 - h02 * h11;
    const F4 a11 = h00 * h22 - h02 * h02, a12 = h01 * h02 - h00 * h12, a22 = h00 * h11 - h01 * h01;
    const F4 det = h00 * a00 + h01 * a01 + h02 * a02;
    const F4 scale = abs4(tr) + splat(1e-30f);
    const F4 tiny = splat(1e-6f);
    const I4 pd =
        (h00 > tiny * scale) & (a22 > tiny * scale * scale) & (det > tiny * scale * scale * scale);
    // Newton's step H^-1 g = adj(H) g / det(H), or g / |tr M|: one division either way.
    const F4 inv = one / select(pd, det, abs4(tr) + splat(1e-9f));
    const F4 d0 = select(pd, a00 * g0 + a01 * g1 + a02 * g2, g0) * inv;
    const F4 d1 = select(pd, a01 * g0 + a11 * g1 + a12 * g2, g1) * inv;
    const F4 d2 = select(pd, a02 * g0 + a12 * g1 + a22 * g2, g2) * inv;
    // World-frame rotation vector omega = R d.
    const F4 o0 = R[0] * d0 + R[1] * d1 + R[2] * d2;
    const F4 o1 = R[3] * d0 + R[4] * d1 + R[5] * d2;
    const F4 o2 = R[6] * d0 + R[7] * d1 + R[8] * d2;
    const F4 angle = sqrt4(o0 * o0 + o1 * o1 + o2 * o2);
    const F4 h = half * angle;
    const I4 move = active & (angle > splat(1e-6f)); // also false for NaN
    // The rotation by omega: q' = (cos h, sin h omega / |omega|) q, h = |omega| / 2, by the
    // Taylor series below 0.03 rad (exact to float precision), else the library (rare: a warm
    // start that far off, as in a hard impact).
    const F4 h2 = h * h;
    F4 s = half * (one - h2 * splat(1.0f / 6.0f));
    F4 c = one - h2 * (half - h2 * splat(1.0f / 24.0f));
    const I4 large = move & (h >= splat(0.03f));
    if (any(large))
        for (int k = 0; k < 4; ++k)
            if (large[k]) {
                const float hk = 0.5f * std::fmin(angle[k], 3.14159265f);
                s[k] = std::sin(hk) / angle[k];
                c[k] = std::cos(hk);
            }
    const F4 tx = o0 * s, ty = o1 * s, tz = o2 * s;
    Q4 r;
    r.w = c * q.w - tx * q.x - ty * q.y - tz * q.z;
    r.x = c * q.x + tx * q.w + ty * q.z - tz * q.y;
    r.y = c * q.y - tx * q.z + ty * q.w + tz * q.x;
    r.z = c * q.z + tx * q.y - ty * q.x + tz * q.w;
    // Renormalise: q and the turn are unit to rounding, so one Newton step for 1/sqrt(n) at
    // n = 1, (3 - n) / 2, is exact to float precision and needs no division.
    const F4 renorm = (splat(3) - (r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z)) * half;
    q.w = select(move, r.w * renorm, q.w);
    q.x = select(move, r.x * renorm, q.x);
    q.y = select(move, r.y * renorm, q.y);
    q.z = select(move, r.z * renorm, q.z);
    return select(active, angle, splat(0));
}

} // namespace

void extractRotations4(const F4 A[9], Q4& q, int maxIterations) {
    // As extractRotation: one Newton step, a second where the first moved noticeably, and the
    // exact solution where the steps are still large (a poor warm start).
    const I4 all{-1, -1, -1, -1};
    const F4 angle = newtonStep(A, q, all);
    I4 fallback = angle > splat(1e-2f);
    if (maxIterations > 1) {
        const I4 again = angle > splat(2e-3f);
        if (any(again)) {
            const F4 angle2 = newtonStep(A, q, again);
            fallback = again & (angle2 > splat(1e-2f));
        }
    }
    if (!any(fallback)) return;
    for (int k = 0; k < 4; ++k) {
        if (!fallback[k]) continue;
        Mat3 m;
        for (int e = 0; e < 9; ++e) m.m[e / 3][e % 3] = A[e][k];
        Quat r = closestRotation(m);
        refineRotation(m, r, 2);
        q.w[k] = r.w, q.x[k] = r.x, q.y[k] = r.y, q.z[k] = r.z;
    }
}

void extractRotations(const float* const a[9], Quat* rotations, size_t count, int maxIterations) {
    size_t r = 0;
    for (; r + 4 <= count; r += 4) {
        F4 A[9];
        for (int e = 0; e < 9; ++e) std::memcpy(&A[e], a[e] + r, sizeof(F4));
        Q4 q;
        for (int k = 0; k < 4; ++k) {
            q.w[k] = rotations[r + size_t(k)].w, q.x[k] = rotations[r + size_t(k)].x;
            q.y[k] = rotations[r + size_t(k)].y, q.z[k] = rotations[r + size_t(k)].z;
        }
        extractRotations4(A, q, maxIterations);
        for (int k = 0; k < 4; ++k) rotations[r + size_t(k)] = {q.w[k], q.x[k], q.y[k], q.z[k]};
    }
    for (; r < count; ++r) {
        Mat3 m;
        for (int e = 0; e < 9; ++e) m.m[e / 3][e % 3] = a[e][r];
        extractRotation(m, rotations[r], maxIterations);
    }
}

} // namespace ffd::detail
