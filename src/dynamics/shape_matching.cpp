// Reference: Rivers & James, "FastLSM: Fast Lattice Shape Matching for Robust Real-Time
// Deformation", SIGGRAPH 2007 (regions, fast summation); Mueller et al., "Meshless Deformations
// Based on Shape Matching", SIGGRAPH 2005 (integration); Mueller et al., "Position Based
// Dynamics", 2006 (rigid-motion-preserving damping, here per region).
#include "dynamics/shape_matching.h"

#include "dynamics/mass_spring.h"
#include "dynamics/polar.h"
#include "ffdaabb/error.h"

#include <algorithm>
#include <cstring>

namespace ffd::detail {

namespace {

// First summation: per region r, sums over its members j of
//   m~ x (3) | m~ x x0^T (9, row-major) | m~ v (3) | m~ x cross v (3) | m~ x x^T (6: xx yy zz xy xz
//   yz)
constexpr int kFirstChannels = 24;
// Second summation: per particle i, sums over the regions r containing it of
//   R_r (9, row-major) | t_r (3) | omega_r (3) | u_r = v_cm - omega x c (3)
constexpr int kSecondChannels = 18;

// One axis of the separable (2w+1)^3 box sum over the point grid, point-major: out[g][0..C) =
// sum of in[g + d * stride][0..C) over the window's points inside the grid. The channels go
// twelve at a time (three vector registers), so that long rows (four bodies' channels) stay
// in registers instead of spilling.
template <int C>
void boxPass(const float* in, float* out, GridCoord dims, int axis, int w) {
    auto load = [](const float* p) {
        F4 v;
        __builtin_memcpy(&v, p, sizeof v);
        return v;
    };
    const ptrdiff_t stride = axis == 0 ? 1 : (axis == 1 ? dims[0] : ptrdiff_t(dims[0]) * dims[1]);
    const int n = dims[axis];
    size_t g = 0;
    for (int z = 0; z < dims[2]; ++z)
        for (int y = 0; y < dims[1]; ++y)
            for (int x = 0; x < dims[0]; ++x, ++g) {
                const int c = axis == 0 ? x : (axis == 1 ? y : z);
                const int lo = std::max(-w, -c), hi = std::min(w, n - 1 - c);
                for (int k = 0; k + 12 <= C; k += 12) {
                    const float* self = in + g * C + k;
                    F4 a0 = load(self), a1 = load(self + 4), a2 = load(self + 8);
                    for (int d = lo; d <= hi; ++d) {
                        if (d == 0) continue;
                        const float* other = in + (ptrdiff_t(g) + d * stride) * C + k;
                        a0 += load(other), a1 += load(other + 4), a2 += load(other + 8);
                    }
                    float* o = out + g * C + k;
                    __builtin_memcpy(o, &a0, sizeof a0);
                    __builtin_memcpy(o + 4, &a1, sizeof a1);
                    __builtin_memcpy(o + 8, &a2, sizeof a2);
                }
                for (int k = C - C % 12; k < C; ++k) { // the tail shorter than twelve, if any
                    float acc = in[g * C + size_t(k)];
                    for (int d = lo; d <= hi; ++d)
                        if (d != 0) acc += in[(ptrdiff_t(g) + d * stride) * C + k];
                    out[g * C + size_t(k)] = acc;
                }
            }
}

// Cube sums of C channels: scattered input in a, result in b.
template <int C>
void cubeSum(const ShapeMatchingModel& model, std::vector<float>& a, std::vector<float>& b) {
    boxPass<C>(a.data(), b.data(), model.pointDims, 0, model.halfWidth);
    boxPass<C>(b.data(), a.data(), model.pointDims, 1, model.halfWidth);
    boxPass<C>(a.data(), b.data(), model.pointDims, 2, model.halfWidth);
}

// Region values from the first sums: rotation, translation and rigid velocity.
struct RegionFrame {
    Mat3 R;
    Vec3 t;     // c_r - R_r c0_r
    Vec3 omega; // angular velocity of the region's rigid motion
    Vec3 u;     // v_cm - omega x c_r
};

RegionFrame regionFrame(const ShapeMatchingModel& model, uint32_t r, const float* S, Quat& q,
                        int iterations, bool wantVelocity) {
    const float M = model.regionMass[r];
    const float invM = 1.0f / M;
    const Vec3 c{S[0] * invM, S[1] * invM, S[2] * invM};
    const Vec3 c0 = model.regionRestCentre[r];
    Mat3 A;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) A.m[i][j] = S[3 + 3 * i + j] - M * c[i] * c0[j];
    extractRotation(A, q, iterations);
    RegionFrame f;
    f.R = toMat3(q);
    f.t = c - f.R * c0;
    if (!wantVelocity) return f;
    const Vec3 vcm{S[12] * invM, S[13] * invM, S[14] * invM};
    const Vec3 L = Vec3{S[15], S[16], S[17]} - cross(c, vcm) * M;
    // Inertia about c: sum m~ (|r|^2 I - r r^T) with r = x - c.
    const float xx = S[18] - M * c.x * c.x, yy = S[19] - M * c.y * c.y, zz = S[20] - M * c.z * c.z;
    const float xy = S[21] - M * c.x * c.y, xz = S[22] - M * c.x * c.z, yz = S[23] - M * c.y * c.z;
    const float trace = xx + yy + zz;
    // A region that is flat or a line has a singular inertia; a small isotropic term keeps
    // the solve well posed and only damps the (ill-defined) spin about the degenerate axis.
    const float reg = 1e-4f * trace + 1e-30f;
    const Mat3 I{
        {{trace - xx + reg, -xy, -xz}, {-xy, trace - yy + reg, -yz}, {-xz, -yz, trace - zz + reg}}};
    Mat3 Iinv;
    f.omega = inverse(I, Iinv) ? Iinv * L : Vec3{};
    f.u = vcm - cross(f.omega, c);
    return f;
}

void writeSecond(float* out, size_t stride, const RegionFrame& f) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[(3 * i + j) * stride] = f.R.m[i][j];
    out[9 * stride] = f.t.x, out[10 * stride] = f.t.y, out[11 * stride] = f.t.z;
    out[12 * stride] = f.omega.x, out[13 * stride] = f.omega.y, out[14 * stride] = f.omega.z;
    out[15 * stride] = f.u.x, out[16 * stride] = f.u.y, out[17 * stride] = f.u.z;
}

// First-summation channels of particle j (positions relative to the body's reference point).
void firstChannels(float* out, size_t stride, float m, Vec3 xr, Vec3 x0, Vec3 vel) {
    const Vec3 mx = xr * m;
    out[0] = mx.x, out[stride] = mx.y, out[2 * stride] = mx.z;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[(3 + 3 * i + j) * stride] = mx[i] * x0[j];
    const Vec3 mv = vel * m, mxv = cross(mx, vel);
    out[12 * stride] = mv.x, out[13 * stride] = mv.y, out[14 * stride] = mv.z;
    out[15 * stride] = mxv.x, out[16 * stride] = mxv.y, out[17 * stride] = mxv.z;
    out[18 * stride] = mx.x * xr.x, out[19 * stride] = mx.y * xr.y, out[20 * stride] = mx.z * xr.z;
    out[21 * stride] = mx.x * xr.y, out[22 * stride] = mx.x * xr.z, out[23 * stride] = mx.y * xr.z;
}

// Goals (relative to ref) and rigid velocities of every particle. outGoal/outRigid: #P.
void computeGoals(const ShapeMatchingModel& model, std::span<const Vec3> x, std::span<const Vec3> v,
                  Vec3 ref, std::span<Quat> rotations, int iterations, bool wantVelocity,
                  ShapeMatchingScratch& s, bool naive) {
    const size_t P = model.particlePoint.size();
    s.goal.resize(P);
    s.rigidVelocity.resize(P);
    if (naive) {
        s.region.resize(P * kSecondChannels);
        float S[kFirstChannels], T[kFirstChannels];
        for (uint32_t r = 0; r < P; ++r) {
            std::fill(S, S + kFirstChannels, 0.0f);
            for (uint32_t k = model.memberStart[r]; k < model.memberStart[r + 1]; ++k) {
                const uint32_t j = model.members[k];
                firstChannels(T, 1, model.tildeMass[j], x[j] - ref, model.restCentred[j],
                              v.empty() ? Vec3{} : v[j]);
                for (int c = 0; c < kFirstChannels; ++c) S[c] += T[c];
            }
            const RegionFrame f = regionFrame(model, r, S, rotations[r], iterations, wantVelocity);
            writeSecond(&s.region[r * kSecondChannels], 1, f);
        }
        for (uint32_t i = 0; i < P; ++i) {
            float U[kSecondChannels] = {};
            for (uint32_t k = model.memberStart[i]; k < model.memberStart[i + 1]; ++k) {
                const float* f = &s.region[model.members[k] * kSecondChannels];
                for (int c = 0; c < kSecondChannels; ++c) U[c] += f[c];
            }
            const float inv = 1.0f / model.regionSize[i];
            const Vec3 x0 = model.restCentred[i];
            const Mat3 SR{{{U[0], U[1], U[2]}, {U[3], U[4], U[5]}, {U[6], U[7], U[8]}}};
            s.goal[i] = (SR * x0 + Vec3{U[9], U[10], U[11]}) * inv;
            s.rigidVelocity[i] =
                (Vec3{U[15], U[16], U[17]} + cross(Vec3{U[12], U[13], U[14]}, x[i] - ref)) * inv;
        }
        return;
    }

    const size_t G = model.pointCount();
    s.a.resize(G * kFirstChannels);
    s.b.resize(G * kFirstChannels);
    auto first = [&]<int C>() {
        std::memset(s.a.data(), 0, G * C * sizeof(float));
        float T[kFirstChannels];
        for (uint32_t j = 0; j < P; ++j) {
            firstChannels(T, 1, model.tildeMass[j], x[j] - ref, model.restCentred[j],
                          v.empty() ? Vec3{} : v[j]);
            std::memcpy(&s.a[size_t(model.particlePoint[j]) * C], T, C * sizeof(float));
        }
        cubeSum<C>(model, s.a, s.b);
        // Regions: their sums give their frames, scattered for the second summation.
        s.region.resize(P * kSecondChannels);
        if constexpr (C == 12) {
            // Without region damping: all the rotations at once (four at a time), then t.
            s.soa.resize(P * 12);
            float* A[9];
            for (int e = 0; e < 9; ++e) A[e] = s.soa.data() + size_t(e) * P;
            float* cx = s.soa.data() + 9 * P;
            for (uint32_t r = 0; r < P; ++r) {
                const float* S = &s.b[size_t(model.particlePoint[r]) * C];
                const float M = model.regionMass[r], invM = 1.0f / M;
                const Vec3 c{S[0] * invM, S[1] * invM, S[2] * invM};
                const Vec3 c0 = model.regionRestCentre[r];
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j)
                        A[3 * i + j][r] = S[3 + 3 * i + j] - M * c[i] * c0[j];
                cx[3 * r] = c.x, cx[3 * r + 1] = c.y, cx[3 * r + 2] = c.z;
            }
            extractRotations(A, rotations.data(), P, iterations);
            for (uint32_t r = 0; r < P; ++r) {
                RegionFrame f;
                f.R = toMat3(rotations[r]);
                f.t =
                    Vec3{cx[3 * r], cx[3 * r + 1], cx[3 * r + 2]} - f.R * model.regionRestCentre[r];
                writeSecond(&s.region[r * kSecondChannels], 1, f);
            }
        } else {
            for (uint32_t r = 0; r < P; ++r) {
                const RegionFrame f =
                    regionFrame(model, r, &s.b[size_t(model.particlePoint[r]) * C], rotations[r],
                                iterations, wantVelocity);
                writeSecond(&s.region[r * kSecondChannels], 1, f);
            }
        }
    };
    auto second = [&]<int C>() {
        std::memset(s.a.data(), 0, G * C * sizeof(float));
        for (uint32_t r = 0; r < P; ++r)
            std::memcpy(&s.a[size_t(model.particlePoint[r]) * C], &s.region[r * kSecondChannels],
                        C * sizeof(float));
        cubeSum<C>(model, s.a, s.b);
        for (uint32_t i = 0; i < P; ++i) {
            const float* U = &s.b[size_t(model.particlePoint[i]) * C];
            const float inv = 1.0f / model.regionSize[i];
            const Mat3 SR{{{U[0], U[1], U[2]}, {U[3], U[4], U[5]}, {U[6], U[7], U[8]}}};
            s.goal[i] = (SR * model.restCentred[i] + Vec3{U[9], U[10], U[11]}) * inv;
            if constexpr (C > 12)
                s.rigidVelocity[i] =
                    (Vec3{U[15], U[16], U[17]} + cross(Vec3{U[12], U[13], U[14]}, x[i] - ref)) *
                    inv;
        }
    };
    if (wantVelocity) {
        first.template operator()<kFirstChannels>();
        second.template operator()<kSecondChannels>();
    } else {
        first.template operator()<12>();
        second.template operator()<12>();
    }
}

Vec3 massCentre(const ShapeMatchingModel& model, std::span<const Vec3> x) {
    Vec3 c{};
    for (size_t i = 0; i < x.size(); ++i) c += x[i] * model.massFraction[i];
    return c;
}

} // namespace

ShapeMatchingModel buildShapeMatching(const Lattice& lattice, int w) {
    if (w < 1 || w > 4)
        throw InputError("body.regionHalfWidth", "region half-width " + std::to_string(w) +
                                                     " is out of range (expected 1..4)");
    ShapeMatchingModel m;
    m.halfWidth = w;
    for (int a = 0; a < 3; ++a) m.pointDims[a] = lattice.dims[a] + 1;
    const size_t P = lattice.particleCount();
    const size_t px = size_t(m.pointDims[0]), py = size_t(m.pointDims[1]);
    std::vector<int32_t> at(m.pointCount(), -1);
    m.particlePoint.resize(P);
    for (size_t p = 0; p < P; ++p) {
        const GridCoord& g = lattice.particleCoords[p];
        const size_t idx = size_t(g[0]) + px * (size_t(g[1]) + py * size_t(g[2]));
        m.particlePoint[p] = uint32_t(idx);
        at[idx] = int32_t(p);
    }
    // Members: the particles in the cube around each particle, in grid order.
    m.memberStart.push_back(0);
    for (size_t p = 0; p < P; ++p) {
        const GridCoord& g = lattice.particleCoords[p];
        for (int dz = -w; dz <= w; ++dz)
            for (int dy = -w; dy <= w; ++dy)
                for (int dx = -w; dx <= w; ++dx) {
                    const int qx = g[0] + dx, qy = g[1] + dy, qz = g[2] + dz;
                    if (qx < 0 || qy < 0 || qz < 0 || qx >= m.pointDims[0] ||
                        qy >= m.pointDims[1] || qz >= m.pointDims[2])
                        continue;
                    const size_t idx = size_t(qx) + px * (size_t(qy) + py * size_t(qz));
                    if (at[idx] >= 0) m.members.push_back(uint32_t(at[idx]));
                }
        m.memberStart.push_back(uint32_t(m.members.size()));
    }
    m.massFraction = lattice.massFraction;
    m.regionSize.resize(P);
    m.tildeMass.resize(P);
    for (size_t p = 0; p < P; ++p) {
        m.regionSize[p] = float(m.memberStart[p + 1] - m.memberStart[p]);
        m.tildeMass[p] = m.massFraction[p] / m.regionSize[p];
    }
    Vec3 centre{};
    for (size_t p = 0; p < P; ++p) centre += lattice.restParticles[p] * m.massFraction[p];
    m.restCentred.resize(P);
    for (size_t p = 0; p < P; ++p) m.restCentred[p] = lattice.restParticles[p] - centre;
    m.regionMass.resize(P);
    m.regionRestCentre.resize(P);
    for (size_t r = 0; r < P; ++r) {
        float M = 0;
        Vec3 c{};
        for (uint32_t k = m.memberStart[r]; k < m.memberStart[r + 1]; ++k) {
            const uint32_t j = m.members[k];
            M += m.tildeMass[j];
            c += m.restCentred[j] * m.tildeMass[j];
        }
        m.regionMass[r] = M;
        m.regionRestCentre[r] = c / M;
    }
    return m;
}

void shapeMatchingGoals(const ShapeMatchingModel& model, std::span<const Vec3> x,
                        std::span<Quat> rotations, int rotationIterations,
                        ShapeMatchingScratch& scratch, std::span<Vec3> outGoals, bool naive) {
    const Vec3 ref = massCentre(model, x);
    computeGoals(model, x, {}, ref, rotations, rotationIterations, false, scratch, naive);
    for (size_t i = 0; i < x.size(); ++i) outGoals[i] = scratch.goal[i] + ref;
}

void stepShapeMatching(const ShapeMatchingModel& model, const ShapeMatchingStep& step,
                       std::span<Vec3> x, std::span<Vec3> v, std::span<Quat> rotations,
                       ShapeMatchingScratch& s, bool naive) {
    const Vec3 ref = massCentre(model, x);
    const bool damp = step.damping > 0;
    const bool regionDamp = damp && step.regionDamping;
    computeGoals(model, x, v, ref, rotations, step.rotationIterations, regionDamp, s, naive);
    const float k = step.stiffness / step.dt;
    // Internal velocity changes (goal pull and damping); stored in s.goal, which is not needed
    // past this point. Goal and position are both taken relative to ref, so that rounding
    // scales with the body's size rather than its distance from the origin.
    for (size_t i = 0; i < x.size(); ++i) {
        Vec3 dvi = (s.goal[i] - (x[i] - ref)) * k;
        if (regionDamp) dvi += (s.rigidVelocity[i] - v[i]) * step.damping;
        s.goal[i] = dvi;
    }
    if (damp && !regionDamp)
        addNonRigidDamping(model.massFraction, x, v, step.damping,
                           std::span<Vec3>(s.goal.data(), x.size()));
    removeMomentumDrift(model.massFraction, std::span<Vec3>(s.goal.data(), x.size()));
    const Vec3 dv = step.acceleration * step.dt;
    for (size_t i = 0; i < x.size(); ++i) {
        v[i] += s.goal[i] + dv;
        if (step.integratePositions) x[i] += v[i] * step.dt;
    }
}

namespace {

// Rotation matrices of four quaternions (row-major elements), as toMat3.
void toMat3x4(const Q4& q, F4 R[9]) {
    const F4 xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    const F4 xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    const F4 wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    const F4 one = splat(1), two = splat(2);
    R[0] = one - two * (yy + zz), R[1] = two * (xy - wz), R[2] = two * (xz + wy);
    R[3] = two * (xy + wz), R[4] = one - two * (xx + zz), R[5] = two * (yz - wx);
    R[6] = two * (xz - wy), R[7] = two * (yz + wx), R[8] = one - two * (xx + yy);
}

// addNonRigidDamping on four lanes: ioDv += fraction (v_rigid - v), with the body's rigid motion
// (mean velocity and angular velocity about the mass centre) taken per lane. x relative to any
// per-lane reference.
void addNonRigidDamping4(std::span<const float> mass, double totalMass, const V4* x, const V4* v,
                         F4 fraction, V4* ioDv, size_t n) {
    const F4 invM = splat(float(1.0 / totalMass));
    V4 c{}, p{};
    for (size_t i = 0; i < n; ++i) {
        const F4 m = splat(mass[i]);
        c = c + x[i] * m;
        p = p + v[i] * m;
    }
    c = c * invM;
    const V4 vcm = p * invM;
    V4 L{};
    F4 xx{}, yy{}, zz{}, xy{}, xz{}, yz{};
    for (size_t i = 0; i < n; ++i) {
        const F4 m = splat(mass[i]);
        const V4 r = x[i] - c;
        L = L + cross(r, v[i] - vcm) * m;
        xx += m * r.x * r.x, yy += m * r.y * r.y, zz += m * r.z * r.z;
        xy += m * r.x * r.y, xz += m * r.x * r.z, yz += m * r.y * r.z;
    }
    const F4 trace = xx + yy + zz;
    const F4 reg = splat(1e-4f) * trace + splat(1e-30f);
    // Inverse of the inertia I = [[a, -xy, -xz], [-xy, b, -yz], [-xz, -yz, c]] by cofactors
    // (symmetric); a lane whose determinant vanishes gets no angular velocity.
    const F4 a = trace - xx + reg, b = trace - yy + reg, cc = trace - zz + reg;
    const F4 c00 = b * cc - yz * yz, c01 = xy * cc + xz * yz, c02 = xy * yz + xz * b;
    const F4 c11 = a * cc - xz * xz, c12 = a * yz + xy * xz, c22 = a * b - xy * xy;
    const F4 det = a * c00 - xy * c01 - xz * c02;
    const I4 ok = abs4(det) > splat(0.0f);
    const F4 invDet = splat(1.0f) / select(ok, det, splat(1.0f));
    const F4 zero = splat(0.0f);
    V4 omega{select(ok, (c00 * L.x + c01 * L.y + c02 * L.z) * invDet, zero),
             select(ok, (c01 * L.x + c11 * L.y + c12 * L.z) * invDet, zero),
             select(ok, (c02 * L.x + c12 * L.y + c22 * L.z) * invDet, zero)};
    for (size_t i = 0; i < n; ++i) {
        const V4 rigid = vcm + cross(omega, x[i] - c);
        ioDv[i] = ioDv[i] + (rigid - v[i]) * fraction;
    }
}

// The i-th Vec3 of four arrays as one V4 (built in registers: lane-by-lane stores to memory
// followed by a vector load would stall on store forwarding).
inline V4 gather(const Vec3* const p[4], size_t i) {
    const Vec3 &a = p[0][i], &b = p[1][i], &c = p[2][i], &d = p[3][i];
    return {F4{a.x, b.x, c.x, d.x}, F4{a.y, b.y, c.y, d.y}, F4{a.z, b.z, c.z, d.z}};
}
// The first `count` lanes of v written to the i-th Vec3 of their arrays.
inline void scatter(const V4& v, Vec3* const p[4], size_t i, int count) {
    for (int l = 0; l < count; ++l) p[l][i] = {v.x[l], v.y[l], v.z[l]};
}
static_assert(sizeof(Quat) == 4 * sizeof(float));
inline Q4 gather(const Quat* const p[4], size_t i) {
    F4 r0 = load4(&p[0][i].w), r1 = load4(&p[1][i].w), r2 = load4(&p[2][i].w),
       r3 = load4(&p[3][i].w);
    transpose(r0, r1, r2, r3);
    return {r0, r1, r2, r3};
}
inline void scatter(const Q4& q, Quat* const p[4], size_t i, int count) {
    F4 r0 = q.w, r1 = q.x, r2 = q.y, r3 = q.z;
    transpose(r0, r1, r2, r3);
    const F4 rows[4] = {r0, r1, r2, r3};
    for (int l = 0; l < count; ++l) store4(&p[l][i].w, rows[l]);
}

} // namespace

void stepShapeMatching4(const ShapeMatchingModel& model, float dt, int rotationIterations,
                        const ShapeMatchingLane* lanes, int count, ShapeMatchingScratch& s) {
    constexpr int C = 12; // channels per point and lane: m~ x (3), m~ x x0^T (9); then R, t
    const size_t P = model.particlePoint.size(), G = model.pointCount();
    auto lane = [&](int l) -> const ShapeMatchingLane& { return lanes[l < count ? l : 0]; };
    // Each lane's arrays (lanes past `count` read lane 0's and are never written).
    const Vec3* xs[4];
    Vec3* vs[4];
    Quat *rs[4], *steps[4];
    bool extrapolate = true;
    for (int l = 0; l < 4; ++l) {
        xs[l] = lane(l).x.data();
        vs[l] = lane(l).v.data();
        rs[l] = lane(l).rotations.data();
        steps[l] = lane(l).rotationSteps.data();
        extrapolate = extrapolate && !lane(l).rotationSteps.empty();
    }
    s.x4.resize(P);
    s.dv4.resize(P);
    // Positions relative to each body's mass centre (the scalar path's reference point).
    V4 ref{};
    for (size_t i = 0; i < P; ++i) {
        const V4 x = gather(xs, i);
        s.x4[i] = x;
        ref = ref + x * splat(model.massFraction[i]);
    }
    for (size_t i = 0; i < P; ++i) s.x4[i] = s.x4[i] - ref;

    // First summation.
    s.a4.assign(G * C, F4{});
    s.b4.resize(G * C);
    for (size_t j = 0; j < P; ++j) {
        F4* out = &s.a4[size_t(model.particlePoint[j]) * C];
        const F4 m = splat(model.tildeMass[j]);
        const V4 mx = s.x4[j] * m;
        const Vec3 x0 = model.restCentred[j];
        out[0] = mx.x, out[1] = mx.y, out[2] = mx.z;
        const F4 mxi[3] = {mx.x, mx.y, mx.z};
        for (int i = 0; i < 3; ++i) {
            out[3 + 3 * i] = mxi[i] * splat(x0.x);
            out[4 + 3 * i] = mxi[i] * splat(x0.y);
            out[5 + 3 * i] = mxi[i] * splat(x0.z);
        }
    }
    float* a = reinterpret_cast<float*>(s.a4.data());
    float* b = reinterpret_cast<float*>(s.b4.data());
    boxPass<4 * C>(a, b, model.pointDims, 0, model.halfWidth);
    boxPass<4 * C>(b, a, model.pointDims, 1, model.halfWidth);
    boxPass<4 * C>(a, b, model.pointDims, 2, model.halfWidth);

    // Regions: rotation and translation, scattered for the second summation.
    std::fill(s.a4.begin(), s.a4.end(), F4{});
    for (size_t r = 0; r < P; ++r) {
        const F4* S = &s.b4[size_t(model.particlePoint[r]) * C];
        const float M = model.regionMass[r];
        const F4 invM = splat(1.0f / M);
        const F4 c[3] = {S[0] * invM, S[1] * invM, S[2] * invM};
        const Vec3 c0 = model.regionRestCentre[r];
        F4 A[9];
        for (int i = 0; i < 3; ++i) {
            const F4 Mc = splat(M) * c[i];
            A[3 * i] = S[3 + 3 * i] - Mc * splat(c0.x);
            A[3 * i + 1] = S[4 + 3 * i] - Mc * splat(c0.y);
            A[3 * i + 2] = S[5 + 3 * i] - Mc * splat(c0.z);
        }
        const Q4 last = gather(rs, r);
        Q4 q = extrapolate ? renormalize(gather(steps, r) * last) : last;
        extractRotations4(A, q, rotationIterations);
        scatter(q, rs, r, count);
        // The step is a product of unit quaternions, normalised when next used.
        if (extrapolate) scatter(q * conjugate(last), steps, r, count);
        F4* out = &s.a4[size_t(model.particlePoint[r]) * C];
        toMat3x4(q, out);
        for (int i = 0; i < 3; ++i)
            out[9 + i] = c[i] - (out[3 * i] * splat(c0.x) + out[3 * i + 1] * splat(c0.y) +
                                 out[3 * i + 2] * splat(c0.z));
    }
    boxPass<4 * C>(a, b, model.pointDims, 0, model.halfWidth);
    boxPass<4 * C>(b, a, model.pointDims, 1, model.halfWidth);
    boxPass<4 * C>(a, b, model.pointDims, 2, model.halfWidth);

    // Goals, and the velocity changes they ask for.
    F4 k, fraction;
    for (int l = 0; l < 4; ++l) {
        k[l] = lane(l).stiffness / dt;
        fraction[l] = lane(l).damping;
    }
    for (size_t i = 0; i < P; ++i) {
        const F4* U = &s.b4[size_t(model.particlePoint[i]) * C];
        const F4 inv = splat(1.0f / model.regionSize[i]);
        const Vec3 x0 = model.restCentred[i];
        const V4 goal{(U[0] * splat(x0.x) + U[1] * splat(x0.y) + U[2] * splat(x0.z) + U[9]) * inv,
                      (U[3] * splat(x0.x) + U[4] * splat(x0.y) + U[5] * splat(x0.z) + U[10]) * inv,
                      (U[6] * splat(x0.x) + U[7] * splat(x0.y) + U[8] * splat(x0.z) + U[11]) * inv};
        s.dv4[i] = (goal - s.x4[i]) * k;
    }
    s.v4.resize(P);
    V4* v4 = s.v4.data();
    for (size_t i = 0; i < P; ++i) v4[i] = gather(vs, i);
    bool damp = false;
    for (int l = 0; l < count; ++l) damp = damp || lanes[l].damping > 0;
    if (damp) {
        double total = 0;
        for (size_t i = 0; i < P; ++i) total += double(model.massFraction[i]);
        addNonRigidDamping4(model.massFraction, total, s.x4.data(), v4, fraction, s.dv4.data(), P);
    }
    // Remove the momentum rounding left in the internal changes (sums in double, per lane),
    // then apply them with the external acceleration.
    typedef double D2 __attribute__((vector_size(16)));
    D2 px[2] = {}, py[2] = {}, pz[2] = {};
    double m = 0;
    auto lo = [](F4 v) { return __builtin_convertvector(__builtin_shufflevector(v, v, 0, 1), D2); };
    auto hi = [](F4 v) { return __builtin_convertvector(__builtin_shufflevector(v, v, 2, 3), D2); };
    for (size_t i = 0; i < P; ++i) {
        const double mi = double(model.massFraction[i]);
        const D2 mm{mi, mi};
        const V4& d = s.dv4[i];
        px[0] += mm * lo(d.x), px[1] += mm * hi(d.x);
        py[0] += mm * lo(d.y), py[1] += mm * hi(d.y);
        pz[0] += mm * lo(d.z), pz[1] += mm * hi(d.z);
        m += mi;
    }
    V4 mean, kick;
    for (int l = 0; l < 4; ++l) {
        mean.x[l] = float(px[l / 2][l % 2] / m);
        mean.y[l] = float(py[l / 2][l % 2] / m);
        mean.z[l] = float(pz[l / 2][l % 2] / m);
        const Vec3 kl = lane(l).acceleration * dt;
        kick.x[l] = kl.x, kick.y[l] = kl.y, kick.z[l] = kl.z;
    }
    for (size_t i = 0; i < P; ++i) scatter(v4[i] + ((s.dv4[i] - mean) + kick), vs, i, count);
}

void removeMomentumDrift(std::span<const float> mass, std::span<Vec3> ioVelocityChange) {
    double p[3] = {0, 0, 0}, m = 0;
    for (size_t i = 0; i < ioVelocityChange.size(); ++i) {
        const Vec3 d = ioVelocityChange[i];
        p[0] += double(mass[i]) * double(d.x);
        p[1] += double(mass[i]) * double(d.y);
        p[2] += double(mass[i]) * double(d.z);
        m += double(mass[i]);
    }
    const Vec3 mean{float(p[0] / m), float(p[1] / m), float(p[2] / m)};
    for (Vec3& d : ioVelocityChange) d -= mean;
}

} // namespace ffd::detail
