// The margins the collision stages share: a body's skin, how far its nodes can travel in a
// substep (its reach), the margin of a node against another body's box, phase 1's sweep window,
// and how much of a deep contact's overlap the projections leave (push-out). Phase 1's test,
// phase 2's hash, phase 3's pairs and the floor all take them from here, so that every mode
// tests the same node/box pairs.
#pragma once

#include "collision/body.h"
#include "collision/contact.h"
#include "collision/overlap_recovery.h"

#include <cmath>

namespace ffd::detail {

/// A body's contact skin, metres (WorldSettings::contactSkin of its cell size).
inline float skinOf(const CollisionWorld& w, const CollisionBody& b) {
    return w.settings.contactSkin * b.cellSize;
}

// How far any node of a body can travel in one substep, as |V| + D (mean velocity and largest
// deviation from it; a node is a convex blend of its cell's particles, so none is faster than
// the fastest particle, and none of those is faster than |V| + D).
inline float reachOf(const CollisionWorld& w, const CollisionBody& b) {
    return w.substep * (length(b.meanVelocity) + b.spread);
}

// Contact margin between a node of A and a box of B: B's skin plus how far the two can close
// in one substep (speculative contacts: found before they touch, so the velocity solve can
// stop them at the surface however fast they come). Any point of A moves relative to any point
// of B by at most |V_A - V_B| + D_A + D_B (mean velocities and largest deviations from them):
// bodies falling together get a thin margin.
inline float marginOf(const CollisionWorld& w, const CollisionBody& a, const CollisionBody& b) {
    return skinOf(w, b) +
           w.substep * (length(a.meanVelocity - b.meanVelocity) + a.spread + b.spread);
}

// How far from the surface a point still makes a contact, given its approach speed along the
// contact's normal (>= 0): the skin, plus twice what it closes in the substep. The margin above
// bounds the two bodies' relative speed in any direction, which finds the box pairs; most of a
// landing pile's points it keeps (62 % at frame 60 of alphabets, more than four skins away)
// close the gap slower than that and leave the constraint inactive in every phase of the
// response (docs/ALGORITHM.md §4, "Speculative reach"). The factor 2 leaves room for what the
// other contacts' corrections add to the approach within the substep.
inline float speculativeReach(float skin, float approach, float substep) {
    return skin + 2.0f * approach * substep;
}

// The margin is never more than B's skin plus each body's own reach, reachOf(A) + reachOf(B)
// (|V_A - V_B| + D_A + D_B <= |V_A| + D_A + |V_B| + D_B). Finding the node/box pairs to test by
// these per-body terms makes what a box queries and how far a node reaches depend on their own
// bodies only: every mode tests the same node/box pairs for a pair of bodies, whichever other
// bodies it also tests, and the pair's margin then decides (findObjectContacts).

// A body's share of the largest margin phase 1 may allow its pairs (twice its skin and reach:
// 2 marginOf(A, B) <= 2 (max(skin A, skin B) + reach A + reach B)), for the sweep's window.
inline float sweepMargin(const CollisionWorld& w, const CollisionBody& b) {
    return 2.0f * (skinOf(w, b) + reachOf(w, b));
}

// Push-out of deep overlap: what the projections leave of a contact's overlap in this substep
// (Contact::tolerated), so that it goes at a bounded speed, and the rigid phase leaves the
// contact out. Removed at once, deep overlap became a dent that shape matching restored at
// depth / substep, and the rigid phase turned that speed into rigid motion: 200 overlapping
// spheres left at 44 m/s, two spheres created 5 cm into each other at 8 m/s (docs/ALGORITHM.md,
// "Overlap recovery" and "Push-out"). Pairs placed overlapping (overlap_recovery.h) keep all of
// it while they recover (or, before that, beyond the skin): the recovery moves their bodies
// apart as rigid wholes, and a contact only stops them sinking further. With
// WorldSettings::pushOutSpeed (0 by default: none) every contact deeper than the skin plus
// pushOutSpeed x substep loses at most that depth.
inline float toleratedOverlap(const CollisionWorld& w, const CollisionBody& b, float distance,
                              uint32_t bodyA, uint32_t bodyB) {
    if (distance < 0 && w.settings.overlapRecoverySpeed > 0)
        if (const OverlapPair* p = recoveringPair(w, bodyA, bodyB))
            if (p->deep || distance < -skinOf(w, b)) return distance;
    if (w.settings.pushOutSpeed == 0) return 0.0f;
    const float depth = skinOf(w, b) + w.settings.pushOutSpeed * w.substep;
    return distance < -depth ? distance + depth : 0.0f;
}

// Sets the contact's push-out: the overlap it keeps for later substeps and whether it does.
inline void setPushOut(const CollisionWorld& w, const CollisionBody& b, uint32_t bodyA,
                       uint32_t bodyB, Contact& c) {
    c.tolerated = toleratedOverlap(w, b, c.distance, bodyA, bodyB);
    c.pushedOut = c.tolerated < 0;
}

/// The least of dot(n, p) over the box's corners: how far along n its lowest corner lies.
inline float lowestAlong(Vec3 n, const Aabb& box) {
    return dot(n, Vec3{n.x >= 0 ? box.lo.x : box.hi.x, n.y >= 0 ? box.lo.y : box.hi.y,
                       n.z >= 0 ? box.lo.z : box.hi.z});
}

inline float combineFriction(const CollisionBody& a, const CollisionBody& b) {
    return std::sqrt(a.friction * b.friction);
}

} // namespace ffd::detail
