// floor_contacts: box nodes within the speculative margin of the floor (collision/pipeline.h).
#include "collision/margins.h"
#include "collision/pipeline.h"

#include <algorithm>
#include <cmath>

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
    makeContactPoint(r.lattice->cellParticles[box.cell].data(), r.firstParticle,
                     box.nodeLocal(corner), w.invMass, c.a, c.invMassA);
    return c;
}

// Calls fn(k, corner, node) for body b's box nodes within the floor's margin (what the body can
// travel in a substep, plus its skin): its k-th box's corner `corner`, world-wide `node`.
template <class F>
void forNodesNearFloor(const CollisionWorld& w, uint32_t b, F&& fn) {
    const CollisionBody& r = w.bodies[b];
    if (r.immovable) return; // contacts do not move it
    const float skin = skinOf(w, r) + w.substep * r.maxSpeed;
    const float limit = w.settings.floorHeight + skin;
    if (r.bounds.lo.y >= limit) return;
    for (uint32_t k = 0; k < r.boxCount; ++k) {
        if (w.boxBounds[r.firstBox + k].lo.y >= limit) continue;
        for (int corner = 0; corner < 8; ++corner) {
            const uint32_t node = (r.firstBox + k) * 8 + uint32_t(corner);
            if (w.nodes[node].y < limit) fn(k, corner, node);
        }
    }
}

// The same for the plane dot(n, p) = offset: body b's nodes within the margin of its solid side.
template <class F>
void forNodesNearPlane(const CollisionWorld& w, uint32_t b, const Plane& plane, F&& fn) {
    const CollisionBody& r = w.bodies[b];
    if (r.immovable) return;
    const float skin = skinOf(w, r) + w.substep * r.maxSpeed;
    const float limit = plane.offset + skin;
    auto lowest = [&](const Aabb& box) { // the box's corner farthest along -n
        const Vec3 n = plane.normal;
        return dot(n, Vec3{n.x >= 0 ? box.lo.x : box.hi.x, n.y >= 0 ? box.lo.y : box.hi.y,
                           n.z >= 0 ? box.lo.z : box.hi.z});
    };
    if (lowest(r.bounds) >= limit) return;
    for (uint32_t k = 0; k < r.boxCount; ++k) {
        if (lowest(w.boxBounds[r.firstBox + k]) >= limit) continue;
        for (int corner = 0; corner < 8; ++corner) {
            const uint32_t node = (r.firstBox + k) * 8 + uint32_t(corner);
            if (dot(plane.normal, w.nodes[node]) < limit) fn(k, corner, node);
        }
    }
}

// Appends the plane colliders' contacts after the floor's, body by body, plane by plane in
// each (counted, then made at their places, as the floor's).
void findPlaneContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    const uint32_t n = uint32_t(w.bodies.size());
    constexpr size_t kBodiesPerChunk = 8;
    std::vector<size_t> start(n + 1, 0);
    w.workers.forChunks(n, kBodiesPerChunk, [&](size_t first, size_t last, int) {
        for (uint32_t b = uint32_t(first); b < last; ++b)
            for (const Plane& plane : w.planes)
                forNodesNearPlane(w, b, plane, [&](uint32_t, int, uint32_t) { ++start[b + 1]; });
    });
    start[0] = s.all.size();
    for (uint32_t b = 0; b < n; ++b) start[b + 1] += start[b];
    if (start[n] == start[0]) return;
    if (s.all.capacity() < start[n]) s.all.reserve(start[n] + start[n] / 2);
    s.all.resize(start[n]);
    w.workers.forChunks(n, kBodiesPerChunk, [&](size_t first, size_t last, int) {
        for (uint32_t b = uint32_t(first); b < last; ++b) {
            size_t at = start[b];
            for (const Plane& plane : w.planes)
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
    w.profile.floorContacts = 0;
    if (!w.settings.floor) {
        if (!w.planes.empty()) findPlaneContacts(w);
        w.profile.floorContacts = int(s.all.size() - s.objectCount);
        return;
    }
    // Counted per body, then made at their places after the object contacts, body by body:
    // the same order for any thread count, and each contact written once, on the thread that
    // makes it (contacts are large: copying them from per-thread lists into place cost more
    // than making them, measured on alphabets).
    const uint32_t n = uint32_t(w.bodies.size());
    constexpr size_t kBodiesPerChunk = 8;
    std::vector<size_t>& start = s.floorStart;
    start.assign(n + 1, 0);
    w.workers.forChunks(n, kBodiesPerChunk, [&](size_t first, size_t last, int) {
        for (uint32_t b = uint32_t(first); b < last; ++b)
            forNodesNearFloor(w, b, [&](uint32_t, int, uint32_t) { ++start[b + 1]; });
    });
    start[0] = s.objectCount;
    for (uint32_t b = 0; b < n; ++b) start[b + 1] += start[b];
    // With room to grow: a resize past the capacity allocates the exact size when it adds
    // more than the list holds, and the count changes every substep.
    if (s.all.capacity() < start[n]) s.all.reserve(start[n] + start[n] / 2);
    s.all.resize(start[n]); // the new contacts are left unwritten (ContactList): written below
    const float floorY = w.settings.floorHeight;
    w.workers.forChunks(n, kBodiesPerChunk, [&](size_t first, size_t last, int) {
        for (uint32_t b = uint32_t(first); b < last; ++b) {
            size_t at = start[b];
            forNodesNearFloor(w, b, [&](uint32_t k, int corner, uint32_t node) {
                s.all[at++] = planeContact(w, b, k, corner, node, {0, 1, 0}, floorY,
                                           w.nodes[node].y - floorY);
            });
        }
    });
    if (!w.planes.empty()) findPlaneContacts(w);
    w.profile.floorContacts = int(s.all.size() - s.objectCount);
}

} // namespace ffd::detail
