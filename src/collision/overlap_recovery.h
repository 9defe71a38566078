// Recovery of bodies placed overlapping (WorldSettings::overlapRecoverySpeed).
//
// A body added, translated or given new particle positions inside another body or below the
// floor starts with an overlap that no collision caused. Projected out at once it becomes a
// dent that shape matching restores at depth / substep, and the rigid phase turns that speed
// into rigid motion: 200 spheres created overlapping left at 44 m/s, a sphere teleported onto
// another at 14 m/s, 50 spheres created at one spot made 224,000 contacts and never parted.
// So the pairs a placed body forms (bounding spheres that touch, the floor when its node bounds
// reach within the skin of it) are remembered, and until they are apart:
//   - a pair with a contact deeper than the skin recovers: its contacts keep all their overlap
//     (Contact::tolerated) and only stop the bodies sinking further, the rigid phase leaves
//     them out, and its bodies move apart as rigid wholes, by positions only, along the way out
//     of its contacts' overlap (their normals weighted by depth), no further than that depth,
//     at the recovery speed split by mass. Moved by the contacts' particles instead, the
//     overlap became a dent that shape matching restored with velocity: two spheres placed
//     30 cm into each other left at 1.51 m/s each and drifted for ever (now 0.07 m/s);
//   - a pair with a centre of mass inside one of the other's lattice cells (deformed cell
//     bounds, interior cells included) is "whole": it finds no object contacts, which would push
//     every node every way and only crush both, and its bodies move apart as rigid wholes along
//     the line of their centres (a direction drawn from the pair's indices when the centres
//     coincide), under gravity along that line's part across gravity, by positions only, at
//     the recovery speed split by mass. A pair that has overlapped stays whole until neither
//     centre is within one cell of the other's cells, so the object contacts take over
//     shallower overlap only. The pair moves as one but for separating along that line (one
//     resting on the other would fall through it, or slide off it).
//   - the bodies joined by whole pairs, with those whose bounding spheres touch them, form a
//     heap; a heap of three or more also pushes each body away from its centre of mass, across
//     gravity, in proportion to the body's distance from it, within the whole pairs' bound, so
//     it expands about its centre instead of pushing its rim into its neighbours.
//   A body's moves from its whole pairs and from its recovering pairs are each summed weighted
//   by how deep each pair is and bounded to the recovery speed. Never down into the floor (the
//   floor would stop the lowest cells only, and the dent would throw the body up): a body within
//   reach of the floor is fixed for the pairs that push it down, and its partners move instead.
//   The sum is then shortened so that the body's centre, which also travels at its velocity,
//   goes no faster than WorldSettings::overlapRecoveryMaxSpeed (or its velocity, if faster).
// A pair is forgotten once it is not whole and either never had a contact deeper than the skin
// or has made its last move (no more overlap than one substep's move): from then on it collides
// as any other pair. Pairs that meet in motion are never remembered, so scenes
// that place nothing overlapping run bit for bit as with the recovery off.
#pragma once

#include <cstdint>

namespace ffd::detail {

struct CollisionWorld;

/// Stands for the floor as the second body of a remembered pair.
inline constexpr uint32_t kFloorBody = UINT32_MAX;

/// Before the contacts of a substep (after the node update): remembers the pairs of bodies
/// placed since the last substep (bounding spheres that touch, or node bounds below the
/// floor's skin) and marks the whole pairs. Computes every body's bounding sphere when it
/// needs them. No-op (and no cost) when nothing is placed or remembered.
void trackOverlaps(CollisionWorld& world);

struct OverlapPair;

/// The pair (dense indices, any order; kFloorBody for the floor) if it is remembered, else null.
const OverlapPair* recoveringPair(const CollisionWorld& world, uint32_t bodyA, uint32_t bodyB);

/// Whether the pair is whole this substep (its object contacts are left out).
bool isWhole(const CollisionWorld& world, uint32_t bodyA, uint32_t bodyB);

/// After the contacts of a substep were found: forgets the pairs that are apart.
void settleOverlaps(CollisionWorld& world);

/// After trackOverlaps, before the contacts: moves the bodies of remembered pairs apart as rigid
/// wholes (positions, nodes and bounds): whole pairs along the line of their centres, across
/// gravity (their velocities lose all relative motion but separating along that line), the
/// others, and the floor's pairs, along the way out of their last substep's contacts' overlap.
void pushPairsApart(CollisionWorld& world, float dt);

/// Keeps the remembered pairs valid when body `dense` is removed (later ones shift down).
void forgetBody(CollisionWorld& world, uint32_t dense);

} // namespace ffd::detail
