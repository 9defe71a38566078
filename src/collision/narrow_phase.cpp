// Reference: Jung, Hong, Choi, "Collision Handling for Free-Form Deformation Embedded Surface",
// IET Image Processing 5(4), 2011; Jeon, Choi, Hong, "Enhanced FFD-AABB Collision Algorithm for
// Deformable Objects", 2012.
#include "collision/narrow_phase.h"

#include "dynamics/simd4.h"
#include "util/unwritten.h"

#include <cmath>

namespace ffd::detail {

BoxPlanes boxPlanes(const Vec3 nodes[8]) {
    BoxPlanes planes;
    const Vec3 centre = boxCentre(nodes);
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
                         Vec3 p, float skin) {
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
    // next cell belongs to that cell's box, not this one.
    const uint8_t candidates = exitFaces(outsideFaces);
    if (d[farthest] > 0 && !((candidates >> farthest) & 1)) return hit;
    float best = -INFINITY;
    for (int f = 0; f < 6; ++f)
        if ((candidates >> f) & 1)
            if (d[f] > best) best = d[f], hit.face = f;
    hit.inside = true;
    hit.distance = best;
    return hit;
}

void invertTrilinear4(const Vec3 c[8], const Vec3* p, Vec3* local, int count, int iterations) {
    // Unused lanes repeat the first point: their work is thrown away.
    auto lanes = [&](const Vec3* v, F4& x, F4& y, F4& z) {
        for (int k = 0; k < 4; ++k) {
            const Vec3& a = v[k < count ? k : 0];
            x[k] = a.x, y[k] = a.y, z[k] = a.z;
        }
    };
    F4 px, py, pz, lx, ly, lz;
    lanes(p, px, py, pz);
    lanes(local, lx, ly, lz);
    // The corners' differences along each axis, for the map's partial derivatives.
    struct Splat {
        F4 x, y, z;
    };
    auto splat3 = [](Vec3 v) { return Splat{splat(v.x), splat(v.y), splat(v.z)}; };
    Splat cs[8];
    for (int k = 0; k < 8; ++k) cs[k] = splat3(c[k]);
    const Splat e10 = splat3(c[1] - c[0]), e32 = splat3(c[3] - c[2]), e54 = splat3(c[5] - c[4]),
                e76 = splat3(c[7] - c[6]);
    const Splat e20 = splat3(c[2] - c[0]), e31 = splat3(c[3] - c[1]), e64 = splat3(c[6] - c[4]),
                e75 = splat3(c[7] - c[5]);
    const Splat e40 = splat3(c[4] - c[0]), e51 = splat3(c[5] - c[1]), e62 = splat3(c[6] - c[2]),
                e73 = splat3(c[7] - c[3]);
    const F4 one = splat(1.0f);
    I4 active = {-1, -1, -1, -1};
    for (int it = 0; it < iterations; ++it) {
        const F4 s = lx, t = ly, u = lz;
        const F4 s0 = one - s, t0 = one - t, u0 = one - u;
        const F4 w[8] = {s0 * t0 * u0, s * t0 * u0, s0 * t * u0, s * t * u0,
                         s0 * t0 * u,  s * t0 * u,  s0 * t * u,  s * t * u};
        F4 fx = -px, fy = -py, fz = -pz;
        for (int k = 0; k < 8; ++k) {
            fx = fx + cs[k].x * w[k];
            fy = fy + cs[k].y * w[k];
            fz = fz + cs[k].z * w[k];
        }
        auto partial = [](const Splat& a, const Splat& b, const Splat& c2, const Splat& d, F4 fa,
                          F4 fb, F4 fc, F4 fd) {
            return Splat{a.x * fa + b.x * fb + c2.x * fc + d.x * fd,
                         a.y * fa + b.y * fb + c2.y * fc + d.y * fd,
                         a.z * fa + b.z * fb + c2.z * fc + d.z * fd};
        };
        const Splat ds = partial(e10, e32, e54, e76, t0 * u0, t * u0, t0 * u, t * u);
        const Splat dt = partial(e20, e31, e64, e75, s0 * u0, s * u0, s0 * u, s * u);
        const Splat du = partial(e40, e51, e62, e73, s0 * t0, s * t0, s0 * t, s * t);
        auto cross3 = [](const Splat& a, const Splat& b) {
            return Splat{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
        };
        const Splat r0 = cross3(dt, du), r1 = cross3(du, ds), r2 = cross3(ds, dt);
        const F4 det = ds.x * r0.x + ds.y * r0.y + ds.z * r0.z;
        active &= abs4(det) > splat(1e-30f); // inverse's test: a lane without one stops here
        if (!any(active)) break;
        const F4 inv = one / det;
        const F4 sx = (r0.x * inv) * fx + (r0.y * inv) * fy + (r0.z * inv) * fz;
        const F4 sy = (r1.x * inv) * fx + (r1.y * inv) * fy + (r1.z * inv) * fz;
        const F4 sz = (r2.x * inv) * fx + (r2.y * inv) * fy + (r2.z * inv) * fz;
        lx = select(active, lx - sx, lx);
        ly = select(active, ly - sy, ly);
        lz = select(active, lz - sz, lz);
        active &= ~(sx * sx + sy * sy + sz * sz < splat(1e-12f)); // float precision reached
        if (!any(active)) break;
    }
    for (int k = 0; k < count; ++k) local[k] = {lx[k], ly[k], lz[k]};
}

namespace {

struct ClipVertex {
    Vec3 position, local;
};

// Sutherland-Hodgman: keeps the part of the polygon with dot(n, p) - offset <= 0. Each
// vertex's distance computed once (not once per edge), no division for the next vertex.
int clipPolygon(const ClipVertex* in, int count, Vec3 n, float offset, ClipVertex* out) {
    if (count == 0) return 0;
    int kept = 0;
    const float first = dot(n, in[0].position) - offset;
    float db = first;
    for (int i = 0; i < count; ++i) {
        const ClipVertex& a = in[i];
        const bool last = i + 1 == count;
        const ClipVertex& b = in[last ? 0 : i + 1];
        const float da = db;
        db = last ? first : dot(n, b.position) - offset;
        if (da <= 0) out[kept++] = a;
        if ((da <= 0) != (db <= 0)) {
            const float t = da / (da - db);
            out[kept++] = {a.position + (b.position - a.position) * t,
                           a.local + (b.local - a.local) * t};
        }
    }
    return kept;
}

// The least signed distance of `nodes` (8) from each face plane of `planes`, into out[0..5]
// (out[6..7]: padding): for each plane, minNum over the nodes in order of dot(normal, node) -
// offset, the six planes in the lanes of two vectors. The same sums in the same order as one
// plane at a time, so the same values.
void leastSeparations(const BoxPlanes& planes, const Vec3* nodes, float out[8]) {
    const Vec3* n = planes.normal;
    const float* o = planes.offset;
    const V4 normal[2] = {{{n[0].x, n[1].x, n[2].x, n[3].x},
                           {n[0].y, n[1].y, n[2].y, n[3].y},
                           {n[0].z, n[1].z, n[2].z, n[3].z}},
                          {{n[4].x, n[5].x, 0, 0}, {n[4].y, n[5].y, 0, 0}, {n[4].z, n[5].z, 0, 0}}};
    const F4 offset[2] = {{o[0], o[1], o[2], o[3]}, {o[4], o[5], 0, 0}};
    F4 least[2] = {splat(INFINITY), splat(INFINITY)};
    for (int k = 0; k < 8; ++k) {
        const V4 node{splat(nodes[k].x), splat(nodes[k].y), splat(nodes[k].z)};
        for (int h = 0; h < 2; ++h) {
            const F4 d = dot(normal[h], node) - offset[h];
            // minNum(least, d) lane by lane: least unless d is smaller (or least is NaN and d
            // is not).
            least[h] = select((least[h] <= d) | (d != d), least[h], d);
        }
    }
    store4(out, least[0]);
    store4(out + 4, least[1]);
}

// The manifold's four points out of `kept` found ones on normal n.
void reduceToFour(const ManifoldPoint* found, int kept, Vec3 n, BoxPairManifold& m) {
    int pick[4];
    pickFour(found, kept, n, pick);
    for (int k : pick)
        if (k >= 0) m.point[m.count++] = found[k];
}

} // namespace

BoxPairManifold boxPairManifold(const BoxView& first, const BoxView& second, float margin,
                                float tolerance) {
    BoxPairManifold m;
    const BoxView* boxes[2] = {&first, &second};
    // Separation of the other box from each face plane of each box: the least signed distance
    // of the other's nodes. The first box's planes are tested before the second's are computed:
    // on the alphabets, 23 % of the pairs tested are apart along one of them.
    float separation[2][8];
    float farthest = -INFINITY;
    int farthestBox = 0, farthestFace = 0;
    for (int r = 0; r < 2; ++r) {
        leastSeparations(*boxes[r]->planes, boxes[1 - r]->nodes, separation[r]);
        for (int f = 0; f < 6; ++f) {
            const float s = separation[r][f];
            if (!(s < margin)) return m; // apart along this plane by more than the margin
            if (s > farthest) farthest = s, farthestBox = r, farthestFace = f;
        }
    }
    auto exits = [&](int r) { return exitFaces(boxes[r]->outsideFaces); };
    // Apart along a plane that leads into the neighbouring cell of its body: that cell's box
    // is what the other box meets.
    if (farthest > 0 && !((exits(farthestBox) >> farthestFace) & 1)) return m;
    // Overlapping along every plane, least along one that leads into a neighbouring cell: the
    // pair shows no more than that overlap.
    if (!((exits(farthestBox) >> farthestFace) & 1)) m.depthBound = -farthest;
    // The reference face: the allowed face of least overlap of each box; the second box's
    // only when it is better by the tolerance, so that two boxes face to face keep one
    // reference from substep to substep instead of flipping on rounding (which moves the
    // contact points between the two faces' corners and leaves a resting stack jittering).
    float bestOf[2] = {-INFINITY, -INFINITY};
    int faceOf[2] = {-1, -1};
    for (int r = 0; r < 2; ++r)
        for (int f = 0; f < 6; ++f)
            if (((exits(r) >> f) & 1) && separation[r][f] > bestOf[r])
                bestOf[r] = separation[r][f], faceOf[r] = f;
    m.reference = faceOf[0] >= 0 ? 0 : 1;
    if (faceOf[0] >= 0 && faceOf[1] >= 0 && bestOf[1] > bestOf[0] + tolerance) m.reference = 1;
    m.face = faceOf[m.reference];
    const float best = bestOf[m.reference];
    if (m.face < 0 || !(best < margin)) {
        m.reference = -1;
        return m;
    }
    const BoxView& ref = *boxes[m.reference];
    const BoxView& inc = *boxes[1 - m.reference];
    const Vec3 n = ref.planes->normal[m.face];
    const float offset = ref.planes->offset[m.face];
    m.normal = n;
    // The incident face: the one whose normal is most opposed to the reference normal.
    int incident = 0;
    float opposed = INFINITY;
    for (int g = 0; g < 6; ++g) {
        const float d = dot(inc.planes->normal[g], n);
        if (d < opposed) opposed = d, incident = g;
    }
    Unwritten<ClipVertex, 16> polygon[2];
    int count = 4;
    for (int k = 0; k < 4; ++k) {
        const int node = kFaceNodes[incident][k];
        polygon[0][k] = {inc.nodes[node], inc.local[node]};
    }
    int cur = 0;
    for (int side = 0; side < 6 && count > 0; ++side) {
        if ((side >> 1) == (m.face >> 1)) continue;
        count = clipPolygon(polygon[cur].data(), count, ref.planes->normal[side],
                            ref.planes->offset[side], polygon[1 - cur].data());
        cur = 1 - cur;
    }
    Unwritten<ManifoldPoint, 16> found;
    int kept = 0;
    for (int k = 0; k < count; ++k) {
        const float d = dot(n, polygon[cur][k].position) - offset;
        if (d < margin) found[kept++] = {polygon[cur][k].position, polygon[cur][k].local, d, n};
    }
    if (kept == 0) {
        // The incident face lies beyond the reference face's sides (an edge or a corner of the
        // incident box reaching in across a side of the reference face): its nodes within the
        // margin of the reference plane, which the planes say the pair overlaps by.
        for (int k = 0; k < 8; ++k) {
            const float d = dot(n, inc.nodes[k]) - offset;
            if (d < margin) found[kept++] = {inc.nodes[k], inc.local[k], d, n};
        }
        if (kept == 0) {
            m.reference = -1;
            return m;
        }
    }
    if (kept <= 4) {
        for (int k = 0; k < kept; ++k) m.point[k] = found[k];
        m.count = kept;
    } else {
        reduceToFour(found.data(), kept, n, m);
    }
    // Side points: incident nodes below the reference plane and beside one of its sides that
    // leads out of the reference box's body, within the margin of that side's plane.
    const uint8_t refExits = exitFaces(ref.outsideFaces);
    for (int k = 0; k < 8 && m.count < 8; ++k) {
        const Vec3 p = inc.nodes[k];
        if (!(dot(n, p) - offset < 0)) continue;
        int side = -1;
        float beyond = 0;
        bool near = true;
        for (int g = 0; g < 6; ++g) {
            if (g == m.face) continue;
            const float d = dot(ref.planes->normal[g], p) - ref.planes->offset[g];
            if (!(d < margin)) near = false;
            if ((g >> 1) != (m.face >> 1) && d > beyond && ((refExits >> g) & 1))
                beyond = d, side = g;
        }
        if (!near || side < 0) continue;
        m.point[m.count++] = {p, inc.local[k], beyond, ref.planes->normal[side]};
    }
    return m;
}

} // namespace ffd::detail
