// Contact response on lattice particles: position projection, then velocity correction with
// restitution and Coulomb friction, Gauss-Seidel over the contacts in a fixed order.
// Reference: Mueller, Heidelberger, Hennix, Ratcliff, "Position Based Dynamics", 2006;
// E. Catto, "Solver2D" / Box2D's speculative contacts (the velocity bound -C/dt).
#include "collision/contact.h"

#include <cmath>

namespace ffd::detail {

namespace {

Vec3 blend(const ContactPoint& p, std::span<const Vec3> values) {
    Vec3 r{};
    for (int k = 0; k < 8; ++k) r += values[p.particle[k]] * p.weight[k];
    return r;
}

// Moves the point by `delta` (generalised-inverse-mass weighted).
void push(const ContactPoint& p, std::span<Vec3> values, std::span<const float> invMass,
          Vec3 delta) {
    for (int k = 0; k < 8; ++k) {
        const uint32_t i = p.particle[k];
        values[i] += delta * (p.weight[k] * invMass[i]);
    }
}

} // namespace

void makeContactPoint(const uint32_t cellParticles[8], uint32_t firstParticle, Vec3 local,
                      std::span<const float> invMass, ContactPoint& out, float& outInvMass) {
    trilinearWeights(local, out.weight);
    outInvMass = 0;
    for (int k = 0; k < 8; ++k) {
        out.particle[k] = firstParticle + cellParticles[k];
        outInvMass += out.weight[k] * out.weight[k] * invMass[out.particle[k]];
    }
}

void solveContactPositions(std::span<Contact> contacts, std::span<Vec3> x, std::span<Vec3> v,
                           std::span<const float> invMass, float dt, int iterations) {
    const float invDt = 1.0f / dt;
    for (Contact& c : contacts) c.positionImpulse = 0;
    for (int it = 0; it < iterations; ++it)
        for (Contact& c : contacts) {
            const Vec3 pa = blend(c.a, x);
            const Vec3 pb = c.hasB ? blend(c.b, x) : Vec3{};
            const float C = dot(pa - pb, c.normal) - c.offset;
            if (C >= 0) continue;
            const float W = c.invMassA + c.invMassB;
            if (!(W > 0)) continue;
            const float lambda = -C / W;
            c.positionImpulse += lambda * invDt;
            push(c.a, x, invMass, c.normal * lambda);
            push(c.a, v, invMass, c.normal * (lambda * invDt));
            if (c.hasB) {
                push(c.b, x, invMass, c.normal * -lambda);
                push(c.b, v, invMass, c.normal * (-lambda * invDt));
            }
        }
}

float residualPenetration(std::span<const Contact> contacts, std::span<const Vec3> x) {
    float deepest = 0;
    for (const Contact& c : contacts) {
        const Vec3 pa = blend(c.a, x);
        const Vec3 pb = c.hasB ? blend(c.b, x) : Vec3{};
        deepest = std::fmax(deepest, c.offset - dot(pa - pb, c.normal));
    }
    return deepest;
}

void solveContactVelocities(std::span<Contact> contacts, std::span<const Vec3> x, std::span<Vec3> v,
                            std::span<const float> invMass, float dt, float bounceThreshold,
                            int iterations) {
    for (Contact& c : contacts) {
        const Vec3 rel = blend(c.a, v) - (c.hasB ? blend(c.b, v) : Vec3{});
        c.approachSpeed = dot(rel, c.normal);
        c.normalImpulse = 0;
        c.tangentImpulse = {};
    }
    const float invDt = 1.0f / dt;
    for (int it = 0; it < iterations; ++it)
        for (Contact& c : contacts) {
            const float W = c.invMassA + c.invMassB;
            if (!(W > 0)) continue;
            const Vec3 pa = blend(c.a, x), pb = c.hasB ? blend(c.b, x) : Vec3{};
            const float gap = dot(pa - pb, c.normal) - c.offset;
            const Vec3 rel = blend(c.a, v) - (c.hasB ? blend(c.b, v) : Vec3{});
            const float vn = dot(rel, c.normal);
            // Allowed normal velocity: close at most the remaining gap in one substep; bounce
            // back fast impacts by the restitution.
            float target = -std::fmax(gap, 0.0f) * invDt;
            if (c.restitution > 0 && c.approachSpeed < -bounceThreshold)
                target = std::fmax(target, -c.restitution * c.approachSpeed);
            const float oldN = c.normalImpulse;
            c.normalImpulse = std::fmax(oldN + (target - vn) / W, 0.0f);
            const float dn = c.normalImpulse - oldN;
            Vec3 impulse = c.normal * dn;
            // Friction from the tangential velocity after the normal change.
            const Vec3 vt = rel - c.normal * vn;
            if (c.friction > 0) {
                const Vec3 oldT = c.tangentImpulse;
                Vec3 t = oldT - vt / W;
                const float limit = c.friction * (c.positionImpulse + c.normalImpulse);
                const float tl = length(t);
                if (tl > limit) t = t * (limit / tl);
                c.tangentImpulse = t;
                impulse += t - oldT;
            }
            push(c.a, v, invMass, impulse);
            if (c.hasB) push(c.b, v, invMass, -impulse);
        }
}

} // namespace ffd::detail
