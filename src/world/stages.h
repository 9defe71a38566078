// The world's own stages of World::step, each over the world's data for one substep (the
// collision stages are in src/collision/, over the view collisionView() gives them).
#pragma once

#include <cstddef>

namespace ffd::detail {

struct WorldData;
struct CollisionWorld;

/// After bodies came, went, slept or woke: the awake shape-matching bodies of each model
/// (without region damping) grouped four at a time, in body order, for latticeDynamicsStage.
void rebuildDynamicsBatches(WorldData& world);

/// lattice_dynamics: shape matching or springs, damping, gravity and forces -> velocities.
void latticeDynamicsStage(WorldData& world, float dt);

/// node_update: every awake body's box nodes, bounds and motion (collision/pipeline.h
/// updateNodes), the bodies split across the world's workers.
void nodeUpdateStage(WorldData& world, CollisionWorld& view);

/// position_update: x += dt v, for the awake bodies.
void positionUpdateStage(WorldData& world, float dt);

/// mesh_update: every awake body's embedded mesh vertices from its particles.
void meshUpdateStage(WorldData& world);

} // namespace ffd::detail
