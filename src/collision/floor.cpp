// floor_contacts: box nodes within the speculative margin of the floor and of the plane
// colliders (collision/pipeline.h).
#include "collision/margins.h"
#include "collision/pipeline.h"

#include <algorithm>
#include <cmath>
#include <span>

namespace ffd::detail {

namespace {

// The contact of body b's node `node` (its k-th box's corner `corner`) with the plane
// dot(normal, p) = offset (the floor or a plane collider), `distance` above it.
Contact planeContact(const CollisionWorld& w, uint32_t b, uint32_t k, int corner, uint32_t node,
                     Vec3 normal, float offset, float distance) {
    const CollisionBody& r = w.bodies[b];
    const CellBox& box = r.lattice->boxes[k];
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
    makeContactPoint(r.firstBox + k, box.nodeLocal(corner), w.collision.boxParticles, w.invMass,
                     c.a, c.invMassA);
    return c;
}

// Calls fn(k, corner, node) for body b's box nodes within the margin of the plane
// dot(n, p) = offset (what the body can travel in a substep, plus its skin) on its open side:
// its k-th box's corner `corner`, world-wide `node`. The floor is the plane n = +y.
template <class F>
void forNodesNearPlane(const CollisionWorld& w, uint32_t b, const Plane& plane, F&& fn) {
    const CollisionBody& r = w.bodies[b];
    if (r.immovable) return; // contacts do not move it
    const float skin = skinOf(w, r) + w.substep * r.maxSpeed;
    const float limit = plane.offset + skin;
    if (lowestAlong(plane.normal, r.bounds) >= limit) return;
    for (uint32_t k = 0; k < r.boxCount; ++k) {
        if (lowestAlong(plane.normal, w.boxBounds[r.firstBox + k]) >= limit) continue;
        for (int corner = 0; corner < 8; ++corner) {
            const uint32_t node = (r.firstBox + k) * 8 + uint32_t(corner);
            if (dot(plane.normal, w.nodes[node]) < limit) fn(k, corner, node);
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
    std::vector<size_t>& start = s.floorStart;
    start.assign(n + 1, 0);
    w.workers.forChunks(n, kBodiesPerChunk, [&](size_t first, size_t last, int) {
        for (uint32_t b = uint32_t(first); b < last; ++b)
            for (const Plane& plane : planes)
                forNodesNearPlane(w, b, plane, [&](uint32_t, int, uint32_t) { ++start[b + 1]; });
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
            for (const Plane& plane : planes)
                forNodesNearPlane(w, b, plane, [&](uint32_t k, int corner, uint32_t node) {
                    s.all[at++] = planeContact(w, b, k, corner, node, plane.normal, plane.offset,
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
