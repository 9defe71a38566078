#include "collision/overlap_recovery.h"

#include "collision/margins.h"
#include "collision/pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>

namespace ffd::detail {

namespace {

uint64_t pairKey(uint32_t a, uint32_t b) {
    return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

uint64_t keyOf(const OverlapPair& p) {
    return (uint64_t(p.a) << 32) | p.b;
}

// The remembered pair of bodies a and b (any order), or null.
template <class Pairs>
auto findPair(Pairs& overlaps, uint32_t a, uint32_t b) {
    const uint64_t key = pairKey(a, b);
    auto it = std::lower_bound(overlaps.begin(), overlaps.end(), key,
                               [](const OverlapPair& p, uint64_t k) { return keyOf(p) < k; });
    return it != overlaps.end() && keyOf(*it) == key ? &*it : nullptr;
}

// Whether `point` lies within `grow` of the bounds of one of the body's deformed lattice cells
// (interior ones too: the cell boxes cover only the surface, and a centre lies in the interior).
bool insideCells(const CollisionWorld& w, const CollisionBody& r, Vec3 point, float grow) {
    if (!r.bounds.contains(point, r.cellSize + grow)) return false;
    const Lattice& L = *r.lattice;
    const Vec3* x = w.x.data() + r.firstParticle;
    for (const std::array<uint32_t, 8>& corners : L.cellParticles) {
        Aabb cell;
        for (const uint32_t p : corners) cell.add(x[p]);
        if (cell.contains(point, grow)) return true;
    }
    return false;
}

// A unit direction that depends only on the pair, for centres that coincide.
Vec3 pairDirection(uint32_t a, uint32_t b) {
    uint64_t h = (uint64_t(a) << 32 | b) + 0x9E3779B97F4A7C15ull; // splitmix64
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
    h ^= h >> 31;
    const float z = 1.0f - 2.0f * float(h & 0xFFFFFF) / float(0x1000000);
    const float phi = 6.2831853f * float((h >> 24) & 0xFFFFFF) / float(0x1000000);
    const float r = std::sqrt(maxNum(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), z, r * std::sin(phi)};
}

} // namespace

void trackOverlaps(CollisionWorld& w) {
    CollisionState& s = w.collision;
    s.wholePairs.clear();
    bool placed = false;
    for (const CollisionBody& r : w.bodies) placed |= r.placed;
    if (!placed && s.overlaps.empty()) return;
    if (w.settings.overlapRecoverySpeed == 0) {
        s.overlaps.clear();
        for (CollisionBody& r : w.bodies) r.placed = false;
        return;
    }
    computeSpheres(w);
    if (placed) {
        std::vector<CandidatePair>& found = s.overlapScratch;
        if (int(w.bodies.size()) > w.settings.sweepThreshold)
            sphereTestSweep(w, found);
        else
            sphereTestAllPairs(w, found);
        std::vector<OverlapPair>& added = s.overlapAdded;
        added.clear();
        for (const CandidatePair& p : found)
            if (w.bodies[p.a].placed || w.bodies[p.b].placed) added.push_back({p.a, p.b});
        for (uint32_t b = 0; b < w.bodies.size(); ++b) {
            const CollisionBody& r = w.bodies[b];
            bool below = w.settings.floor && r.placed &&
                         r.bounds.lo.y < w.settings.floorHeight + skinOf(w, r);
            // The planes (World::addPlane) share the floor's pair: their contacts are its kind.
            for (const Plane& plane : w.planes) {
                if (below || !r.placed || r.immovable) break;
                below = lowestAlong(plane.normal, r.bounds) < plane.offset + skinOf(w, r);
            }
            if (below) added.push_back({b, kFloorBody});
        }
        auto byKey = [](const OverlapPair& x, const OverlapPair& y) { return keyOf(x) < keyOf(y); };
        std::sort(added.begin(), added.end(), byKey);
        // Pairs remembered already keep their state (set_union takes the first range's).
        std::vector<OverlapPair>& merged = s.overlapMerged;
        merged.clear();
        std::set_union(s.overlaps.begin(), s.overlaps.end(), added.begin(), added.end(),
                       std::back_inserter(merged), byKey);
        s.overlaps.swap(merged);
        for (CollisionBody& r : w.bodies) r.placed = false;
    }
    // Centres of mass of the bodies in object pairs (NaN: not needed).
    s.overlapCentre.assign(w.bodies.size(), Vec3{NAN, NAN, NAN});
    for (OverlapPair& p : s.overlaps) {
        p.whole = 0;
        if (p.b == kFloorBody) continue;
        for (uint32_t i : {p.a, p.b})
            if (std::isnan(s.overlapCentre[i].x))
                s.overlapCentre[i] = massWeightedMean(w.bodies[i], w.x);
        const CollisionBody& A = w.bodies[p.a];
        const CollisionBody& B = w.bodies[p.b];
        // A centre inside the other's cells: the pair does overlap deeply. Once it has
        // overlapped, it stays whole until neither centre is within a cell of the other's
        // cells, so that the object contacts take over shallow overlap only.
        const Vec3 ca = s.overlapCentre[p.a], cb = s.overlapCentre[p.b];
        if (insideCells(w, B, ca, 0) || insideCells(w, A, cb, 0))
            p.confirmed = 1, p.whole = 1;
        else if (p.confirmed)
            p.whole = insideCells(w, B, ca, B.cellSize) || insideCells(w, A, cb, A.cellSize);
        if (p.whole) s.wholePairs.push_back(keyOf(p)); // sorted, as the pairs are
    }
}

bool isRecovering(const CollisionWorld& w, uint32_t a, uint32_t b) {
    return !w.collision.overlaps.empty() && findPair(w.collision.overlaps, a, b) != nullptr;
}

bool isWhole(const CollisionWorld& w, uint32_t a, uint32_t b) {
    const std::vector<uint64_t>& e = w.collision.wholePairs;
    return !e.empty() && std::binary_search(e.begin(), e.end(), pairKey(a, b));
}

void settleOverlaps(CollisionWorld& w) {
    CollisionState& s = w.collision;
    if (s.overlaps.empty()) return;
    for (OverlapPair& p : s.overlaps) p.deep = 0;
    for (const Contact& c : s.all) {
        const uint32_t other = c.hasB ? c.bodyB : kFloorBody;
        const CollisionBody& owner = w.bodies[c.hasB ? c.bodyB : c.bodyA];
        if (c.distance >= -skinOf(w, owner)) continue;
        if (OverlapPair* p = findPair(s.overlaps, c.bodyA, other)) p->deep = p->confirmed = 1;
    }
    std::erase_if(s.overlaps, [](const OverlapPair& p) { return !p.deep && !p.whole; });
}

void pushWholePairsApart(CollisionWorld& w, float dt) {
    CollisionState& s = w.collision;
    if (s.wholePairs.empty()) return;
    const size_t n = w.bodies.size();
    std::vector<Vec3>& push = s.overlapPush;
    std::vector<Vec3>& velocity = s.overlapVelocity; // mean velocity, NaN: not yet needed
    std::vector<Vec3>& before = s.overlapVelocityBefore;
    std::vector<float>& heaviest = s.overlapWeight; // each body's largest pair weight
    push.assign(n, Vec3{});
    velocity.assign(n, Vec3{NAN, NAN, NAN});
    before.resize(n);
    heaviest.assign(n, 0.0f);
    for (const uint64_t key : s.wholePairs) {
        const uint32_t a = uint32_t(key >> 32), b = uint32_t(key);
        const CollisionBody& A = w.bodies[a];
        const CollisionBody& B = w.bodies[b];
        Vec3 d = s.overlapCentre[a] - s.overlapCentre[b];
        const float len = length(d);
        const float scale = minNum(A.sphereRadius, B.sphereRadius);
        d = len > 1e-4f * scale ? d / len : pairDirection(a, b);
        // The pair neither approaches along the line of centres (one resting on the other
        // under gravity would otherwise fall through it: there are no object contacts).
        for (const uint32_t i : {a, b})
            if (std::isnan(velocity[i].x))
                before[i] = velocity[i] = massWeightedMean(w.bodies[i], w.v);
        const float approach = dot(velocity[a] - velocity[b], d);
        // A static or kinematic body (awake, not dynamic) is one of infinite mass: its partner
        // does all the moving.
        const bool fixedA = A.immovable && !A.asleep, fixedB = B.immovable && !B.asleep;
        if (approach < 0 && !fixedA && !fixedB) {
            const float j = -approach / (1.0f / A.mass + 1.0f / B.mass);
            velocity[a] += d * (j / A.mass);
            velocity[b] -= d * (j / B.mass);
        } else if (approach < 0 && fixedA != fixedB) {
            if (fixedB) velocity[a] -= d * approach;
            if (fixedA) velocity[b] += d * approach;
        }
        // Deeper pairs push harder (a body amid many partners is moved by the sum, bounded):
        // the weight is the bounding spheres' overlap as a share of their radii's sum. Split by
        // mass as the contacts do: the lighter body moves more.
        const float radii = A.sphereRadius + B.sphereRadius;
        const float weight = radii > 0 ? minNum(maxNum(1.0f - len / radii, 0.05f), 1.0f) : 1.0f;
        const float share = fixedA ? 0.0f : fixedB ? weight : weight * B.mass / (A.mass + B.mass);
        push[a] += d * share;
        push[b] -= d * (weight - share);
        heaviest[a] = maxNum(heaviest[a], weight);
        heaviest[b] = maxNum(heaviest[b], weight);
    }
    const float step = w.settings.overlapRecoverySpeed * dt;
    for (uint32_t b = 0; b < n; ++b) {
        if (std::isnan(velocity[b].x)) continue; // in no whole pair
        CollisionBody& r = w.bodies[b];
        if (r.immovable && !r.asleep) continue; // a collider is not pushed
        const Vec3 dv = velocity[b] - before[b];
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i) w.v[i] += dv;
        const float len = length(push[b]);
        if (len == 0) continue; // partners balanced
        // A body with one partner moves its mass share of the speed; the sum over many
        // partners is bounded to the same.
        Vec3 move = push[b] * (step / maxNum(heaviest[b], len));
        // Not down into the floor: the floor would stop the body's lowest cells only, and the
        // dent, restored against the floor, would throw the body up.
        if (w.settings.floor && move.y < 0 &&
            r.bounds.lo.y + move.y < w.settings.floorHeight + skinOf(w, r))
            move.y = 0;
        // Everything the contacts are found on moves with the particles (the nodes are
        // trilinear blends of them), so contacts see the moved body. Overlap with the floor or
        // a third body that the move makes is pre-existing for the response and projected
        // away without velocity (collision/contact.h, step 0).
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i)
            w.x[i] += move;
        for (uint32_t k = r.firstBox; k < r.firstBox + r.boxCount; ++k) {
            for (uint32_t m = 0; m < 8; ++m) w.nodes[size_t(k) * 8 + m] += move;
            w.boxBounds[k].lo += move, w.boxBounds[k].hi += move;
        }
        r.bounds.lo += move, r.bounds.hi += move;
        r.sphereCentre += move;
    }
}

void forgetBody(CollisionWorld& w, uint32_t dense) {
    CollisionState& s = w.collision;
    s.wholePairs.clear();
    std::erase_if(s.overlaps, [&](const OverlapPair& p) { return p.a == dense || p.b == dense; });
    for (OverlapPair& p : s.overlaps) {
        if (p.a > dense) --p.a;
        if (p.b > dense && p.b != kFloorBody) --p.b;
    }
}

} // namespace ffd::detail
