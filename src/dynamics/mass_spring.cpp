// Reference: Macklin, Mueller, Chentanez, "XPBD: Position-Based Simulation of Compliant
// Constrained Dynamics", MIG 2016; Mueller et al., "Position Based Dynamics", 2006 (damping).
#include "dynamics/mass_spring.h"

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

void dampNonRigidVelocity(std::span<const float> mass, std::span<const Vec3> x,
                          std::span<Vec3> v, float fraction) {
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
    const Mat3 I{{{trace - xx + reg, -xy, -xz}, {-xy, trace - yy + reg, -yz}, {-xz, -yz, trace - zz + reg}}};
    Mat3 Iinv;
    const Vec3 omega = inverse(I, Iinv) ? Iinv * L : Vec3{};
    for (size_t i = 0; i < x.size(); ++i) {
        const Vec3 rigid = vcm + cross(omega, x[i] - c);
        v[i] += (rigid - v[i]) * fraction;
    }
}

void stepMassSpring(const MassSpringModel& model, const MassSpringStep& step,
                    std::span<const float> invMass, std::span<Vec3> x, std::span<Vec3> v,
                    MassSpringScratch& scratch) {
    const float dt = step.dt;
    std::vector<Vec3>& g = scratch.goal;
    g.assign(x.begin(), x.end());
    // XPBD: the multipliers start at zero every substep and accumulate over the iterations.
    std::vector<float>& lambda = scratch.lambda;
    lambda.assign(model.springs.size(), 0.0f);
    const float invDt2 = 1.0f / (dt * dt);
    for (int it = 0; it < step.iterations; ++it)
        for (size_t k = 0; k < model.springs.size(); ++k) {
            const Spring& s = model.springs[k];
            const float wa = invMass[s.a], wb = invMass[s.b];
            const Vec3 d = g[s.a] - g[s.b];
            const float len = length(d);
            if (len < 1e-12f) continue;
            const float compliance = invDt2 / (step.youngsModulus * s.rest * s.stiffnessScale);
            const float C = len - s.rest;
            const float dl = (-C - compliance * lambda[k]) / (wa + wb + compliance);
            lambda[k] += dl;
            const Vec3 n = d / len;
            g[s.a] += n * (wa * dl);
            g[s.b] -= n * (wb * dl);
        }
    if (step.damping > 0) {
        scratch.mass.resize(x.size());
        for (size_t i = 0; i < x.size(); ++i) scratch.mass[i] = 1.0f / invMass[i];
        dampNonRigidVelocity(scratch.mass, x, v, step.damping);
    }
    const float invDt = 1.0f / dt;
    const Vec3 dv = step.acceleration * dt;
    for (size_t i = 0; i < x.size(); ++i) {
        v[i] += (g[i] - x[i]) * invDt + dv;
        x[i] += v[i] * dt;
    }
}

} // namespace ffd::detail
