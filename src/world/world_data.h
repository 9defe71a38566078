// The world's internal state, shared by the stage functions (dynamics, collision, ...).
// Hot per-particle and per-node data live in world-wide flat arrays; each body owns a range.
// Rest/topology data live in BodyModel, immutable and shared between bodies.
#pragma once

#include "collision/contact.h"
#include "dynamics/mass_spring.h"
#include "dynamics/shape_matching.h"
#include "ffdaabb/world.h"
#include "util/workers.h"
#include "world/pins.h"
#include "world/query_state.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ffd::detail {

/// Immutable data shared by every body made from the same mesh and model settings.
struct BodyModel {
    TriangleMesh mesh; ///< rest mesh
    Lattice lattice;
    DynamicsModel dynamics = DynamicsModel::ShapeMatching;
    ShapeMatchingModel shapeMatching; ///< empty for mass-spring bodies
    MassSpringModel springs;          ///< empty for shape-matching bodies
    float volume = 0;                 ///< m^3: the mesh's when closed, else the lattice's
};

/// A body's slot in the world: its ranges in the flat arrays and its material.
struct BodyRecord {
    std::shared_ptr<const BodyModel> model;
    BodySettings settings;
    uint32_t slot = 0;
    uint32_t firstParticle = 0, particleCount = 0;
    uint32_t firstBox = 0, boxCount = 0; // nodes: [firstBox * 8, (firstBox + boxCount) * 8)
    uint32_t firstVertex = 0, vertexCount = 0;
    float mass = 0;
    float cellSize = 0;
    Vec3 force; ///< accumulated for the next step
    /// Velocities are stored at half steps (leapfrog): a body whose velocity was just set gets
    /// half the acceleration's kick in its first substep, which makes free fall exact.
    bool halfKick = true;
    // Sleeping (world/sleeping.h).
    bool asleep = false;
    float quietTime = 0; ///< seconds it has been quiet, while awake
    uint32_t island = 0; ///< the bodies that fell asleep together share it (0: none)
    // What the collision stages find of the body (bounds, bounding sphere, motion) is theirs:
    // WorldData::collision.bodies, same index.
};

struct Slot {
    uint32_t generation = 1;
    uint32_t dense = UINT32_MAX; ///< index into WorldData::bodies, UINT32_MAX when free
};

/// Per-thread scratch of the per-body stages.
struct ThreadScratch {
    ShapeMatchingScratch shapeMatching;
    MassSpringScratch massSpring;
};

/// A work item of the dynamics stage: up to four shape-matching bodies of one model (without
/// region damping), stepped together one per vector lane, or a single other body.
struct DynamicsBatch {
    uint32_t body[4] = {};
    uint32_t count = 0;
    bool lanes = false; ///< stepShapeMatching4 (else the body's own model, alone)
};

struct WorldData {
    WorldSettings settings;
    std::vector<BodyRecord> bodies; ///< in insertion order
    std::vector<Slot> slots;
    std::vector<uint32_t> freeSlots;

    // Flat per-particle state.
    std::vector<Vec3> x, v;
    std::vector<Vec3> particleForce; ///< external forces for the next step, N
    std::vector<float> invMass;
    /// invMass as the collision stages see it: 0 for the particles of sleeping bodies, which
    /// awake bodies meet as bodies of infinite mass (world/sleeping.h).
    std::vector<float> contactInvMass;
    std::vector<Quat> rotations;     ///< warm start of each shape-matching region
    std::vector<Quat> rotationSteps; ///< each region's rotation over the last substep
    // Flat per-box / per-node state.
    std::vector<Vec3> nodes;     ///< 8 per box
    std::vector<Aabb> boxBounds; ///< AABB of each box's 8 nodes
    // Flat per-vertex state.
    std::vector<Vec3> vertices;

    std::map<std::string, std::shared_ptr<const BodyModel>> modelCache;
    Profile profile;
    uint64_t frame = 0;

    std::vector<DynamicsBatch> dynamicsBatches; ///< rebuilt when bodies come, go, sleep or wake
    std::vector<uint32_t> awake;     ///< dense indices of the awake dynamic bodies, in order
                                     ///< (same times)
    uint32_t sleeping = 0;           ///< bodies asleep (same times)
    std::vector<uint32_t> kinematic; ///< dense indices of the kinematic bodies (same times)
    /// The kinematic bodies that move in the step in progress (a particle velocity not 0), in
    /// order: stepped by the node, position and mesh updates beside the awake bodies.
    std::vector<uint32_t> moving;
    /// Plane colliders (World::addPlane): slots never reused; `planes` the live ones in order.
    std::vector<std::pair<Plane, bool>> planeSlots;
    std::vector<Plane> planes;
    uint32_t nextIsland = 1;       ///< the next island number for bodies falling asleep together
    std::vector<Vec3> frameStartX; ///< particles at the frame's start (awake bodies' ranges)
    std::vector<uint32_t> islandParent; ///< scratch of the sleep stage, per body
    CollisionState collision;
    float substep = 1.0f / 120.0f;      ///< dt of the substep in progress
    Workers workers;                    ///< the world's own threads
    std::vector<ThreadScratch> scratch; ///< one per worker
    PinState pins;                      ///< world/pins.h
    mutable QueryCache queries;         ///< the geometric queries' caches (queries.cpp)
    ContactTally contactTally;          ///< the step's contact pairs and events
    /// Called after each stage of a step has run (instrumentation: bench/causes'
    /// ffdaabb_energy_stages); none by default.
    std::function<void(Stage)> stageObserver;

    /// The handle of the body at dense index `dense`.
    BodyId handleOf(uint32_t dense) const {
        const BodyRecord& r = bodies[dense];
        return {r.slot, slots[r.slot].generation};
    }

    const BodyRecord* find(BodyId id) const {
        if (id.index >= slots.size()) return nullptr;
        const Slot& s = slots[id.index];
        if (s.dense == UINT32_MAX || s.generation != id.generation) return nullptr;
        return &bodies[s.dense];
    }
    BodyRecord* find(BodyId id) {
        return const_cast<BodyRecord*>(static_cast<const WorldData*>(this)->find(id));
    }
};

/// The collision stages' view of the world for a step (collision/body.h): valid until bodies
/// come or go.
CollisionWorld collisionView(WorldData& world);

/// After bodies came or went: each body's layout and material in the collision state, and the
/// collision's lookups from nodes and boxes to bodies (collision/pipeline.h); refreshAwake
/// (world/sleeping.h) then sets who is asleep or immovable.
void syncCollisionBodies(WorldData& world);

/// Mass-weighted mean over a body's particles of a per-particle quantity (`x`: the centre of
/// mass; `v`: the linear velocity), by the model's mass fractions.
inline Vec3 massWeightedMean(const BodyRecord& r, const std::vector<Vec3>& perParticle) {
    Vec3 sum{};
    for (uint32_t p = 0; p < r.particleCount; ++p)
        sum += perParticle[r.firstParticle + p] * r.model->lattice.massFraction[p];
    return sum;
}

} // namespace ffd::detail

namespace ffd {

/// The world's data behind its public interface.
struct World::State : detail::WorldData {};

namespace detail {

/// The library's own way in to a world's data (the stages' tests, the contact-cause
/// instrumentation); the public interface is World's.
struct WorldAccess {
    static WorldData& data(World& world) { return *world.state_; }
    static const WorldData& data(const World& world) { return *world.state_; }
};

inline WorldData& dataOf(World& world) {
    return WorldAccess::data(world);
}
inline const WorldData& dataOf(const World& world) {
    return WorldAccess::data(world);
}

} // namespace detail
} // namespace ffd
