// Sleeping (WorldSettings::sleepSpeed, sleepTime): bodies at rest stop costing anything.
//
// A body is quiet in a frame when both its particles' root-mean-square velocity and their
// root-mean-square motion over the frame (which also sees positions moved without velocity:
// pre-stabilisation, the overlap recovery) are below sleepSpeed. Its quiet time grows by the
// frame while it is quiet and starts again from 0 when it is not. After each frame the awake
// bodies are joined into islands by the object contacts of the frame's last substep; an island
// all of whose bodies have been quiet for sleepTime (and may sleep) falls asleep at once, the
// way Box2D and Jolt put islands to sleep: a body alone would be woken again by a neighbour
// still settling. Before each frame, a sleeping body that an awake body may reach within the
// frame (its bounds grown by what it can travel in a frame under gravity, plus the larger
// skin) is woken with its island. Falling asleep and waking happen between frames only, so a
// body is asleep or awake for a whole step; inside a step a sleeping body is one of infinite
// mass (its particles' inverse masses in the collision view are 0). All of it is a function of
// the state, in body order: the same for any thread count.
#pragma once

#include <cstdint>

namespace ffd::detail {

struct WorldData;

/// After bodies came or went, slept or woke: the awake bodies' list, the dynamics batches, the
/// collision's view of the inverse masses and each collision body's flag.
void refreshAwake(WorldData& world);

/// Wakes body `dense` and every body that fell asleep with it; their quiet time starts again.
/// Returns whether any was asleep (refreshAwake then needed, and done).
bool wakeIsland(WorldData& world, uint32_t dense);

/// Wakes every sleeping body (what holds them may have changed: gravity, the floor, planes).
void wakeEverybody(WorldData& world);

/// Puts the bodies of `island` (dense indices) to sleep now: velocities 0, nodes, bounds and
/// spheres from the current positions and no motion. Then refreshAwake.
void putToSleep(WorldData& world, const uint32_t* bodies, uint32_t count);

/// Before a frame's substeps: wakes the sleeping bodies an awake body may reach in the frame,
/// and keeps the awake bodies' particles for the quiet test. No cost when sleeping is off.
void wakeWithinReach(WorldData& world);

/// After a frame: each awake body's quiet time, and the islands quiet long enough put to sleep.
void fallAsleep(WorldData& world);

} // namespace ffd::detail
