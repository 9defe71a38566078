// Contacts and their response on lattice particles.
//
// A contact joins an embedded point of body A (a boundary node) to an embedded point of body B
// (or the floor). Every embedded point is a trilinear blend sum_a w_a x_a of its cell's 8
// particles, so a correction D at the point maps back to particles exactly: with inverse masses
// 1/m_a, moving particle a by (w_a / m_a) * D / W, W = sum w_a^2 / m_a, moves the point by D
// with the least mass-weighted motion. The correction is split between the two bodies by these
// generalised inverse masses (Position Based Dynamics, Mueller et al. 2006).
#pragma once

#include "collision/narrow_phase.h"
#include "collision/spatial_hash.h"
#include "ffdaabb/math.h"

#include <span>
#include <vector>

namespace ffd::detail {

/// An embedded point: 8 particles (world-wide indices) and their trilinear weights.
struct ContactPoint {
    uint32_t particle[8] = {};
    float weight[8] = {};
};

struct Contact {
    ContactPoint a, b;  ///< b unused when !hasB (floor)
    Vec3 normal;        ///< unit, the direction A must move relative to B
    float offset = 0;   ///< constraint C = dot(pA - pB, normal) - offset >= 0
    float invMassA = 0; ///< sum w^2 / m over A's particles
    float invMassB = 0;
    float friction = 0.5f;
    float restitution = 0;
    float depth = 0; ///< penetration when detected, metres (>= 0)
    bool hasB = false;
    // Identification, for a canonical order and for tests.
    uint32_t bodyA = 0, bodyB = UINT32_MAX; ///< dense body indices
    uint32_t nodeA = 0;                     ///< world-wide node index on A
    uint32_t boxB = UINT32_MAX;             ///< world-wide box index on B
    // Solver state.
    float approachSpeed = 0;   ///< normal velocity when the velocity solve began
    float positionImpulse = 0; ///< normal impulse of the position projection (lambda / dt)
    float normalImpulse = 0;   ///< accumulated by the velocity solve, >= 0
    Vec3 tangentImpulse;       ///< |.| <= friction * (positionImpulse + normalImpulse)
};

/// Sort key giving every contact set the same order whichever pipeline found it.
inline uint64_t contactKey(const Contact& c) {
    return (uint64_t(c.nodeA) << 32) | c.boxB;
}

/// Fills weights and generalised inverse mass of an embedded point.
void makeContactPoint(const uint32_t cellParticles[8], uint32_t firstParticle, Vec3 local,
                      std::span<const float> invMass, ContactPoint& out, float& outInvMass);

/// Gauss-Seidel position projection: `iterations` sweeps over the contacts in order. A
/// correction dx also changes velocity by dx / dt (position-based): the particles did not
/// travel where their velocity took them, so they no longer move that way. Without this, a
/// particle that contacts reach only through small weights can keep a velocity that each
/// substep's projection cancels (a static state with kinetic energy).
void solveContactPositions(std::span<Contact> contacts, std::span<Vec3> x, std::span<Vec3> v,
                           std::span<const float> invMass, float dt, int iterations);

/// Deepest remaining violation of the contacts' constraints (metres, >= 0).
float residualPenetration(std::span<const Contact> contacts, std::span<const Vec3> x);

/// Velocity correction: removes approach beyond what closes the remaining gap within dt
/// (speculative), applies restitution to fast impacts and Coulomb friction.
void solveContactVelocities(std::span<Contact> contacts, std::span<const Vec3> x, std::span<Vec3> v,
                            std::span<const float> invMass, float dt, float bounceThreshold,
                            int iterations);

/// An object pair that passed the bounding-sphere test (dense body indices, a < b).
struct CandidatePair {
    uint32_t a = 0, b = 0;
    friend bool operator==(const CandidatePair&, const CandidatePair&) = default;
};

/// Collision buffers kept between steps (no steady-state allocation).
struct CollisionState {
    std::vector<CandidatePair> pairs;
    std::vector<uint32_t> partnerStart, partners; ///< CSR of each body's candidate partners
    std::vector<uint8_t> isCandidate;             ///< per body
    std::vector<uint32_t> sweepOrder;
    SpatialHash hash;
    std::vector<BoxPlanes> planes; ///< per box, for the narrow phase
    std::vector<Contact> floorContacts, objectContacts, all;
    std::vector<uint32_t> nodeBody, boxBody; ///< world-wide node/box -> dense body
};

} // namespace ffd::detail
