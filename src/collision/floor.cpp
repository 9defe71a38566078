// floor_contacts: what of each body lies within the speculative margin of the floor and of the
// plane colliders (collision/pipeline.h): its cell boxes' corners (the paper's nodes), or with
// WorldSettings::vertexFloorContacts its mesh's vertices, a few per box.
#include "collision/margins.h"
#include "collision/pipeline.h"

#include <algorithm>
#include <cmath>
#include <span>

namespace ffd::detail {

namespace {

// The contact of body b's point `local` in world-wide box `box` with the plane
// dot(normal, p) = offset (the floor or a plane collider), `distance` above it; `node` names the
// point (Contact::nodeA).
Contact planeContact(const CollisionWorld& w, uint32_t b, uint32_t box, Vec3 local, uint32_t node,
                     Vec3 normal, float offset, float distance) {
    const CollisionBody& r = w.bodies[b];
    Contact c;
    c.bodyA = b;
    c.nodeA = node;
    c.normal = normal;
    c.offset = offset;
    c.distance = distance;
    setPushOut(w, r, b, kFloorBody, c);
    c.friction = r.friction;
    c.restitution = r.restitution;
    c.rigidity = r.contactRigidity;
    makeContactPoint(box, local, w.collision.boxParticles, w.invMass, c.a, c.invMassA);
    return c;
}

// How far above a plane a point of body r still makes a contact: what the body can travel in a
// substep, plus its skin.
float planeMargin(const CollisionWorld& w, const CollisionBody& r) {
    return skinOf(w, r) + w.substep * r.maxSpeed;
}

// Calls fn(k, corner, node) for body b's box nodes within the margin of the plane
// dot(n, p) = offset on its open side: its k-th box's corner `corner`, world-wide `node`. The
// floor is the plane n = +y.
template <class F>
void forNodesNearPlane(const CollisionWorld& w, uint32_t b, const Plane& plane, F&& fn) {
    const CollisionBody& r = w.bodies[b];
    if (r.immovable) return; // contacts do not move it
    const float limit = plane.offset + planeMargin(w, r);
    if (lowestAlong(plane.normal, r.bounds) >= limit) return;
    for (uint32_t k = 0; k < r.boxCount; ++k) {
        if (lowestAlong(plane.normal, w.boxBounds[r.firstBox + k]) >= limit) continue;
        for (int corner = 0; corner < 8; ++corner) {
            const uint32_t node = (r.firstBox + k) * 8 + uint32_t(corner);
            if (dot(plane.normal, w.nodes[node]) < limit) fn(k, corner, node);
        }
    }
}

// How far below a plane a vertex may get within a substep without a contact of its own, as a
// share of the contact skin (pickPlaneVertices).
constexpr float kVertexSlop = 0.2f;

// Of one box's vertices near a plane (`near`, in vertex order), those that get contacts,
// appended to `out` in the same order: all of them when four or fewer; else the deepest, the
// one farthest from it, the two that span the largest triangles with those two on either side
// (pickFour, as a box pair's manifold is reduced), and every other vertex that its
// velocity would take more than `slop` below the plane within the substep. The four hold the
// box's part of the surface where it lies on the plane, and move over the surface as the body
// turns; the others are left to them while the body moves as they do, and get contacts of
// their own once it moves otherwise (a tumbling letter landing: the four alone let one of its
// vertices 1 cm below the floor, docs/ALGORITHM.md section 5).
void reduceBoxVertices(std::span<const CollisionState::PlaneVertex> near, Vec3 normal, float slop,
                       std::vector<CollisionState::PlaneVertex>& out) {
    const size_t n = near.size();
    if (n <= 4) {
        out.insert(out.end(), near.begin(), near.end());
        return;
    }
    int pick[4];
    pickFour(near.data(), int(n), normal, pick);
    for (size_t m = 0; m < n; ++m)
        if (std::find(pick, pick + 4, int(m)) != pick + 4 || near[m].ahead < -slop)
            out.push_back(near[m]);
}

// Body b's vertices that get contacts with `planes` this substep (vertexFloorContacts), plane
// by plane, box by box, into `out`: of each box near a plane, its vertices within the margin,
// reduced (reduceBoxVertices). `near` is scratch.
void pickPlaneVertices(const CollisionWorld& w, uint32_t b, std::span<const Plane> planes,
                       std::vector<CollisionState::PlaneVertex>& near,
                       std::vector<CollisionState::PlaneVertex>& out) {
    out.clear();
    const CollisionBody& r = w.bodies[b];
    if (r.immovable) return;
    const Lattice& L = *r.lattice;
    const float margin = planeMargin(w, r), slop = kVertexSlop * skinOf(w, r);
    const std::span<const BoxParticles> boxes = w.collision.boxParticles;
    for (uint32_t p = 0; p < planes.size(); ++p) {
        const Plane& plane = planes[p];
        const float limit = plane.offset + margin;
        if (lowestAlong(plane.normal, r.bounds) >= limit) continue;
        for (uint32_t k = 0; k < r.boxCount; ++k) {
            const uint32_t box = r.firstBox + k;
            // The box's corners bound its vertices (a trilinear map's extremes over a box lie
            // at its corners).
            if (lowestAlong(plane.normal, w.boxBounds[box]) >= limit) continue;
            near.clear();
            // Each vertex's height first, from its cell's corners' heights (a vertex is the
            // trilinear blend of its cell's particles; most of a box's lie above the margin).
            float h[8];
            for (int c = 0; c < 8; ++c) h[c] = dot(plane.normal, w.x[boxes[box][size_t(c)]]);
            for (uint32_t i = L.boxVertexStart[k]; i < L.boxVertexStart[k + 1]; ++i) {
                const BoxVertex& v = L.boxVertices[i];
                const Vec3 q = v.local;
                auto lerp = [](float lo, float hi, float t) { return lo + (hi - lo) * t; };
                const float height =
                    lerp(lerp(lerp(h[0], h[1], q.x), lerp(h[2], h[3], q.x), q.y),
                         lerp(lerp(h[4], h[5], q.x), lerp(h[6], h[7], q.x), q.y), q.z);
                if (height >= limit) continue;
                const PointWeights at(ContactPoint{box, v.local}, boxes);
                const Vec3 x = blend(at, w.x);
                const float distance = dot(plane.normal, x) - plane.offset;
                const float ahead = distance + w.substep * dot(plane.normal, blend(at, w.v));
                near.push_back({box, v.vertex, p, v.local, x, distance, ahead});
            }
            reduceBoxVertices(near, plane.normal, slop, out);
        }
    }
}

// Appends the contacts of every body with `planes`, body by body, plane by plane in each.
// Counted per body, then made at their places: the same order for any thread count, and each
// contact written once, on the thread that makes it (contacts are large: copying them from
// per-thread lists into place cost more than making them, measured on alphabets).
void appendPlaneContacts(CollisionWorld& w, std::span<const Plane> planes) {
    CollisionState& s = w.collision;
    const uint32_t n = uint32_t(w.bodies.size());
    constexpr size_t kBodiesPerChunk = 8;
    const bool byVertex = w.settings.vertexFloorContacts != 0;
    if (byVertex) {
        if (s.planeVertices.size() < n) s.planeVertices.resize(n);
        const size_t slots = size_t(w.workers.count());
        if (s.planeVertexScratch.size() < slots) s.planeVertexScratch.resize(slots);
    }
    std::vector<size_t>& start = s.floorStart;
    start.assign(n + 1, 0);
    w.workers.forChunks(n, kBodiesPerChunk, [&](size_t first, size_t last, int slot) {
        for (uint32_t b = uint32_t(first); b < last; ++b) {
            if (byVertex) {
                pickPlaneVertices(w, b, planes, s.planeVertexScratch[size_t(slot)],
                                  s.planeVertices[b]);
                start[b + 1] = s.planeVertices[b].size();
                continue;
            }
            for (const Plane& plane : planes)
                forNodesNearPlane(w, b, plane, [&](uint32_t, int, uint32_t) { ++start[b + 1]; });
        }
    });
    start[0] = s.all.size();
    for (uint32_t b = 0; b < n; ++b) start[b + 1] += start[b];
    if (start[n] == start[0]) return;
    // With room to grow: a resize past the capacity allocates the exact size when it adds
    // more than the list holds, and the count changes every substep.
    if (s.all.capacity() < start[n]) s.all.reserve(start[n] + start[n] / 2);
    s.all.resize(start[n]); // the new contacts are left unwritten (ContactList): written below
    w.workers.forChunks(n, kBodiesPerChunk, [&](size_t first, size_t last, int) {
        for (uint32_t b = uint32_t(first); b < last; ++b) {
            size_t at = start[b];
            if (byVertex) {
                for (const CollisionState::PlaneVertex& v : s.planeVertices[b])
                    s.all[at++] =
                        planeContact(w, b, v.box, v.local, v.vertex, planes[v.plane].normal,
                                     planes[v.plane].offset, v.distance);
                continue;
            }
            for (const Plane& plane : planes)
                forNodesNearPlane(w, b, plane, [&](uint32_t k, int corner, uint32_t node) {
                    const uint32_t box = w.bodies[b].firstBox + k;
                    s.all[at++] =
                        planeContact(w, b, box, w.bodies[b].lattice->boxes[k].nodeLocal(corner),
                                     node, plane.normal, plane.offset,
                                     dot(plane.normal, w.nodes[node]) - plane.offset);
                });
        }
    });
}

} // namespace

void findFloorContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    s.all.resize(s.objectCount);
    // The floor's contacts, then the plane colliders'.
    if (w.settings.floor) {
        const Plane floor{{0, 1, 0}, w.settings.floorHeight};
        appendPlaneContacts(w, std::span(&floor, 1));
    }
    if (!w.planes.empty()) appendPlaneContacts(w, w.planes);
    w.profile.floorContacts = int(s.all.size() - s.objectCount);
}

} // namespace ffd::detail
