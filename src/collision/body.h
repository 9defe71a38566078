// A body as the collision stages see it, and the view of the world they work on.
//
// The stages under src/collision/ know nothing of the world's own types: each substep the world
// hands them a CollisionWorld (views of its flat arrays, a snapshot of its settings, its threads
// and the collision state they own) and they read and write only that.
#pragma once

#include "ffdaabb/lattice.h"
#include "ffdaabb/math.h"
#include "ffdaabb/profile.h"
#include "ffdaabb/world.h"

#include <span>

namespace ffd::detail {

class Workers;
struct CollisionState;

/// One body: its layout and material, which the world sets when bodies come and go
/// (rebuildCollisionTopology), and what the collision stages find of it each substep.
struct CollisionBody {
    // Layout and material (the world's).
    const Lattice* lattice = nullptr;    ///< its model's, shared by every body of the model
    std::span<const float> massFraction; ///< per particle, sums to 1
    uint32_t firstParticle = 0, particleCount = 0;
    uint32_t firstBox = 0, boxCount = 0; ///< nodes: [firstBox * 8, (firstBox + boxCount) * 8)
    float cellSize = 0;
    float mass = 0;
    float friction = 0.5f, restitution = 0, contactRigidity = 0.5f; ///< BodySettings'
    /// Asleep (the world's): it does not move in this step, its particles' inverse masses in
    /// the view are 0, and no contacts are made between two sleeping bodies nor with the floor.
    bool asleep = false;
    /// Asleep, static or kinematic (the world's): contacts do not move it (its particles'
    /// inverse masses in the view are 0); no contacts are made between two immovable bodies,
    /// nor between one and the floor or the planes.
    bool immovable = false;
    // Written by node_update.
    Aabb bounds;        ///< of the box nodes
    float maxSpeed = 0; ///< fastest particle, m/s
    Vec3 meanVelocity;  ///< mass-weighted mean particle velocity
    float spread = 0;   ///< largest |v_i - meanVelocity| over the particles, m/s
    // Written by sphere_test (and by the overlap recovery when it needs the spheres).
    Vec3 sphereCentre;
    float sphereRadius = 0;
    /// Added, translated or set since the last substep (the world sets it): its overlaps are
    /// remembered (collision/overlap_recovery.h), which clears it.
    bool placed = true;
};

/// Mass-weighted mean over a body's particles of a per-particle quantity (`x`: the centre of
/// mass; `v`: the linear velocity), by its mass fractions.
inline Vec3 massWeightedMean(const CollisionBody& body, std::span<const Vec3> perParticle) {
    Vec3 sum{};
    for (uint32_t p = 0; p < body.particleCount; ++p)
        sum += perParticle[body.firstParticle + p] * body.massFraction[p];
    return sum;
}

/// What the collision stages read and write in a step: the world's particles, nodes and box
/// bounds (views into its flat arrays, which keep their size during a step), a snapshot of its
/// settings, the substep, its threads, the collision state (the bodies included) and the
/// profile's counters.
struct CollisionWorld {
    WorldSettings settings;
    float substep = 1.0f / 120.0f;
    std::span<Vec3> x, v;
    std::span<const float> invMass; ///< per particle; 0 for sleeping bodies (infinite mass)
    std::span<Vec3> nodes;          ///< 8 per box
    std::span<Aabb> boxBounds;      ///< per box
    std::span<CollisionBody> bodies;
    std::span<const Plane> planes; ///< plane colliders besides the floor (World::addPlane)
    CollisionState& collision;
    Workers& workers;
    Profile& profile;
};

/// Two bodies that contacts do not move (asleep, static or kinematic): no pairs are made
/// between them.
inline bool bothImmovable(const CollisionWorld& w, uint32_t a, uint32_t b) {
    return w.bodies[a].immovable && w.bodies[b].immovable;
}

} // namespace ffd::detail
