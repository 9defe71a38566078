// object_contacts, phases 2-3: the candidate bodies' boxes culled, their nodes and centres
// hashed, the box pairs such a sample names tested once each (separating axes, one normal, at most
// four points), the contacts in canonical order (collision/pipeline.h). Reference: Jeon, Choi,
// Hong, "Enhanced FFD-AABB Collision Algorithm for Deformable Objects", 2012; Jung, Hong, Choi,
// "Collision Handling for Free-Form Deformation Embedded Surface", IET Image Processing 5(4), 2011;
// Teschner et al., VMV 2003 (spatial hashing).
#include "collision/margins.h"
#include "collision/overlap_recovery.h"
#include "collision/pipeline.h"
#include "util/unwritten.h"

#include <algorithm>
#include <cmath>

namespace ffd::detail {

namespace {

// A box pair's reference face is on its second box only when that overlaps less than the
// first's by more than this share of the smaller skin (narrow_phase.h boxPairManifold).
constexpr float kReferenceTolerance = 0.1f;

// The reach every hash query covers beyond its box (SpatialHash::begin's allowance): the largest
// reach of the bodies hashed in the substep, so that every node is stored in its own cell only
// and a body's queries grow by its partners' largest reach, no further (forEachNearAll), but
// at least this share of the hash cell and at most a whole cell (past it, the nodes of the
// fastest bodies are stored in the cells of their cubes shrunk by the allowance). Below a
// quarter the allowance costs nothing: no node's reach exceeds it and every query grows by its
// partners' reach alone. Measured against a quarter of a cell always, interleaved frame by
// frame (docs/BENCHMARKS.md, "Phase 2's allowance follows the reach"): while the piles land
// (frames 0-60) object_contacts takes 0.34-0.40 of its time on the teapots, 0.46-0.47 on the
// dragons and 0.72 on the alphabets, and over the benchmark's frames 0.76-0.79, 0.58-0.68 and
// 0.98; the results are the same.
constexpr float kLeastAllowance = 0.25f, kMostAllowance = 1.0f;

// No box pair (both halves the same box).
constexpr uint64_t kNoKey = ~uint64_t(0);

// Marks a hash item that stands for its box's centre rather than one of its nodes.
constexpr uint32_t kCentreItem = 0x80000000u;

// Local coordinates, in the cell of box `box` of body B, of the `count` points q (on or near
// the box): the box's trilinear map inverted by Newton, started from its linearised map (close
// for all but thin, strongly deformed boxes), kept within the box. Four points at a time, in
// vector lanes (invertTrilinear4): a manifold's points all lie on its reference box.
void locateInBox(const CollisionWorld& w, const CollisionBody& B, uint32_t box,
                 const BoxPlanes& planes, const Vec3* q, int count, Vec3* local) {
    if (count == 0) return;
    const Lattice& LB = *B.lattice;
    const CellBox& boxB = LB.boxes[box - B.firstBox];
    const auto& cornersB = LB.cellParticles[boxB.cell];
    Vec3 corners[8];
    for (int k = 0; k < 8; ++k) corners[k] = w.x[B.firstParticle + cornersB[k]];
    for (int k = 0; k < count; ++k) {
        Vec3 abc = max(Vec3{0, 0, 0}, min(boxParameters(planes, q[k]), Vec3{1, 1, 1}));
        if (!isFinite(abc)) abc = {0.5f, 0.5f, 0.5f};
        local[k] = boxB.lo + mul(boxB.hi - boxB.lo, abc);
    }
    for (int k = 0; k < count; k += 4)
        invertTrilinear4(corners, q + k, local + k, std::min(4, count - k), 3);
    for (int k = 0; k < count; ++k) {
        if (!isFinite(local[k])) local[k] = (boxB.lo + boxB.hi) * 0.5f;
        local[k] = max(boxB.lo, min(local[k], boxB.hi));
    }
}

// A contact between body A's point at `localA` in the cell of box `boxA` and body B's point at
// `localB` in the cell of box `box`, pushing A along `normal`; `distance` is the signed
// distance to B's face plane.
Contact makeObjectContact(const CollisionWorld& w, uint32_t bodyA, uint32_t boxA, Vec3 localA,
                          uint32_t bodyB, uint32_t box, Vec3 localB, Vec3 normal, float distance) {
    const CollisionBody& A = w.bodies[bodyA];
    const CollisionBody& B = w.bodies[bodyB];
    Contact c;
    c.bodyA = bodyA;
    c.bodyB = bodyB;
    c.boxB = box;
    c.hasB = true;
    c.normal = normal;
    c.distance = distance;
    setPushOut(w, B, bodyA, bodyB, c);
    c.friction = combineFriction(A, B);
    c.restitution = maxNum(A.restitution, B.restitution);
    c.rigidity = 0.5f * (A.contactRigidity + B.contactRigidity);
    const std::span<const BoxParticles> boxes = w.collision.boxParticles;
    makeContactPoint(boxA, localA, boxes, w.invMass, c.a, c.invMassA);
    makeContactPoint(box, localB, boxes, w.invMass, c.b, c.invMassB);
    return c;
}

// emitPairs' keys are sorted by their first box, so each pair's second box comes from anywhere
// in the world: its nodes, planes and particles' indices are prefetched this many pairs ahead.
// Measured interleaved frame by frame (docs/BENCHMARKS.md): `object_contacts` 0.976-0.978 of
// its time on alphabets_x10, whose boxes' data no cache holds, 0.964 on the teapots, 0.973-1.003
// on the alphabets, 0.988-0.995 on the spheres, 1.00 on the dragons.
constexpr size_t kPrefetchPairs = 4;

// Tests the box pairs `keys` (sorted), each once: its manifold's points become contacts, and
// what the pair may claim (from the last substep's claims) a claim, appended to `contacts` and
// `claims`; returns how many pairs gave a contact.
int emitPairs(const CollisionWorld& w, std::span<const uint64_t> keys, ContactList& contacts,
              std::vector<BoxPairClaim>& claims) {
    const CollisionState& s = w.collision;
    int touching = 0;
    if (keys.empty()) return touching;
    // Into the last substep's claims, sorted like keys.
    size_t last =
        size_t(std::lower_bound(s.claims.begin(), s.claims.end(), keys.front(),
                                [](const BoxPairClaim& c, uint64_t k) { return c.key < k; }) -
               s.claims.begin());
    for (size_t at = 0; at < keys.size(); ++at) {
        const uint64_t key = keys[at];
        if (at + kPrefetchPairs < keys.size()) {
            const uint32_t ahead = uint32_t(keys[at + kPrefetchPairs]);
            const char* nodes = reinterpret_cast<const char*>(&w.nodes[size_t(ahead) * 8]);
            __builtin_prefetch(nodes);
            __builtin_prefetch(nodes + 64);
            const char* planes = reinterpret_cast<const char*>(&s.planes[ahead]);
            __builtin_prefetch(planes);
            __builtin_prefetch(planes + 64);
            __builtin_prefetch(planes + 128);
            __builtin_prefetch(&s.boxParticles[ahead]);
        }
        const uint32_t box[2] = {uint32_t(key >> 32), uint32_t(key)};
        uint32_t body[2];
        Unwritten<BoxView, 2> view; // every field written below
        for (int k = 0; k < 2; ++k) {
            body[k] = s.boxBody[box[k]];
            const CollisionBody& r = w.bodies[body[k]];
            const CellBox& cb = r.lattice->boxes[box[k] - r.firstBox];
            view[k].nodes = &w.nodes[size_t(box[k]) * 8];
            for (int j = 0; j < 8; ++j) view[k].local[j] = cb.nodeLocal(j);
            view[k].planes = &s.planes[box[k]];
            view[k].outsideFaces = cb.outsideFaces;
        }
        const CollisionBody& P = w.bodies[body[0]];
        const CollisionBody& Q = w.bodies[body[1]];
        const float margin = maxNum(marginOf(w, P, Q), marginOf(w, Q, P));
        const float tolerance = kReferenceTolerance * minNum(s.skin[body[0]], s.skin[body[1]]);
        const BoxPairManifold m = boxPairManifold(view[0], view[1], margin, tolerance);
        if (m.reference < 0) continue;
        const int ref = m.reference, inc = 1 - m.reference;
        const size_t first = contacts.size();
        float deepest = 0, closing = 0;
        // A point farther from the reference face than it can close in the substep is no
        // contact (speculativeReach): its constraint would stay inactive in every phase.
        // Bounded from the cells' particles, so that the inverse map of B's point is not needed
        // for the points left out: A's point blended exactly, B's at most its cell's fastest
        // particle along the point's normal (the manifold's, or a side point's side).
        auto refSpeedAlong = [&](Vec3 normal) {
            float fastest = -INFINITY;
            for (const uint32_t i : s.boxParticles[box[ref]])
                fastest = maxNum(fastest, dot(w.v[i], normal));
            return fastest;
        };
        const float refSpeed = refSpeedAlong(m.normal);
        const float skin = s.skin[body[ref]];
        // Which points become contacts (B's points are located together afterwards), and for
        // those left out, their approach.
        bool kept[8];
        float approachOf[8];
        Unwritten<Vec3, 8> va, onFace, localB; // each read only where written below
        int keptCount = 0;
        for (int k = 0; k < m.count; ++k) {
            const ManifoldPoint& pt = m.point[k];
            // A's point, as its contact will have it.
            va[k] = blend(ContactPoint{box[inc], pt.local}, s.boxParticles, w.v);
            kept[k] = true;
            if (pt.distance > skin) {
                const float speed = pt.normal == m.normal ? refSpeed : refSpeedAlong(pt.normal);
                approachOf[k] = maxNum(0.0f, speed - dot(va[k], pt.normal));
                kept[k] = !(pt.distance > speculativeReach(skin, approachOf[k], w.substep));
            }
            if (kept[k]) onFace[keptCount++] = pt.position - pt.normal * pt.distance;
        }
        const CollisionBody& R = w.bodies[body[ref]];
        locateInBox(w, R, box[ref], *view[ref].planes, onFace.data(), keptCount, localB.data());
        for (int k = 0, located = 0; k < m.count; ++k) {
            if (!kept[k]) {
                closing = maxNum(closing, approachOf[k]);
                continue;
            }
            const ManifoldPoint& pt = m.point[k];
            Contact c = makeObjectContact(w, body[inc], box[inc], pt.local, body[ref], box[ref],
                                          localB[located++], pt.normal, pt.distance);
            c.nodeA = box[inc] * 8 + uint32_t(k);
            deepest = maxNum(deepest, -pt.distance);
            closing = maxNum(closing, -dot(va[k] - blend(c.b, s.boxParticles, w.v), c.normal));
            contacts.push_back(c);
        }
        // What the pair may claim: all its overlap, unless its boxes overlap least across
        // a face into a neighbouring cell; then that overlap, or what it claimed in the last
        // substep plus how much deeper its deepest point has got since, whichever is more.
        // A box grazing such a face can lie a cell deep along the normal: claimed at once,
        // that depth threw resting letters into the air, while a pair that deepens under a
        // load keeps up with it (docs/ALGORITHM.md, section 5). The deepening counts only as
        // far as the bodies close at the pair's points in a substep: the manifold's depth
        // jumps when its reference face or its points change (a pair at rest found 8 cm
        // deeper from one substep to the next), and claimed, such a jump is the same throw.
        while (last < s.claims.size() && s.claims[last].key < key) ++last;
        const BoxPairClaim* before =
            last < s.claims.size() && s.claims[last].key == key ? &s.claims[last] : nullptr;
        const float deepened =
            minNum(maxNum(0.0f, deepest - (before ? before->deepest : 0.0f)), closing * w.substep);
        const float grown = before ? before->claimed + deepened : 0.0f;
        const float allowed = m.depthBound < INFINITY ? maxNum(m.depthBound, grown) : INFINITY;
        claims.push_back({key, minNum(deepest, allowed), deepest});
        // The rest of each point's overlap is kept for later substeps.
        for (size_t n = first; n < contacts.size(); ++n)
            contacts[n].tolerated =
                minNum(contacts[n].tolerated, minNum(0.0f, contacts[n].distance + allowed));
        touching += contacts.size() > first;
    }
    return touching;
}

// The bits a box index needs (at least 1).
int boxIndexBits(uint32_t boxes) {
    int bits = 1;
    while (bits < 32 && (uint64_t(1) << bits) < boxes) ++bits;
    return bits;
}

// Sorts `items` by keyOf(item), a number below 2^keyBits, least significant digit first (11
// bits a pass), keeping the order of equal keys: what std::sort gives for unique keys.
template <class T, class KeyOf>
void radixSort(std::vector<T>& items, std::vector<T>& scratch, int keyBits, KeyOf keyOf) {
    constexpr int kDigit = 11;
    constexpr size_t kBuckets = size_t(1) << kDigit;
    scratch.resize(items.size());
    uint32_t count[kBuckets];
    for (int shift = 0; shift < keyBits; shift += kDigit) {
        std::fill(std::begin(count), std::end(count), 0u);
        for (const T& item : items) ++count[(keyOf(item) >> shift) & (kBuckets - 1)];
        uint32_t at = 0;
        for (uint32_t& c : count) {
            const uint32_t n = c;
            c = at;
            at += n;
        }
        for (const T& item : items)
            scratch[count[(keyOf(item) >> shift) & (kBuckets - 1)]++] = item;
        items.swap(scratch);
    }
}

// Canonical order whatever found them, in the solver's zones: sorts small (key, index) pairs,
// then moves each contact once, rather than shuffling the large contacts themselves.
// Node-major (contactKey): ordering the Gauss-Seidel sweeps box by box instead left the paper's
// piles measurably more entangled (docs/ALGORITHM.md). The contacts of `sources` (each one
// thread's, or `out` itself) land in `out` sorted. The keys are unique, so any sort gives the
// same order: by radix on the zone, A's node and B's box packed together (passes of 11 bits; the
// zone's bits add about one), where std::sort took 1 % of the alphabets run.
//
// The contacts go zone by zone (contact.h, buildSolverSchedule: the zone's key, its colour and
// place, above the canonical key), so that the solver, which sweeps zone by zone, reads them in
// runs instead of at random: in a pile ten times the paper's the response took 0.86-0.96 of its
// time (docs/BENCHMARKS.md). Within a zone the order is the canonical one, as the schedule keeps
// it, so the sweeps visit the contacts in the same order either way. Left canonical while placed
// bodies recover (settleOverlaps sums their contacts in order) and where the zones' indices and
// the canonical key do not fit 64 bits together. The bodies' zone cells are s.solver.cells, as
// findObjectContacts computed them for its queries.
void sortContacts(const CollisionWorld& w, std::span<const std::span<const Contact>> sources,
                  ContactList& out) {
    CollisionState& s = w.collision;
    std::vector<const Contact*>& from = s.sortSources;
    std::vector<size_t> at(sources.size() + 1, 0);
    for (size_t k = 0; k < sources.size(); ++k) at[k + 1] = at[k] + sources[k].size();
    const size_t n = at.back();
    from.resize(n);
    // A's node is a box's index times 8 plus a point's (contactKey), B's a box's index.
    const int bits = boxIndexBits(uint32_t(s.boxBody.size()));
    const int canonicalBits = 2 * bits + 3;
    // The zones' keys packed: colour (3 bits), then the block's indices from the lowest cell.
    int rowBits = 0, columnBits = 0;
    int32_t i0 = 0, k0 = 0;
    bool zoned = s.overlaps.empty() && n > 0;
    if (zoned) {
        lowestZoneCell(s.solver.cells, i0, k0);
        int64_t rows = 0, columns = 0;
        for (const ZoneCell& c : s.solver.cells)
            if (c.i != ZoneCell::kNowhere)
                rows = std::max(rows, int64_t(c.i) - i0),
                columns = std::max(columns, int64_t(c.k) - k0);
        rowBits = boxIndexBits(uint32_t(std::min<int64_t>(rows + 1, INT32_MAX)));
        columnBits = boxIndexBits(uint32_t(std::min<int64_t>(columns + 1, INT32_MAX)));
        zoned = canonicalBits + 3 + rowBits + columnBits <= 64;
    }
    const int keyBits = zoned ? canonicalBits + 3 + rowBits + columnBits : canonicalBits;
    std::vector<std::pair<uint64_t, uint32_t>>& keys = s.sortKeys;
    keys.resize(n);
    w.workers.forChunks(sources.size(), 1, [&](size_t k, size_t, int) {
        for (size_t i = 0; i < sources[k].size(); ++i) {
            const Contact& c = sources[k][i];
            from[at[k] + i] = &c;
            uint64_t key = uint64_t(c.nodeA) << bits | c.boxB;
            if (zoned) {
                const uint32_t zone =
                    zoneKey(s.solver.cells[c.bodyA], s.solver.cells[c.bodyB], i0, k0);
                // Colour (the tail's 4, its indices 0), row, column, each in its own bits.
                const uint64_t place =
                    uint64_t(zone >> 2 * kZoneIndexBits) << (rowBits + columnBits) |
                    uint64_t(zone >> kZoneIndexBits & kZoneIndexMask) << columnBits |
                    uint64_t(zone & kZoneIndexMask);
                key |= place << canonicalBits;
            }
            keys[at[k] + i] = {key, uint32_t(at[k] + i)};
        }
    });
    radixSort(keys, s.sortKeyScratch, keyBits,
              [](const std::pair<uint64_t, uint32_t>& k) { return k.first; });
    ContactList& sorted = s.sortScratch;
    sorted.resize(n);
    w.workers.forRange(n, [&](size_t first, size_t last, int) {
        for (size_t i = first; i < last; ++i) sorted[i] = *from[keys[i].second];
    });
    out.swap(sorted);
}

// Bounds in lanes, four to a group of six (lo x, y, z, hi x, y, z), NaN past the last: no
// comparison with NaN holds, so those lanes meet nothing.
void inLanes(const std::vector<Aabb>& each, std::vector<F4>& lanes) {
    lanes.assign((each.size() + 3) / 4 * 6, splat(NAN));
    for (size_t p = 0; p < each.size(); ++p) {
        F4* g = &lanes[p / 4 * 6];
        const int l = int(p % 4);
        for (int a = 0; a < 3; ++a) g[a][l] = each[p].lo[a], g[3 + a][l] = each[p].hi[a];
    }
}

// Whether `grown` overlaps any of the bounds in `lanes` (inLanes): Aabb::overlaps, the same
// comparisons, four at a time.
bool overlapsAny(const Aabb& grown, const std::vector<F4>& lanes) {
    const F4 lx = splat(grown.lo.x), ly = splat(grown.lo.y), lz = splat(grown.lo.z);
    const F4 hx = splat(grown.hi.x), hy = splat(grown.hi.y), hz = splat(grown.hi.z);
    for (size_t k = 0; k < lanes.size(); k += 6) {
        const F4* g = &lanes[k];
        if (any((lx <= g[3]) & (g[0] <= hx) & (ly <= g[4]) & (g[1] <= hy) & (lz <= g[5]) &
                (g[2] <= hz)))
            return true;
    }
    return false;
}

} // namespace

void findObjectContacts(CollisionWorld& w, CollisionMode mode, ContactList& out,
                        ObjectContactCounts& counts) {
    out.clear();
    counts = {};
    CollisionState& s = w.collision;
    const uint32_t n = uint32_t(w.bodies.size());
    s.nextClaims.clear();
    // Each body's zone cell on the floor: the order of the queries, of the contacts found and of
    // the solver's schedule (respondBeforeMove reads them), so computed even with nothing to find.
    zoneCells(w, s.solver.cells);
    if (mode == CollisionMode::None || n < 2) return;

    // Box planes are built on first use in a step: most boxes never meet another body's node.
    s.planeStamp.resize(s.planes.size(), 0);
    if (++s.stamp == 0) {
        std::fill(s.planeStamp.begin(), s.planeStamp.end(), 0);
        s.stamp = 1;
    }
    // Each body's terms of the bound on the margin (marginOf): its nodes' reach and its boxes'
    // skin.
    s.reach.resize(n);
    s.skin.resize(n);
    for (uint32_t b = 0; b < n; ++b) {
        s.reach[b] = reachOf(w, w.bodies[b]);
        s.skin[b] = skinOf(w, w.bodies[b]);
    }
    const size_t slots = size_t(w.workers.count());
    if (s.queryScratch.size() < slots) s.queryScratch.resize(slots);
    for (size_t k = 0; k < slots; ++k) {
        CollisionState::QueryScratch& q = s.queryScratch[k];
        q.partnerMark.assign(n, 0);
        q.partnerMargin.resize(n);
        q.keys.clear();
        q.potential = 0;
    }
    // The box pairs found (a node of one within the other's node bounds grown by the pair's
    // margin), each tested once as a pair: its manifold's points become contacts. The pairs
    // come from the threads' queries in any order; sorted, they are the same for any thread
    // count, and so are the chunks of consecutive pairs tested on the threads.
    auto emitBoxPairs = [&] {
        // Each thread's pairs sorted on its own, then merged.
        w.workers.forChunks(slots, 1, [&](size_t k, size_t, int) {
            std::vector<uint64_t>& q = s.queryScratch[k].keys;
            sortBoxPairKeys(q, s.queryScratch[k].keySortScratch, uint32_t(w.boxBounds.size()));
            q.erase(std::unique(q.begin(), q.end()), q.end());
        });
        std::vector<uint64_t>& keys = s.boxPairKeys;
        keys.clear();
        for (size_t k = 0; k < slots; ++k) {
            const CollisionState::QueryScratch& q = s.queryScratch[k];
            const size_t middle = keys.size();
            keys.insert(keys.end(), q.keys.begin(), q.keys.end());
            std::inplace_merge(keys.begin(), keys.begin() + ptrdiff_t(middle), keys.end());
            counts.nodeBoxPairs += q.potential;
        }
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        // The planes of every box in a pair, each built once.
        s.planeBoxes.clear();
        for (const uint64_t key : keys)
            for (const uint32_t box : {uint32_t(key >> 32), uint32_t(key)})
                if (s.planeStamp[box] != s.stamp) {
                    s.planeStamp[box] = s.stamp;
                    s.planeBoxes.push_back(box);
                }
        w.workers.forRange(s.planeBoxes.size(), [&](size_t first, size_t last, int) {
            for (size_t i = first; i < last; ++i) {
                const uint32_t box = s.planeBoxes[i];
                s.planes[box] = boxPlanes(&w.nodes[size_t(box) * 8]);
            }
        });
        s.sortSpans.clear();
        counts.boxPairs = int(keys.size());
        if (slots == 1) { // in place
            counts.contactBoxPairs = emitPairs(w, keys, out, s.nextClaims);
            s.sortSpans.push_back(out);
            return;
        }
        constexpr size_t kPairsPerChunk = 32;
        const size_t chunks = (keys.size() + kPairsPerChunk - 1) / kPairsPerChunk;
        if (s.pairChunks.size() < chunks) s.pairChunks.resize(chunks);
        w.workers.forChunks(keys.size(), kPairsPerChunk, [&](size_t first, size_t end, int) {
            CollisionState::PairChunk& chunk = s.pairChunks[first / kPairsPerChunk];
            chunk.contacts.clear();
            chunk.claims.clear();
            chunk.touching = emitPairs(w, std::span(keys).subspan(first, end - first),
                                       chunk.contacts, chunk.claims);
        });
        for (size_t c = 0; c < chunks; ++c) {
            const CollisionState::PairChunk& chunk = s.pairChunks[c];
            counts.contactBoxPairs += chunk.touching;
            s.sortSpans.push_back(chunk.contacts);
            s.nextClaims.insert(s.nextClaims.end(), chunk.claims.begin(), chunk.claims.end());
        }
    };
    // A box's samples for phase 2: its 8 nodes (item: the node) and its centre (item: its
    // first node with kCentreItem set), each as fn(item, position). The nodes alone miss a
    // thin box that runs through another with both ends outside it (a sliver of a letter's
    // stroke through the middle of another letter's cell, found 1.6 cm deep by the mesh
    // measure: docs/ALGORITHM.md §4, "Crossings"); its centre lies inside.
    auto forEachSample = [&](uint32_t box, auto&& fn) {
        const Vec3* nodes = &w.nodes[size_t(box) * 8];
        for (uint32_t k = 0; k < 8; ++k) fn(box * 8 + k, nodes[k]);
        fn(box * 8 | kCentreItem, boxCentre(nodes));
    };
    // Sample `node` of body A at p (a node, or a box's centre: kCentreItem), whose cube of A's
    // reach meets box `box` of body B grown by B's skin and reach (SpatialHash::cubeMeets: the one
    // test every mode applies before this): when it lies within the box's node bounds grown by the
    // pair's margin (marginOf(A, B)), the box pair of its own box and `box` is one to test
    // (emitBoxPairs).
    // `last`: the key this box's query found last; a box's nodes come in order from each hash
    // cell, so most repeats are that key.
    auto testBox = [&](CollisionState::QueryScratch& q, uint32_t bodyB, uint32_t box,
                       uint32_t bodyA, uint32_t node, Vec3 p, float margin, uint64_t& last) {
        if (isWhole(w, bodyA, bodyB)) return;       // never in enhanced (pairs left out)
        if (bothImmovable(w, bodyA, bodyB)) return; // nor these
        ++q.potential;
        if (!w.boxBounds[box].contains(p, margin)) return;
        const uint32_t own = (node & ~kCentreItem) / 8;
        const uint64_t key = own < box ? (uint64_t(own) << 32 | box) : (uint64_t(box) << 32 | own);
        if (key != last) q.keys.push_back(key), last = key;
    };
    auto grow = [](const Aabb& a, float r) {
        return Aabb{a.lo - Vec3{r, r, r}, a.hi + Vec3{r, r, r}};
    };

    if (mode == CollisionMode::Brute) {
        for (uint32_t b = 0; b < n; ++b) {
            const CollisionBody& B = w.bodies[b];
            for (uint32_t box = B.firstBox; box < B.firstBox + B.boxCount; ++box) {
                const Aabb grown = grow(w.boxBounds[box], s.skin[b] + s.reach[b]);
                uint64_t last = kNoKey;
                for (uint32_t a = 0; a < n; ++a) {
                    if (a == b) continue;
                    const CollisionBody& A = w.bodies[a];
                    const float margin = marginOf(w, A, B);
                    for (uint32_t own = A.firstBox; own < A.firstBox + A.boxCount; ++own)
                        forEachSample(own, [&](uint32_t item, Vec3 p) {
                            if (SpatialHash::cubeMeets(p, s.reach[a], grown))
                                testBox(s.queryScratch[0], b, box, a, item, p, margin, last);
                        });
                }
            }
        }
        emitBoxPairs();
        sortContacts(w, s.sortSpans, out);
        return;
    }

    // Phase 2: hash the nodes of the candidate objects (all objects for `previous`), each with
    // the cube of its body's reach, then each box of a candidate object visits the hash cells
    // its node bounds grown by its body's skin and reach overlap and tests the nodes of the
    // other objects it forms a candidate pair with (every other object for `previous`) whose
    // cubes meet them. The sizes depend on the two bodies alone, so a pair that phase 1 keeps
    // has the same node/box pairs tested in both modes; `previous` pays for hashing every
    // object's nodes and querying every object's boxes, because no pair is rejected early.
    //
    // A box whose grown bounds miss every partner's bounds can neither find a node (a node
    // lies within its object's bounds) nor have its nodes found (a box only finds nodes within
    // its own grown bounds): it is neither queried nor hashed, and no contact is lost.
    const bool enhanced = mode == CollisionMode::Enhanced;
    if (enhanced && s.pairs.empty()) return;
    auto isCandidate = [&](uint32_t b) { return !enhanced || s.isCandidate[b]; };
    // Each body's bounds grown by its reach (where its nodes' cubes lie) and by its skin and
    // reach (where its boxes' queries lie); for `previous`, the union of all bodies' but one,
    // by prefix and suffix unions.
    s.reachBounds.resize(n);
    s.queryBounds.resize(n);
    for (uint32_t b = 0; b < n; ++b) {
        s.reachBounds[b] = grow(w.bodies[b].bounds, s.reach[b]);
        s.queryBounds[b] = grow(w.bodies[b].bounds, s.skin[b] + s.reach[b]);
    }
    auto unions = [&](const std::vector<Aabb>& of, std::vector<Aabb>& prefix,
                      std::vector<Aabb>& suffix) {
        prefix.assign(n + 1, Aabb{});
        suffix.assign(n + 1, Aabb{});
        for (uint32_t a = 0; a < n; ++a) prefix[a + 1] = prefix[a], prefix[a + 1].add(of[a]);
        for (uint32_t a = n; a-- > 0;) suffix[a] = suffix[a + 1], suffix[a].add(of[a]);
    };
    if (!enhanced) {
        unions(s.reachBounds, s.prefixBounds, s.suffixBounds);
        unions(s.queryBounds, s.prefixQueryBounds, s.suffixQueryBounds);
    }
    // An object's partners' bounds tested one by one (four at a time, overlapsAny) up to this
    // many, their union past it. The union flags boxes that meet no partner, queried and hashed
    // for nothing; the results are the same either way. Measured interleaved against 8: the
    // alphabets' object_contacts 0.971-0.976, the spheres' 0.984-0.993 (docs/BENCHMARKS.md);
    // no limit at all measured the same as 32 on both.
    constexpr uint32_t kIndividual = 32;
    // Body b's partners: their reach and query bounds, one by one or as unions (into the
    // thread's scratch). `previous` has no partners: a box meets every other object's bounds
    // at once, their union (prefix and suffix unions), however few objects there are. Tested
    // one by one, they would be an object-pair test in all but name: on the dragons (29 others
    // each) its object_contacts took 0.52-0.60 of the time with them.
    auto gatherPartners = [&](uint32_t b, CollisionState::QueryScratch& q) {
        q.partnerBounds.clear();
        q.partnerQueryBounds.clear();
        q.individual = false;
        if (enhanced) {
            for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k) {
                q.partnerBounds.push_back(s.reachBounds[s.partners[k]]);
                q.partnerQueryBounds.push_back(s.queryBounds[s.partners[k]]);
            }
            q.individual = q.partnerBounds.size() <= kIndividual;
        }
        q.reachUnion = q.queryUnion = Aabb{};
        if (q.individual) {
            inLanes(q.partnerBounds, q.partnerLanes);
            inLanes(q.partnerQueryBounds, q.partnerQueryLanes);
            return;
        }
        if (enhanced) {
            for (const Aabb& a : q.partnerBounds) q.reachUnion.add(a);
            for (const Aabb& a : q.partnerQueryBounds) q.queryUnion.add(a);
        } else {
            q.reachUnion = s.prefixBounds[b], q.reachUnion.add(s.suffixBounds[b + 1]);
            q.queryUnion = s.prefixQueryBounds[b], q.queryUnion.add(s.suffixQueryBounds[b + 1]);
        }
    };
    auto near = [&](const CollisionState::QueryScratch& q, const Aabb& grown,
                    const std::vector<F4>& each, const Aabb& all) {
        return q.individual ? overlapsAny(grown, each) : grown.overlaps(all);
    };
    constexpr uint8_t kQuery = 1, kHash = 2;
    s.boxFlags.resize(w.boxBounds.size());
    s.hashedSamples.assign(n, 0);
    w.workers.forRange(n, [&](size_t firstBody, size_t lastBody, int slot) {
        CollisionState::QueryScratch& q = s.queryScratch[size_t(slot)];
        for (uint32_t b = uint32_t(firstBody); b < lastBody; ++b) {
            if (!isCandidate(b)) continue;
            const CollisionBody& B = w.bodies[b];
            gatherPartners(b, q);
            for (uint32_t box = B.firstBox; box < B.firstBox + B.boxCount; ++box) {
                const Aabb& bb = w.boxBounds[box];
                // Queried when its query bounds meet a partner's nodes' cubes; hashed when its
                // nodes' cubes meet a partner's query bounds.
                const bool query =
                    near(q, grow(bb, s.skin[b] + s.reach[b]), q.partnerLanes, q.reachUnion);
                const bool hash = near(q, grow(bb, s.reach[b]), q.partnerQueryLanes, q.queryUnion);
                s.boxFlags[box] = uint8_t((query ? kQuery : 0) | (hash ? kHash : 0));
                if (hash) s.hashedSamples[b] += 9; // nodes and centre
            }
        }
    });
    size_t sampleCount = 0;
    float cell = 0;
    for (uint32_t b = 0; b < n; ++b)
        if (isCandidate(b))
            sampleCount += s.hashedSamples[b], cell = maxNum(cell, w.bodies[b].cellSize);
    if (sampleCount == 0) return;
    float reach = 0;
    for (uint32_t b = 0; b < n; ++b)
        if (s.hashedSamples[b] > 0) reach = maxNum(reach, s.reach[b]);
    const float allowance = std::clamp(reach, kLeastAllowance * cell, kMostAllowance * cell);
    s.hash.begin(sampleCount, cell, s.reach, allowance);
    // The hashed boxes' samples staged in batches of bodies on the threads, added in body order.
    constexpr size_t kBodiesPerBatch = 16;
    const size_t batches = (n + kBodiesPerBatch - 1) / kBodiesPerBatch;
    if (s.hashBatches.size() < batches) s.hashBatches.resize(batches);
    w.workers.forChunks(n, kBodiesPerBatch, [&](size_t firstBody, size_t lastBody, int) {
        SpatialHash::Batch& batch = s.hashBatches[firstBody / kBodiesPerBatch];
        batch.staged.clear();
        batch.wide.clear();
        for (uint32_t b = uint32_t(firstBody); b < lastBody; ++b) {
            if (!isCandidate(b)) continue;
            const CollisionBody& r = w.bodies[b];
            for (uint32_t box = r.firstBox; box < r.firstBox + r.boxCount; ++box)
                if (s.boxFlags[box] & kHash)
                    forEachSample(box, [&](uint32_t item, Vec3 p) {
                        s.hash.add(batch, item, b, p); // the position too: no random reads later
                    });
        }
    });
    s.hash.addBatches(std::span(s.hashBatches).first(batches), w.workers);
    s.hash.reserveTable(s.hash.stagedCount()); // nodes of fast bodies lie in several cells
    s.hash.build(&w.workers);
    // Each object's boxes query the table on the world's threads (the table is read only), the
    // objects in the order of their places on the floor (the solver's zone cells, row after
    // row), so that the table's blocks one object reads are read again by the next while cached
    // (SpatialHash::cellKey): in a pile ten times the paper's, whose table outgrows the cache,
    // that and the blocks took a twelfth off object_contacts. The pairs found are sorted, so
    // the order changes no result.
    s.queryOrder.resize(n);
    for (uint32_t b = 0; b < n; ++b) s.queryOrder[b] = b;
    std::sort(s.queryOrder.begin(), s.queryOrder.end(), [&](uint32_t a, uint32_t b) {
        const ZoneCell &ca = s.solver.cells[a], &cb = s.solver.cells[b];
        return ca.k != cb.k ? ca.k < cb.k : ca.i != cb.i ? ca.i < cb.i : a < b;
    });
    w.workers.forRange(n, [&](size_t first, size_t last, int slot) {
        CollisionState::QueryScratch& q = s.queryScratch[size_t(slot)];
        for (size_t at = first; at < last; ++at) {
            const uint32_t b = s.queryOrder[at];
            if (!isCandidate(b)) continue;
            const CollisionBody& B = w.bodies[b];
            // Each partner's margin against b's boxes (every other object's for `previous`), and
            // the largest of their reaches: the queries need visit no further (a body whose
            // partners are slow, as in a pile at rest, visits fewer cells).
            float partnerReach = INFINITY;
            if (enhanced) {
                partnerReach = 0;
                for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k) {
                    const uint32_t a = s.partners[k];
                    q.partnerMark[a] = 1;
                    q.partnerMargin[a] = marginOf(w, w.bodies[a], B);
                    partnerReach = maxNum(partnerReach, s.reach[a]);
                }
            } else {
                for (uint32_t a = 0; a < n; ++a)
                    if (a != b) q.partnerMargin[a] = marginOf(w, w.bodies[a], B);
            }
            // The body's queried boxes, queried together: the cells that several of them
            // visit are read once (SpatialHash::forEachNearAll).
            q.queryBoxes.clear();
            q.queryWithin.clear();
            for (uint32_t box = B.firstBox; box < B.firstBox + B.boxCount; ++box) {
                if (!(s.boxFlags[box] & kQuery)) continue;
                q.queryBoxes.push_back(box);
                q.queryWithin.push_back(grow(w.boxBounds[box], s.skin[b] + s.reach[b]));
            }
            q.lastKey.assign(q.queryBoxes.size(), kNoKey);
            s.hash.forEachNearAll(
                q.queryWithin, b, q.group,
                [&](uint32_t k, const SpatialHash::Entry& e) {
                    if (!enhanced || q.partnerMark[e.owner])
                        testBox(q, b, q.queryBoxes[k], e.owner, e.item, e.position,
                                q.partnerMargin[e.owner], q.lastKey[k]);
                },
                partnerReach);
            if (enhanced)
                for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k)
                    q.partnerMark[s.partners[k]] = 0;
        }
    });
    emitBoxPairs();
    sortContacts(w, s.sortSpans, out);
}

// Least significant digit first, on the two halves packed into one number of twice the bits a
// box index needs (three passes of 11 bits for up to 2^16 boxes); std::sort for few keys. For
// the tens of thousands of keys (most of them repeats) a dense pile's queries find: with the
// last pair each box remembers, the sort went from 2.4 % of the alphabets run to 0.9 %
// (docs/BENCHMARKS.md).
void sortBoxPairKeys(std::vector<uint64_t>& keys, std::vector<uint64_t>& scratch, uint32_t boxes) {
    constexpr size_t kFew = 256;
    if (keys.size() < kFew) {
        std::sort(keys.begin(), keys.end());
        return;
    }
    const int bits = boxIndexBits(boxes);
    radixSort(keys, scratch, 2 * bits,
              [bits](uint64_t key) { return (key >> 32) << bits | (key & 0xffffffffu); });
}

void findAllObjectContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    ObjectContactCounts counts;
    findObjectContacts(w, w.settings.mode, s.all, counts);
    w.profile.potentialPairs = counts.nodeBoxPairs;
    w.profile.boxPairs = counts.boxPairs;
    w.profile.contactBoxPairs = counts.contactBoxPairs;
    std::swap(s.claims, s.nextClaims);
    s.objectCount = s.all.size();
    w.profile.contacts = int(s.objectCount);
}

} // namespace ffd::detail
