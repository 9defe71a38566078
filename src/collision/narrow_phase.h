// Phase 3 of the Enhanced FFD-AABB pipeline: a boundary node against the six face planes of
// another object's deformed cell box (Jung, Hong, Choi 2011; Jeon, Choi, Hong 2012).
//
// A deformed box's faces are bilinear patches; each is approximated by the plane through its
// four nodes' centroid with normal (q2 - q0) x (q3 - q1), oriented away from the box centre.
// A node is inside when it lies within the box's node bounds grown by the skin and its signed
// distance to all six planes is below the skin. The contact normal is that of the outside face
// (neighbouring lattice cell empty) with the largest signed distance: the nearest way out that
// leads out of the object, not into its neighbouring cell; all faces count when none is outside.
// A node lying outside the box (within the skin) beyond a face that is not an outside face
// gets no contact from this box: it is in the neighbouring cell's region.
// Pure functions: no world needed, so they are tested on their own.
#pragma once

#include "ffdaabb/lattice.h"
#include "ffdaabb/math.h"

namespace ffd::detail {

/// Node indices (n = i + 2j + 4k) of each face in cyclic order, faces -x,+x,-y,+y,-z,+z.
inline constexpr int kFaceNodes[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                         {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};

/// The six face planes of a deformed box: signed distance of p to face f is
/// dot(normal[f], p) - offset[f], positive outside.
struct BoxPlanes {
    Vec3 normal[6];
    float offset[6];
    /// The box's map from its parameters (a,b,c) in [0,1]^3, linearised at the centre:
    /// p ~ centre + frame * ((a,b,c) - 0.5); `inverseFrame` maps back (zero when degenerate).
    Vec3 centre;
    Mat3 inverseFrame;
};

/// Box parameters (a,b,c) of point p by the linearised map (exact for affine deformations).
inline Vec3 boxParameters(const BoxPlanes& box, Vec3 p) {
    return box.inverseFrame * (p - box.centre) + Vec3{0.5f, 0.5f, 0.5f};
}

BoxPlanes boxPlanes(const Vec3 nodes[8]);

/// Result of a node/box test.
struct NodeBoxHit {
    bool inside = false;
    int face = -1;      ///< face whose plane gives the contact normal
    float distance = 0; ///< signed distance to that face (negative = penetrating)
    uint8_t tied = 0;   ///< faces as near as `face` within the tie tolerance (bit per face)
};

/// Tests node p against the box (its 8 nodes, their AABB and its outside-face mask). The
/// candidate faces within `tieTolerance` of the nearest way out, and no deeper than it, are
/// reported as `tied`: at an edge or a corner of the box the nearest face is a near tie, which
/// the caller may settle (settleTie).
NodeBoxHit testNodeInBox(const BoxPlanes& planes, const Aabb& nodeBounds, uint8_t outsideFaces,
                         Vec3 p, float skin, float tieTolerance = 0);

/// Settles a near tie (`hit.tied` holds two faces or more: the node is at an edge or a corner
/// of the box) by the side of the box the node comes from: when the centre of the node's own
/// box lies inside the nearest face's plane, pushing the node out through that face would not
/// take its box out of this one, and the tied face its box lies farthest outside of is taken.
void settleTie(const BoxPlanes& planes, Vec3 p, Vec3 ownCentre, NodeBoxHit& hit);

/// Local coordinates (s,t,u) of p in the trilinear map of 8 corner positions (corner
/// i + 2j + 4k), by Newton's method from `guess`; returns the best iterate.
Vec3 invertTrilinear(const Vec3 corners[8], Vec3 p, Vec3 guess, int iterations = 6);

} // namespace ffd::detail
