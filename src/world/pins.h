// Pins: embedded points of bodies held at targets (ffdaabb/world.h: World::pinParticle and the
// like), projected every substep after the position update (docs/ALGORITHM.md, "Pins").
#pragma once

#include "ffdaabb/world.h"

#include <cstdint>
#include <vector>

namespace ffd::detail {

struct WorldData;

/// A pin: its body, its point (up to 8 of the body's particles, body-local, and their
/// trilinear weights), its target and what it did over the last step.
struct Pin {
    uint32_t slot = 0;
    BodyId body;
    uint32_t particle[8] = {};
    float weight[8] = {};
    Vec3 target;   ///< as last set
    Vec3 start;    ///< the target at the start of the step: the substeps go from here to target
    Vec3 followed; ///< what the projection aims at: the target, followed at maxSpeed at most
    Vec3 previous; ///< followed in the substep before
    PinSettings settings;
    Vec3 impulse; ///< N s, summed over the step in progress
    Vec3 force;   ///< N, the last step's mean
};

struct PinSlot {
    uint32_t generation = 1;
    uint32_t dense = UINT32_MAX; ///< index into PinState::list, UINT32_MAX when free
};

/// Every pin of the world, in the order they were made (the order they are projected).
struct PinState {
    std::vector<Pin> list;
    std::vector<PinSlot> slots;
    std::vector<uint32_t> freeSlots;
    std::vector<uint32_t> passes; ///< scratch: how many pins each dense body has this substep

    const Pin* find(PinId id) const {
        if (id.index >= slots.size()) return nullptr;
        const PinSlot& s = slots[id.index];
        if (s.dense == UINT32_MAX || s.generation != id.generation) return nullptr;
        return &list[s.dense];
    }
    Pin* find(PinId id) { return const_cast<Pin*>(static_cast<const PinState*>(this)->find(id)); }
};

/// The pins' projection in substep `substep` of `substeps` (dt each), after the position
/// update: each pin's point is moved to its target (hard) or toward it (soft), first through
/// its body's rigid motion, then through its cell's particles, velocities following; then the
/// swing damping. One thread, in the pins' order. Nothing to do (and no cost) without pins.
void pinStage(WorldData& world, float dt, int substep, int substeps);

/// Removes every pin of `body` (before the body itself goes).
void forgetPins(WorldData& world, BodyId body);

/// The rest-pose embedding of the point of a body whose deformed particles are `particles`
/// that lies at `point` now: the cell whose deformed shape holds it, by Newton's method on the
/// trilinear map; when none does, the nearest point of the nearest cell.
Embedding embedDeformedPoint(const Lattice& lattice, std::span<const Vec3> particles, Vec3 point);

} // namespace ffd::detail
