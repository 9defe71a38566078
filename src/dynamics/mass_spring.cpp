// Reference: Baraff & Witkin, "Large Steps in Cloth Simulation", SIGGRAPH 1998; Mueller et al.,
// "Position Based Dynamics", 2006 (rigid-motion-preserving damping).
#include "dynamics/mass_spring.h"

#include "dynamics/shape_matching.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace ffd::detail {

MassSpringModel buildMassSpring(const Lattice& lattice, float bendingScale) {
    // Pairs of corners inside one cell, by their offset: edges (one axis), face diagonals (two
    // axes) and body diagonals (three). Keyed by particle pair so shared ones appear once.
    std::map<std::pair<uint32_t, uint32_t>, Spring> unique;
    const float h = lattice.cellSize;
    for (const auto& corners : lattice.cellParticles)
        for (int a = 0; a < 8; ++a)
            for (int b = a + 1; b < 8; ++b) {
                const int axes = __builtin_popcount(unsigned(a ^ b));
                Spring s;
                s.a = std::min(corners[a], corners[b]);
                s.b = std::max(corners[a], corners[b]);
                s.kind = axes == 1 ? SpringKind::Structural
                                   : (axes == 2 ? SpringKind::Shear : SpringKind::Diagonal);
                s.rest = h * std::sqrt(float(axes));
                unique.emplace(std::make_pair(s.a, s.b), s);
            }
    // Bending: particle pairs two steps apart along an axis with the middle particle present.
    std::map<GridCoord, uint32_t> byCoord;
    for (uint32_t p = 0; p < lattice.particleCount(); ++p) byCoord[lattice.particleCoords[p]] = p;
    for (uint32_t p = 0; p < lattice.particleCount(); ++p)
        for (int axis = 0; axis < 3; ++axis) {
            GridCoord mid = lattice.particleCoords[p], end = mid;
            mid[axis] += 1;
            end[axis] += 2;
            auto m = byCoord.find(mid), e = byCoord.find(end);
            if (m == byCoord.end() || e == byCoord.end()) continue;
            Spring s;
            s.a = std::min(p, e->second);
            s.b = std::max(p, e->second);
            s.kind = SpringKind::Bending;
            s.rest = 2 * h;
            s.stiffnessScale = bendingScale;
            unique.emplace(std::make_pair(s.a, s.b), s);
        }
    MassSpringModel model;
    model.springs.reserve(unique.size());
    for (const auto& [key, s] : unique) model.springs.push_back(s);
    return model;
}

void addNonRigidDamping(std::span<const float> mass, std::span<const Vec3> x,
                        std::span<const Vec3> v, float fraction, std::span<Vec3> ioVelocityChange) {
    if (fraction <= 0 || x.empty()) return;
    double M = 0;
    Vec3 c{}, p{};
    for (size_t i = 0; i < x.size(); ++i) {
        M += double(mass[i]);
        c += x[i] * mass[i];
        p += v[i] * mass[i];
    }
    const float invM = float(1.0 / M);
    c *= invM;
    const Vec3 vcm = p * invM;
    Vec3 L{};
    float xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        const Vec3 r = x[i] - c;
        L += cross(r, v[i] - vcm) * mass[i];
        xx += mass[i] * r.x * r.x, yy += mass[i] * r.y * r.y, zz += mass[i] * r.z * r.z;
        xy += mass[i] * r.x * r.y, xz += mass[i] * r.x * r.z, yz += mass[i] * r.y * r.z;
    }
    const float trace = xx + yy + zz;
    const float reg = 1e-4f * trace + 1e-30f;
    const Mat3 I{
        {{trace - xx + reg, -xy, -xz}, {-xy, trace - yy + reg, -yz}, {-xz, -yz, trace - zz + reg}}};
    Mat3 Iinv;
    const Vec3 omega = inverse(I, Iinv) ? Iinv * L : Vec3{};
    for (size_t i = 0; i < x.size(); ++i) {
        const Vec3 rigid = vcm + cross(omega, x[i] - c);
        ioVelocityChange[i] += (rigid - v[i]) * fraction;
    }
}

namespace {

// y = (M - dt^2 K) u, K assembled from the per-spring blocks J_s = dF_a/dx_a:
// (K u)_a += J_s (u_a - u_b), (K u)_b -= J_s (u_a - u_b).
void applySystem(const MassSpringModel& model, std::span<const Mat3> J, std::span<const float> mass,
                 float dt2, std::span<const Vec3> u, std::span<Vec3> y) {
    for (size_t i = 0; i < u.size(); ++i) y[i] = u[i] * mass[i];
    for (size_t k = 0; k < model.springs.size(); ++k) {
        const Spring& s = model.springs[k];
        const Vec3 f = (J[k] * (u[s.a] - u[s.b])) * dt2;
        y[s.a] -= f;
        y[s.b] += f;
    }
}

float dot(std::span<const Vec3> a, std::span<const Vec3> b) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += double(ffd::dot(a[i], b[i]));
    return float(sum);
}

} // namespace

int stepMassSpring(const MassSpringModel& model, const MassSpringStep& step,
                   std::span<const float> invMass, std::span<Vec3> x, std::span<Vec3> v,
                   MassSpringScratch& s) {
    const size_t n = x.size();
    const float dt = step.dt, dt2 = dt * dt;
    s.mass.resize(n);
    for (size_t i = 0; i < n; ++i) s.mass[i] = 1.0f / invMass[i];
    s.force.assign(n, Vec3{});
    s.jacobian.resize(model.springs.size());
    s.diag.resize(n);
    for (size_t i = 0; i < n; ++i) s.diag[i] = Vec3{1, 1, 1} * s.mass[i];
    for (size_t k = 0; k < model.springs.size(); ++k) {
        const Spring& sp = model.springs[k];
        const Vec3 d = x[sp.a] - x[sp.b];
        const float len = length(d);
        const float stiffness = step.youngsModulus * sp.rest * sp.stiffnessScale;
        if (!(len > 1e-9f * sp.rest)) {
            s.jacobian[k] = Mat3{};
            continue;
        }
        const Vec3 dir = d / len;
        const Vec3 f = dir * (-stiffness * (len - sp.rest));
        s.force[sp.a] += f;
        s.force[sp.b] -= f;
        const float transverse = maxNum(0.0f, 1.0f - sp.rest / len);
        const Mat3 nn = outer(dir, dir);
        const Mat3 J = (nn + (Mat3::identity() + nn * -1.0f) * transverse) * -stiffness;
        s.jacobian[k] = J;
        for (int c = 0; c < 3; ++c) {
            s.diag[sp.a][c] -= dt2 * J.m[c][c];
            s.diag[sp.b][c] -= dt2 * J.m[c][c];
        }
    }
    // rhs = dt (f + dt K v); the gravity kick stays outside the solve (it is uniform, and the
    // system's rows sum to M, so solving it would return the same kick).
    s.rhs.resize(n);
    applySystem(model, s.jacobian, s.mass, dt2, v, s.rhs); // (M - dt^2 K) v
    for (size_t i = 0; i < n; ++i) s.rhs[i] = s.force[i] * dt + (v[i] * s.mass[i] - s.rhs[i]);
    // Preconditioned conjugate gradients from dv = 0.
    s.dv.assign(n, Vec3{});
    s.r.assign(s.rhs.begin(), s.rhs.end());
    s.z.resize(n);
    s.p.resize(n);
    s.q.resize(n);
    for (size_t i = 0; i < n; ++i)
        s.z[i] = {s.r[i].x / s.diag[i].x, s.r[i].y / s.diag[i].y, s.r[i].z / s.diag[i].z};
    s.p.assign(s.z.begin(), s.z.end());
    float rz = dot(s.r, s.z);
    const float stop = step.tolerance * step.tolerance * dot(s.rhs, s.rhs);
    int it = 0;
    for (; it < step.iterations && dot(s.r, s.r) > stop; ++it) {
        applySystem(model, s.jacobian, s.mass, dt2, s.p, s.q);
        const float pq = dot(s.p, s.q);
        if (!(pq > 0)) break;
        const float alpha = rz / pq;
        for (size_t i = 0; i < n; ++i) {
            s.dv[i] += s.p[i] * alpha;
            s.r[i] -= s.q[i] * alpha;
            s.z[i] = {s.r[i].x / s.diag[i].x, s.r[i].y / s.diag[i].y, s.r[i].z / s.diag[i].z};
        }
        const float rzNew = dot(s.r, s.z);
        const float beta = rzNew / rz;
        rz = rzNew;
        for (size_t i = 0; i < n; ++i) s.p[i] = s.z[i] + s.p[i] * beta;
    }
    if (step.damping > 0) addNonRigidDamping(s.mass, x, v, step.damping, s.dv);
    removeMomentumDrift(s.mass, s.dv);
    const Vec3 kick = step.acceleration * dt;
    for (size_t i = 0; i < n; ++i) {
        v[i] += s.dv[i] + kick;
        if (step.integratePositions) x[i] += v[i] * dt;
    }
    return it;
}

} // namespace ffd::detail
