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

// Heaps: the bodies joined by whole pairs, with the bodies whose bounding spheres touch theirs
// (phase 1's test on this substep's spheres), since those are pushed too. A heap of three or more
// spreads as a whole: each body's push (`spread`, at most 1 long; zero outside such heaps) leads
// away from its heap's centre of mass across gravity, as long as its distance from it over the
// heap's reach, so the heap expands about its centre and every two of its bodies separate at once.
// Pushed only by their pairs, the pushes inside a heap cancel, its rim is pushed into the bodies
// beyond it, and what those contacts make of it was the heap's speed (docs/LIMITS.md, known problem
// 1). Bodies that coincide (a heap with no reach) spread over a disc (a ball without gravity) by a
// direction and distance drawn from the body's index. Static and kinematic bodies belong to no
// heap.
void spreadHeaps(CollisionWorld& w, Vec3 up, std::vector<Vec3>& spread) {
    CollisionState& s = w.collision;
    const uint32_t n = uint32_t(w.bodies.size());
    spread.assign(n, Vec3{});
    if (s.wholePairs.empty()) return;
    std::vector<uint32_t>& heap = s.heapOf;
    heap.resize(n);
    for (uint32_t i = 0; i < n; ++i) heap[i] = i;
    auto find = [&](uint32_t i) {
        while (heap[i] != i) i = heap[i] = heap[heap[i]];
        return i;
    };
    auto join = [&](uint32_t a, uint32_t b) {
        const uint32_t x = find(a), y = find(b);
        if (x != y) heap[std::max(x, y)] = std::min(x, y); // the lowest index is the entry
    };
    auto movable = [&](uint32_t i) { return !w.bodies[i].immovable || w.bodies[i].asleep; };
    std::vector<uint32_t>& size = s.heapSize;
    size.assign(n, 0); // here: 1 for a body in a whole pair
    for (const OverlapPair& p : s.overlaps)
        if (p.whole && movable(p.a) && movable(p.b)) join(p.a, p.b), size[p.a] = size[p.b] = 1;
    std::vector<CandidatePair>& near = s.overlapScratch;
    if (!s.overlapNearFound) sphereTestPairs(w, near); // else trackOverlaps found them
    for (const CandidatePair& c : near)
        if ((size[c.a] || size[c.b]) && movable(c.a) && movable(c.b)) {
            join(c.a, c.b);
            for (const uint32_t i : {c.a, c.b})
                if (std::isnan(s.overlapCentre[i].x))
                    s.overlapCentre[i] = massWeightedMean(w.bodies[i], w.x);
        }
    auto acrossGravity = [&](Vec3 v) { return v - up * dot(v, up); };
    s.heapMass.assign(n, 0.0f);
    s.heapReach.assign(n, 0.0f);
    s.heapCentre.assign(n, Vec3{});
    size.assign(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
        heap[i] = find(i);
        if (heap[i] == i && std::isnan(s.overlapCentre[i].x)) continue; // in none
        const float m = w.bodies[i].mass;
        s.heapMass[heap[i]] += m;
        s.heapCentre[heap[i]] += s.overlapCentre[i] * m;
        ++size[heap[i]];
    }
    for (uint32_t i = 0; i < n; ++i)
        if (size[i] >= 3) s.heapCentre[i] = s.heapCentre[i] / s.heapMass[i];
    for (uint32_t i = 0; i < n; ++i)
        if (size[heap[i]] >= 3)
            s.heapReach[heap[i]] =
                maxNum(s.heapReach[heap[i]],
                       length(acrossGravity(s.overlapCentre[i] - s.heapCentre[heap[i]])));
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t h = heap[i];
        if (size[h] < 3) continue;
        if (s.heapReach[h] > 1e-3f * w.bodies[i].sphereRadius) {
            spread[i] = acrossGravity(s.overlapCentre[i] - s.heapCentre[h]) / s.heapReach[h];
            continue;
        }
        Vec3 d = acrossGravity(pairDirection(i, i));
        if (length(d) < 1e-3f) d = acrossGravity(pairDirection(i, i + 1));
        const float u = 0.5f + 0.5f * pairDirection(i + 1, i).y; // uniform in [0, 1]
        spread[i] = normalize(d) * (up == Vec3{} ? std::cbrt(u) : std::sqrt(u));
    }
}

} // namespace

void trackOverlaps(CollisionWorld& w) {
    CollisionState& s = w.collision;
    s.wholePairs.clear();
    s.overlapNearFound = false;
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
        sphereTestPairs(w, found);
        s.overlapNearFound = true; // spreadHeaps reads them: nothing moves in between
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

bool isWhole(const CollisionWorld& w, uint32_t a, uint32_t b) {
    const std::vector<uint64_t>& e = w.collision.wholePairs;
    return !e.empty() && std::binary_search(e.begin(), e.end(), pairKey(a, b));
}

const OverlapPair* recoveringPair(const CollisionWorld& w, uint32_t a, uint32_t b) {
    return w.collision.overlaps.empty() ? nullptr : findPair(w.collision.overlaps, a, b);
}

void settleOverlaps(CollisionWorld& w) {
    CollisionState& s = w.collision;
    if (s.overlaps.empty()) return;
    for (OverlapPair& p : s.overlaps) p.out = {}, p.depth = 0;
    for (const Contact& c : s.all) {
        if (!(c.distance < 0)) continue;
        const uint32_t other = c.hasB ? c.bodyB : kFloorBody;
        OverlapPair* p = findPair(s.overlaps, c.bodyA, other);
        if (!p) continue;
        // The contact pushes its body A away from B; the pair's way out is for p->a.
        p->out += (c.bodyA == p->a ? c.normal : -c.normal) * -c.distance;
        p->depth = maxNum(p->depth, -c.distance);
    }
    // A pair starts recovering with a contact deeper than the skin (a body placed resting on
    // another is no different from one that landed there), and goes on while it overlaps at
    // all, until its last move (pushPairsApart).
    for (OverlapPair& p : s.overlaps) {
        const float skin = minNum(skinOf(w, w.bodies[p.a]),
                                  p.b == kFloorBody ? INFINITY : skinOf(w, w.bodies[p.b]));
        if (p.depth > skin) p.confirmed = 1;
        p.deep = (p.deep && p.depth > 0) || p.depth > skin;
    }
    std::erase_if(s.overlaps, [](const OverlapPair& p) { return !p.deep && !p.whole; });
}

namespace {

// The recovery's move of a body, shortened so that its centre, which also travels at the
// body's velocity over the substep, goes no faster than `maxSpeed`, or than the velocity alone
// where that is faster (the move may then only slow it). The move keeps its direction: the
// largest share t in [0, 1] of it with |velocity dt + t move| within that bound. Moved by
// positions, a body amid a heap moved at the velocity its contacts gave it plus up to twice
// the recovery speed (a whole pair's push and a recovering pair's), and 200 spheres created at
// one spot moved their centres at up to 5.96-6.55 m/s between frames with velocities of
// 2.74-4.00 (docs/ALGORITHM.md, "Overlap recovery", "The centre's bound").
Vec3 boundCentreMove(Vec3 velocity, Vec3 move, float maxSpeed, float dt) {
    const Vec3 travel = velocity * dt;
    const float reach = maxNum(maxSpeed * dt, length(travel));
    const float mm = lengthSquared(move), tm = dot(travel, move);
    if (!(mm > 0)) return move;
    // |travel + t move|^2 = reach^2: its larger root (the smaller is <= 0, as |travel| <= reach).
    const float disc = maxNum(tm * tm - mm * (lengthSquared(travel) - reach * reach), 0.0f);
    const float t = (-tm + std::sqrt(disc)) / mm;
    return move * minNum(maxNum(t, 0.0f), 1.0f);
}

} // namespace

void pushPairsApart(CollisionWorld& w, float dt) {
    CollisionState& s = w.collision;
    if (s.overlaps.empty()) return;
    const size_t n = w.bodies.size();
    // Whole pairs and pairs overlapping by their contacts push each body separately, each
    // push bounded to the recovery speed: a body amid a heap has both kinds, and bounded
    // together, the contacts' pushes held back the whole pairs' (200 spheres at one spot still
    // had 432 whole pairs after 2.5 s instead of none after 1.7 s).
    for (int kind = 0; kind < 2; ++kind) {
        s.overlapPush[kind].assign(n, Vec3{});
        s.overlapWeight[kind].assign(n, 0.0f); // each body's largest pair weight
    }
    std::vector<Vec3>& velocity = s.overlapVelocity; // mean velocity, NaN: not yet needed
    std::vector<Vec3>& before = s.overlapVelocityBefore;
    velocity.assign(n, Vec3{NAN, NAN, NAN});
    before.resize(n);
    // A static or kinematic body (awake, not dynamic) is one of infinite mass: its partner
    // does all the moving; so is the floor.
    auto fixed = [&](uint32_t i) {
        return i == kFloorBody || (w.bodies[i].immovable && !w.bodies[i].asleep);
    };
    auto mass = [&](uint32_t i) { return i == kFloorBody ? INFINITY : w.bodies[i].mass; };
    // Nor is a body down into the floor (the floor would stop its lowest cells only, and the
    // dent, restored against the floor, would throw it up): one within a substep's recovery of
    // it is fixed for the pairs that push it down, and its partners do that moving. Left to
    // the mass split, each sphere at the bottom of a heap kept half of every push from above,
    // and the push from its neighbours beside it was bounded together with those and lost.
    const float step = w.settings.overlapRecoverySpeed * dt;
    auto onFloor = [&](uint32_t i) {
        const CollisionBody& r = w.bodies[i];
        return w.settings.floor && r.bounds.lo.y < w.settings.floorHeight + skinOf(w, r) + step;
    };
    // The pair's push: along d, with its weight among the body's pairs, for `part` of a
    // substep's recovery (less when it has less overlap left).
    auto pushPair = [&](int kind, uint32_t a, uint32_t b, Vec3 d, float weight, float part) {
        std::vector<Vec3>& push = s.overlapPush[kind];
        std::vector<float>& heaviest = s.overlapWeight[kind];
        // Split by mass as the contacts do: the lighter body moves more.
        const bool fixedA = fixed(a) || (d.y < 0 && onFloor(a));
        const bool fixedB = fixed(b) || (d.y > 0 && onFloor(b));
        if (fixedA && fixedB) return;
        const float share = part * (fixedA   ? 0.0f
                                    : fixedB ? weight
                                             : weight * mass(b) / (mass(a) + mass(b)));
        push[a] += d * share;
        heaviest[a] = maxNum(heaviest[a], weight);
        if (b == kFloorBody) return;
        push[b] -= d * (part * weight - share);
        heaviest[b] = maxNum(heaviest[b], weight);
    };
    const Vec3 up = normalize(-w.settings.gravity); // zero without gravity
    auto acrossGravity = [&](Vec3 v) { return v - up * dot(v, up); };
    for (const OverlapPair& p : s.overlaps) {
        const uint32_t a = p.a, b = p.b;
        if (!p.whole) {
            // Overlapping by its contacts in the last substep: apart along the way out of
            // their overlap, no further than its depth, while the contacts keep all of it and
            // only stop the bodies sinking further (margins.h, toleratedOverlap). Moved by
            // particles instead, the overlap became a dent, shape matching restored it with
            // velocity and the pair left at 1.5 m/s each where it should have stopped.
            const float len = length(p.out);
            if (p.deep && len > 0 && std::isfinite(len))
                pushPair(1, a, b, p.out / len, 1.0f, minNum(1.0f, p.depth / step));
            continue;
        }
        const CollisionBody& A = w.bodies[a];
        const CollisionBody& B = w.bodies[b];
        Vec3 d = s.overlapCentre[a] - s.overlapCentre[b];
        const float len = length(d);
        const float scale = minNum(A.sphereRadius, B.sphereRadius);
        d = len > 1e-4f * scale ? d / len : pairDirection(a, b);
        // The pair moves as one but for separating along the line of centres: all its other
        // relative velocity is removed (an inelastic impulse that sticks), so that one resting
        // on the other under gravity neither falls through it (there are no object contacts)
        // nor slides off it. With only the approach along the line removed (a line that means
        // little for bodies this deep in each other), a heap of whole pairs was a slope without
        // friction that carried the bodies riding it off at up to 4 m/s.
        for (const uint32_t i : {a, b})
            if (std::isnan(velocity[i].x))
                before[i] = velocity[i] = massWeightedMean(w.bodies[i], w.v);
        const Vec3 relative = velocity[a] - velocity[b];
        const Vec3 removed = relative - d * maxNum(dot(relative, d), 0.0f);
        const bool fixedA = fixed(a), fixedB = fixed(b);
        if (!fixedA && !fixedB) {
            const Vec3 j = removed / (1.0f / A.mass + 1.0f / B.mass);
            velocity[a] -= j / A.mass;
            velocity[b] += j / B.mass;
        } else if (fixedA != fixedB) {
            if (fixedB) velocity[a] -= removed;
            if (fixedA) velocity[b] += removed;
        }
        // Under gravity the pair is pushed apart across it, along the line of centres' part
        // square to gravity (a pair one exactly above the other: its own direction's part).
        // Pushed along the line itself, 200 bodies created at one spot were stacked into a heap
        // 3-4 m high, which they rolled down at up to 5.8 m/s once apart; spread across the
        // floor none is faster than 4.7 (docs/ALGORITHM.md, "Overlap recovery").
        Vec3 across = d;
        if (up != Vec3{}) {
            across = acrossGravity(d);
            if (length(across) < 1e-3f) across = acrossGravity(pairDirection(a, b));
            across = normalize(across);
        }
        // Deeper pairs push harder (a body amid many partners is moved by the sum, bounded):
        // the weight is the bounding spheres' overlap as a share of their radii's sum.
        const float radii = A.sphereRadius + B.sphereRadius;
        pushPair(0, a, b, across,
                 radii > 0 ? minNum(maxNum(1.0f - len / radii, 0.05f), 1.0f) : 1.0f, 1.0f);
    }
    std::vector<Vec3>& spread = s.heapSpread;
    spreadHeaps(w, up, spread);
    for (uint32_t b = 0; b < n; ++b) {
        CollisionBody& r = w.bodies[b];
        if (r.immovable && !r.asleep) continue; // a collider is not pushed
        if (!std::isnan(velocity[b].x)) {       // in a whole pair
            const Vec3 dv = velocity[b] - before[b];
            for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i)
                w.v[i] += dv;
        }
        // A body with one partner moves its mass share of the speed; the sum over many
        // partners is bounded to the same.
        Vec3 move{};
        const bool floored = onFloor(b);
        for (int kind = 0; kind < 2; ++kind) {
            Vec3 push = s.overlapPush[kind][b];
            if (floored) push.y = maxNum(push.y, 0.0f);
            const float len = length(push);
            const Vec3 heapPush = kind == 0 ? spread[b] : Vec3{};
            // Outside a heap, the arithmetic of before heaps, so such bodies move bit for bit
            // as they did (the paper scenes' hashes hold).
            if (heapPush.x == 0 && heapPush.y == 0 && heapPush.z == 0) {
                if (len > 0) move += push * (step / maxNum(s.overlapWeight[kind][b], len));
                continue;
            }
            // A heap's spreading joins its whole pairs' pushes, within their bound.
            if (len > 0) push *= 1.0f / maxNum(s.overlapWeight[kind][b], len);
            push += heapPush;
            if (floored) push.y = maxNum(push.y, 0.0f);
            move += push * (step / maxNum(1.0f, length(push)));
        }
        if (move.x == 0 && move.y == 0 && move.z == 0) continue; // none, or balanced
        if (w.settings.floor && move.y < 0 &&
            r.bounds.lo.y + move.y < w.settings.floorHeight + skinOf(w, r))
            move.y = 0;
        if (w.settings.overlapRecoveryMaxSpeed > 0) {
            const Vec3 v = std::isnan(velocity[b].x) ? massWeightedMean(r, w.v) : velocity[b];
            move = boundCentreMove(v, move, w.settings.overlapRecoveryMaxSpeed, dt);
            if (move.x == 0 && move.y == 0 && move.z == 0) continue;
        }
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
    // A pair with no more overlap than one substep's move has made its last: from here on it
    // collides as any other, with nothing left for the contacts to push out.
    std::erase_if(s.overlaps,
                  [&](const OverlapPair& p) { return p.deep && !p.whole && p.depth <= step; });
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
