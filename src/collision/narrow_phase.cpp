// Reference: Jung, Hong, Choi, "Collision Handling for Free-Form Deformation Embedded Surface",
// IET Image Processing 5(4), 2011; Jeon, Choi, Hong, "Enhanced FFD-AABB Collision Algorithm for
// Deformable Objects", 2012.
#include "collision/narrow_phase.h"

#include <cmath>

namespace ffd::detail {

BoxPlanes boxPlanes(const Vec3 nodes[8]) {
    BoxPlanes planes;
    Vec3 centre{};
    for (int n = 0; n < 8; ++n) centre += nodes[n];
    centre *= 0.125f;
    planes.centre = centre;
    // Mean edge along each parameter: the trilinear map's derivative at the centre.
    const Vec3 ea =
        (nodes[1] - nodes[0] + nodes[3] - nodes[2] + nodes[5] - nodes[4] + nodes[7] - nodes[6]) *
        0.25f;
    const Vec3 eb =
        (nodes[2] - nodes[0] + nodes[3] - nodes[1] + nodes[6] - nodes[4] + nodes[7] - nodes[5]) *
        0.25f;
    const Vec3 ec =
        (nodes[4] - nodes[0] + nodes[5] - nodes[1] + nodes[6] - nodes[2] + nodes[7] - nodes[3]) *
        0.25f;
    if (!inverse(Mat3::fromColumns(ea, eb, ec), planes.inverseFrame, 1e-30f))
        planes.inverseFrame = Mat3{};
    for (int f = 0; f < 6; ++f) {
        const Vec3 q0 = nodes[kFaceNodes[f][0]], q1 = nodes[kFaceNodes[f][1]],
                   q2 = nodes[kFaceNodes[f][2]], q3 = nodes[kFaceNodes[f][3]];
        const Vec3 faceCentre = (q0 + q1 + q2 + q3) * 0.25f;
        Vec3 n = cross(q2 - q0, q3 - q1);
        if (dot(n, faceCentre - centre) < 0) n = -n;
        float len = length(n);
        if (!(len > 0)) {
            // A face collapsed to a line or a point: fall back on the direction from the box
            // centre, or the rest axis when even that vanishes.
            n = faceCentre - centre;
            len = length(n);
            if (!(len > 0)) {
                n = Vec3{};
                n[f >> 1] = (f & 1) ? 1.0f : -1.0f;
                len = 1.0f;
            }
        }
        n = n / len;
        planes.normal[f] = n;
        planes.offset[f] = dot(n, faceCentre);
    }
    return planes;
}

NodeBoxHit testNodeInBox(const BoxPlanes& planes, const Aabb& nodeBounds, uint8_t outsideFaces,
                         Vec3 p, float skin, float tieTolerance) {
    NodeBoxHit hit;
    if (!nodeBounds.contains(p, skin)) return hit;
    float d[6];
    int farthest = 0;
    for (int f = 0; f < 6; ++f) {
        d[f] = dot(planes.normal[f], p) - planes.offset[f];
        if (!(d[f] < skin)) return hit;
        if (d[f] > d[farthest]) farthest = f;
    }
    // A node outside the box (within the skin) through a face that leads into the object's own
    // next cell belongs to that cell's box, not this one: taken here it would be pushed out
    // through some far outside face as if it were deep inside.
    const uint8_t candidates = outsideFaces ? outsideFaces : uint8_t(63);
    if (d[farthest] > 0 && !((candidates >> farthest) & 1)) return hit;
    float best = -INFINITY;
    for (int f = 0; f < 6; ++f)
        if ((candidates >> f) & 1)
            if (d[f] > best) best = d[f], hit.face = f;
    for (int f = 0; f < 6; ++f)
        if (((candidates >> f) & 1) && d[f] >= best - tieTolerance && d[f] >= -tieTolerance)
            hit.tied |= uint8_t(1u << f);
    hit.inside = true;
    hit.distance = best;
    return hit;
}

void settleTie(const BoxPlanes& planes, Vec3 p, Vec3 ownCentre, NodeBoxHit& hit) {
    if (!(hit.tied & (hit.tied - 1))) return;
    auto side = [&](int f) { return dot(planes.normal[f], ownCentre) - planes.offset[f]; };
    if (side(hit.face) > 0) return;
    int face = -1;
    float farthest = 0;
    for (int f = 0; f < 6; ++f)
        if (((hit.tied >> f) & 1) && side(f) > farthest) farthest = side(f), face = f;
    if (face < 0) return;
    hit.face = face;
    hit.distance = dot(planes.normal[face], p) - planes.offset[face];
}

Vec3 invertTrilinear(const Vec3 c[8], Vec3 p, Vec3 guess, int iterations) {
    Vec3 l = guess;
    for (int it = 0; it < iterations; ++it) {
        const float s = l.x, t = l.y, u = l.z;
        float w[8];
        trilinearWeights(l, w);
        Vec3 f = -p;
        for (int k = 0; k < 8; ++k) f += c[k] * w[k];
        // Partial derivatives of the trilinear map.
        const Vec3 ds = (c[1] - c[0]) * ((1 - t) * (1 - u)) + (c[3] - c[2]) * (t * (1 - u)) +
                        (c[5] - c[4]) * ((1 - t) * u) + (c[7] - c[6]) * (t * u);
        const Vec3 dt = (c[2] - c[0]) * ((1 - s) * (1 - u)) + (c[3] - c[1]) * (s * (1 - u)) +
                        (c[6] - c[4]) * ((1 - s) * u) + (c[7] - c[5]) * (s * u);
        const Vec3 du = (c[4] - c[0]) * ((1 - s) * (1 - t)) + (c[5] - c[1]) * (s * (1 - t)) +
                        (c[6] - c[2]) * ((1 - s) * t) + (c[7] - c[3]) * (s * t);
        Mat3 J = Mat3::fromColumns(ds, dt, du), Jinv;
        if (!inverse(J, Jinv, 1e-30f)) break;
        const Vec3 step = Jinv * f;
        l -= step;
        if (lengthSquared(step) < 1e-12f) break; // float precision of local coordinates
    }
    return l;
}

} // namespace ffd::detail
