// Recovery of bodies placed overlapping (WorldSettings::overlapRecoverySpeed).
//
// A body added, translated or given new particle positions inside another body or below the
// floor starts with an overlap that no collision caused. Projected out at once it becomes a
// dent that shape matching restores at depth / substep, and the rigid phase turns that speed
// into rigid motion: 200 spheres created overlapping left at 44 m/s, a sphere teleported onto
// another at 14 m/s, 50 spheres created at one spot made 224,000 contacts and never parted.
// So the pairs a placed body forms (bounding spheres that touch, the floor when its node bounds
// reach within the skin of it) are remembered, and until they are apart:
//   - a node contact of the pair keeps any overlap beyond the recovery speed x substep for the
//     next substep (Contact::tolerated, as WorldSettings::pushOutSpeed does for every contact):
//     the overlap goes at that speed, by moving positions, and the rigid phase leaves it out;
//   - a pair with a centre of mass inside one of the other's lattice cells (deformed cell
//     bounds, interior cells included) is "whole": it finds no object contacts, which would push
//     every node every way and only crush both, and its bodies move apart as rigid wholes along
//     the line of their centres (a direction drawn from the pair's indices when the centres
//     coincide), by positions only, at the recovery speed split by mass; a body with many
//     such partners moves by their sum weighted by how deep each pair is, bounded to the same
//     speed; never down into the floor (the floor would stop the lowest cells only, and the dent
//     would throw the body up). The pair does not approach along that line either (one resting
//     on the other would fall through it). A pair that has overlapped stays whole until neither
//     centre is within one cell of the other's cells, so the object contacts take over shallow
//     overlap only.
// A pair is forgotten once it is not whole and has no contact deeper than the skin: from then
// on it collides as any other pair. Pairs that meet in motion are never remembered, so scenes
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

/// Whether the pair (dense indices, any order; kFloorBody for the floor) is remembered.
bool isRecovering(const CollisionWorld& world, uint32_t bodyA, uint32_t bodyB);

/// Whether the pair is whole this substep (its object contacts are left out).
bool isWhole(const CollisionWorld& world, uint32_t bodyA, uint32_t bodyB);

/// After the contacts of a substep were found: forgets the pairs that are apart.
void settleOverlaps(CollisionWorld& world);

/// After trackOverlaps, before the contacts: moves the bodies of whole pairs apart
/// (positions, nodes and bounds; velocities only lose the pairs' approach along their line).
void pushWholePairsApart(CollisionWorld& world, float dt);

/// Keeps the remembered pairs valid when body `dense` is removed (later ones shift down).
void forgetBody(CollisionWorld& world, uint32_t dense);

} // namespace ffd::detail
