// Phase 3 of the Enhanced FFD-AABB pipeline, between the deformed cell boxes of two objects
// (Jung, Hong, Choi 2011; Jeon, Choi, Hong 2012), grown from the paper's node-against-planes
// test into a box-pair test.
//
// A deformed box's faces are bilinear patches; each is approximated by the plane through its
// four nodes' centroid with normal (q2 - q0) x (q3 - q1), oriented away from the box centre.
// The paper tests each boundary node of one object against the six planes of the other's
// boxes and pushes it out through the nearest face. Measured on the alphabets scene, that
// leaves meshes up to 12 cm inside each other with every node contact met: nodes of one box
// pushed out through different faces of the other, or crossing edges with no node inside, leave
// the boxes overlapping (docs/ALGORITHM.md, section 4). So a pair of boxes whose nodes come
// within the pair's margin of each other's (found by the paper's phases 1 and 2) is tested as a
// pair: separating axes on both boxes' face planes, one normal for the pair (the face of least
// overlap among those that lead out of their objects), and the incident face clipped to the
// reference face: at most four points (Gregorius, "Robust Contact Creation for Physics
// Simulations", GDC 2015; Ericson, Real-Time Collision Detection, ch. 5).
// Pure functions: no world needed, so they are tested on their own.
#pragma once

#include "ffdaabb/lattice.h"
#include "ffdaabb/math.h"
#include "util/unwritten.h"

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

/// A deformed box's centre: the mean of its 8 nodes (BoxPlanes::centre, and phase 2's ninth
/// sample of the box).
inline Vec3 boxCentre(const Vec3 nodes[8]) {
    Vec3 centre{};
    for (int n = 0; n < 8; ++n) centre += nodes[n];
    return centre * 0.125f;
}

/// The faces of a box that lead out of its object, as BoxFace bits: its outside faces, or all
/// six when it has none.
inline uint8_t exitFaces(uint8_t outsideFaces) {
    return outsideFaces ? outsideFaces : uint8_t(63);
}

/// Result of a node/box test.
struct NodeBoxHit {
    bool inside = false;
    int face = -1;      ///< face whose plane gives the way out
    float distance = 0; ///< signed distance to that face (negative = penetrating)
};

/// Tests node p against the box (its face planes, its nodes' AABB and its outside-face mask):
/// inside when within `skin` of every plane, the way out through the nearest outside face (all
/// six when there is none); a node outside by a face that is not an outside face is in the
/// neighbouring cell's region and not inside. The box-pair test (boxPairManifold) makes the
/// contacts; this serves tools and tests that ask whether a point lies in a box.
NodeBoxHit testNodeInBox(const BoxPlanes& planes, const Aabb& nodeBounds, uint8_t outsideFaces,
                         Vec3 p, float skin);

/// Local coordinates (s,t,u) of `count` (1 to 4) points p in the trilinear map of 8 corner
/// positions (corner i + 2j + 4k), by Newton's method from the guesses in local[k], which
/// become the best iterates: at most `iterations` steps, a point stopping where its Jacobian
/// has no inverse (|det| <= 1e-30) or its step has reached float precision (squared length
/// under 1e-12). The points go in vector lanes that never mix, so a point's result does not
/// depend on the others: bit for bit what one point at a time gives by the same steps in
/// scalar arithmetic (test NarrowPhase.TrilinearInversionInLanesIsTheScalarOneBitForBit).
void invertTrilinear4(const Vec3 corners[8], const Vec3* p, Vec3* local, int count, int iterations);

/// One cell box for the box-pair test: its 8 nodes (node n = i + 2j + 4k), their local
/// coordinates in the box's lattice cell, its face planes and its outside faces (BoxFace bits).
struct BoxView {
    const Vec3* nodes = nullptr;
    Vec3 local[8];
    const BoxPlanes* planes = nullptr;
    uint8_t outsideFaces = 0;
};

/// One point of a box pair's contact manifold: a point of the incident box's face, or one of
/// its nodes beside a side of the reference face.
struct ManifoldPoint {
    Vec3 position;      ///< world position (on the incident face, linearly interpolated)
    Vec3 local;         ///< local coordinates in the incident box's cell
    float distance = 0; ///< signed distance to the plane of `normal` (negative: inside)
    Vec3 normal;        ///< the way the incident box must move at this point
};

/// The contact manifold of two deformed cell boxes (boxPairManifold).
struct BoxPairManifold {
    int reference = -1; ///< 0: the first box holds the reference face, 1: the second; -1: none
    int face = -1;      ///< the reference face (kFaceNodes order)
    Vec3 normal;        ///< its outward normal: the way the incident box must move
    int count = 0;
    /// The clipped face's points (at most four, on `normal`), then the side points: incident
    /// nodes below the reference plane but beside one of its outside side faces, within the
    /// margin of it, on that face's normal (at most four). Only the first `count` are written:
    /// most pairs tested have none, and filling the eight took 3 % of the box-pair test.
    Unwritten<ManifoldPoint, 8> point;
    /// How deep the pair can show its boxes overlap: when the plane of least overlap of all
    /// twelve leads into the neighbouring cell of its body, that overlap (>= 0), since the rest
    /// of the overlap along the normal lies across that plane, where the neighbouring cell's box
    /// meets the other box; infinity otherwise. A box grazing that plane can lie a whole cell
    /// deep along the normal: claimed at once, that depth threw resting bodies into the air
    /// (docs/ALGORITHM.md, section 5).
    float depthBound = INFINITY;
};

/// Of `count` points (anything with a `position` and a signed `distance` to a plane of normal
/// n), the indices of the four that a contact manifold keeps: the deepest, the farthest from it,
/// and the two that span the largest triangles with those two on either side (-1 where none
/// does; the second is the first when every point lies where the deepest does). Box pairs'
/// manifolds (boxPairManifold) and the floor's vertices (floor.cpp) are reduced by it.
template <class Point>
void pickFour(const Point* points, int count, Vec3 n, int pick[4]) {
    pick[0] = 0, pick[1] = pick[2] = pick[3] = -1;
    for (int k = 1; k < count; ++k)
        if (points[k].distance < points[pick[0]].distance) pick[0] = k;
    float far = -1;
    for (int k = 0; k < count; ++k) {
        const float d2 = lengthSquared(points[k].position - points[pick[0]].position);
        if (d2 > far) far = d2, pick[1] = k;
    }
    float most = 0, least = 0;
    const Vec3 a = points[pick[0]].position, b = points[pick[1]].position;
    for (int k = 0; k < count; ++k) {
        const float area = dot(cross(b - a, points[k].position - a), n);
        if (area > most) most = area, pick[2] = k;
        if (area < least) least = area, pick[3] = k;
    }
}

/// Separating-axis test of two deformed cell boxes on their twelve face planes, and the
/// manifold of the axis of least overlap among the faces that lead out of their bodies
/// (outside faces; all six when a box has none): the incident box's face most opposed to the
/// reference face, clipped to the reference face's side planes, the points closer than
/// `margin` to the reference plane (the incident box's nodes closer than that when the clipped
/// face keeps none), at most four (the deepest, the farthest from it, and the two that span the
/// largest triangles with those on either side); and the incident box's nodes that lie below the
/// reference plane beside one of the reference face's sides that leads out of its body, within
/// `margin` of that side's plane, as points on that side's normal: the clip drops them, and a
/// box moving in across that side in the substep would be met by nothing (docs/ALGORITHM.md,
/// section 4, "Side points"). No contact when the boxes lie more than `margin`
/// apart along any face plane, or apart along one that leads into the neighbouring cell of its body
/// (that cell's box meets the other box first); when they overlap least along such a plane, the
/// manifold's depthBound says by how much. The first box holds the reference face unless the
/// second's face overlaps less by more than `tolerance`.
BoxPairManifold boxPairManifold(const BoxView& first, const BoxView& second, float margin,
                                float tolerance);

} // namespace ffd::detail
