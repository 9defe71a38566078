// Reference: Jeon, Choi, Hong, "Enhanced FFD-AABB Collision Algorithm for Deformable Objects",
// 2012; Jung, Hong, Choi, "Collision Handling for Free-Form Deformation Embedded Surface", IET
// Image Processing 5(4), 2011; Teschner et al., VMV 2003 (spatial hashing).
#include "collision/pipeline.h"

#include "collision/overlap_recovery.h"
#include "util/check.h"

#include <algorithm>
#include <cmath>

namespace ffd::detail {

float skinOf(const CollisionWorld& w, const CollisionBody& b) {
    return w.settings.contactSkin * b.cellSize;
}

namespace {

// A box pair's reference face is on its second box only when that overlaps less than the
// first's by more than this share of the smaller skin (narrow_phase.h boxPairManifold).
constexpr float kReferenceTolerance = 0.1f;

// The reach every hash query covers beyond its box, as a share of the hash cell: a node whose
// body's reach is larger is stored in the cells of its cube shrunk by this much
// (spatial_hash.h). Measured against the rule before per-body reaches (alphabets, spheres; 200
// frames, enhanced, side by side): 0 (every fast node in every cell its cube meets) 1.42x and
// 1.39x the time, 1/8 1.21x and 1.17x, 1/4 1.07x and 1.19x, 1/2 1.06x and 1.40x.
constexpr float kReachAllowance = 0.25f;

// How far any node of a body can travel in one substep, as |V| + D (mean velocity and largest
// deviation from it; a node is a convex blend of its cell's particles, so none is faster than
// the fastest particle, and none of those is faster than |V| + D).
float reachOf(const CollisionWorld& w, const CollisionBody& b) {
    return w.substep * (length(b.meanVelocity) + b.spread);
}

// Contact margin between a node of A and a box of B: B's skin plus how far the two can close
// in one substep (speculative contacts: found before they touch, so the velocity solve can
// stop them at the surface however fast they come). Any point of A moves relative to any point
// of B by at most |V_A - V_B| + D_A + D_B (mean velocities and largest deviations from them):
// bodies falling together get a thin margin.
float marginOf(const CollisionWorld& w, const CollisionBody& a, const CollisionBody& b) {
    return skinOf(w, b) +
           w.substep * (length(a.meanVelocity - b.meanVelocity) + a.spread + b.spread);
}

// The margin is never more than B's skin plus each body's own reach, reachOf(A) + reachOf(B)
// (|V_A - V_B| + D_A + D_B <= |V_A| + D_A + |V_B| + D_B). Finding the node/box pairs to test by
// these per-body terms makes what a box queries and how far a node reaches depend on their own
// bodies only: every mode tests the same node/box pairs for a pair of bodies, whichever other
// bodies it also tests, and the pair's margin then decides (findObjectContacts).

// A body's share of the largest margin phase 1 may allow its pairs (twice its skin and reach:
// 2 marginOf(A, B) <= 2 (max(skin A, skin B) + reach A + reach B)), for the sweep's window.
float sweepMargin(const CollisionWorld& w, const CollisionBody& b) {
    return 2.0f * (skinOf(w, b) + reachOf(w, b));
}

// Push-out of deep overlap: what the projections leave of a contact's overlap in this substep
// (Contact::tolerated), so that it goes at a bounded speed, by moving positions, and the rigid
// phase leaves the contact out. Removed at once, deep overlap became a dent that shape matching
// restored at depth / substep, and the rigid phase turned that speed into rigid motion: 200
// overlapping spheres left at 44 m/s, two spheres created 5 cm into each other at 8 m/s
// (docs/ALGORITHM.md, "Overlap recovery" and "Push-out"). Pairs placed overlapping
// (overlap_recovery.h) lose at most WorldSettings::overlapRecoverySpeed x substep per substep;
// with WorldSettings::pushOutSpeed (0 by default: none) every contact deeper than the skin plus
// pushOutSpeed x substep loses at most that depth.
float toleratedOverlap(const CollisionWorld& w, const CollisionBody& b, float distance,
                       uint32_t bodyA, uint32_t bodyB) {
    // Pairs placed overlapping: at most the recovery speed x substep of overlap per substep.
    const float recovery = w.settings.overlapRecoverySpeed * w.substep;
    if (recovery > 0 && distance < -recovery && isRecovering(w, bodyA, bodyB))
        return distance + recovery;
    if (w.settings.pushOutSpeed == 0) return 0.0f;
    const float depth = skinOf(w, b) + w.settings.pushOutSpeed * w.substep;
    return distance < -depth ? distance + depth : 0.0f;
}

// Sets the contact's push-out: the overlap it keeps for later substeps and whether it does.
void setPushOut(const CollisionWorld& w, const CollisionBody& b, uint32_t bodyA, uint32_t bodyB,
                Contact& c) {
    c.tolerated = toleratedOverlap(w, b, c.distance, bodyA, bodyB);
    c.pushedOut = c.tolerated < 0;
}

float combineFriction(const CollisionBody& a, const CollisionBody& b) {
    return std::sqrt(a.friction * b.friction);
}

// Local coordinates, in the cell of box `box` of body B, of point q (on or near the box):
// the box's trilinear map inverted by Newton, started from its linearised map (close for all
// but thin, strongly deformed boxes), kept within the box.
Vec3 locateInBox(const CollisionWorld& w, const CollisionBody& B, uint32_t box,
                 const BoxPlanes& planes, Vec3 q) {
    const Lattice& LB = *B.lattice;
    const CellBox& boxB = LB.boxes[box - B.firstBox];
    const auto& cornersB = LB.cellParticles[boxB.cell];
    Vec3 corners[8];
    for (int k = 0; k < 8; ++k) corners[k] = w.x[B.firstParticle + cornersB[k]];
    Vec3 abc = max(Vec3{0, 0, 0}, min(boxParameters(planes, q), Vec3{1, 1, 1}));
    if (!isFinite(abc)) abc = {0.5f, 0.5f, 0.5f};
    Vec3 local = invertTrilinear(corners, q, boxB.lo + mul(boxB.hi - boxB.lo, abc), 3);
    if (!isFinite(local)) local = (boxB.lo + boxB.hi) * 0.5f;
    return max(boxB.lo, min(local, boxB.hi));
}

// A contact between body A's point at `localA` in the cell of box `boxA` and body B's box
// `box`, pushing A along `normal`; `distance` is the signed distance to B's face plane and
// `q` the point on it.
Contact makeObjectContact(const CollisionWorld& w, uint32_t bodyA, uint32_t boxA, Vec3 localA,
                          uint32_t bodyB, uint32_t box, Vec3 normal, float distance, Vec3 q,
                          const BoxPlanes& planes) {
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
    const Lattice& LA = *A.lattice;
    makeContactPoint(LA.cellParticles[LA.boxes[boxA - A.firstBox].cell].data(), A.firstParticle,
                     localA, w.invMass, c.a, c.invMassA);
    const Lattice& LB = *B.lattice;
    makeContactPoint(LB.cellParticles[LB.boxes[box - B.firstBox].cell].data(), B.firstParticle,
                     locateInBox(w, B, box, planes, q), w.invMass, c.b, c.invMassB);
    return c;
}

// Tests the box pairs `keys` (sorted), each once: its manifold's points become contacts, and
// what the pair may claim (from the last substep's claims) a claim, appended to `contacts` and
// `claims`.
void emitPairs(const CollisionWorld& w, std::span<const uint64_t> keys,
               std::vector<Contact>& contacts, std::vector<BoxPairClaim>& claims) {
    const CollisionState& s = w.collision;
    if (keys.empty()) return;
    // Into the last substep's claims, sorted like keys.
    size_t last =
        size_t(std::lower_bound(s.claims.begin(), s.claims.end(), keys.front(),
                                [](const BoxPairClaim& c, uint64_t k) { return c.key < k; }) -
               s.claims.begin());
    for (const uint64_t key : keys) {
        const uint32_t box[2] = {uint32_t(key >> 32), uint32_t(key)};
        uint32_t body[2];
        BoxView view[2];
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
        for (int k = 0; k < m.count; ++k) {
            const ManifoldPoint& pt = m.point[k];
            Contact c = makeObjectContact(w, body[inc], box[inc], pt.local, body[ref], box[ref],
                                          m.normal, pt.distance,
                                          pt.position - m.normal * pt.distance, *view[ref].planes);
            c.nodeA = box[inc] * 8 + uint32_t(k);
            deepest = maxNum(deepest, -pt.distance);
            closing = maxNum(closing, -dot(blend(c.a, w.v) - blend(c.b, w.v), c.normal));
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
    }
}

// Canonical order whatever found them: sorts small (key, index) pairs, then moves each contact
// once, rather than shuffling the large contacts themselves. Node-major (contactKey): ordering
// the Gauss-Seidel sweeps box by box instead left the paper's piles measurably more entangled
// (docs/ALGORITHM.md). The contacts of `sources` (each one thread's, or `out` itself) land in
// `out` sorted. The keys are unique, so any split of the sort gives the same order: one piece
// per thread, each sorted on its own, then merged.
void sortContacts(std::span<const std::span<const Contact>> sources, std::vector<Contact>& out,
                  CollisionState& s, Workers& workers) {
    std::vector<const Contact*>& from = s.sortSources;
    std::vector<size_t> at(sources.size() + 1, 0);
    for (size_t k = 0; k < sources.size(); ++k) at[k + 1] = at[k] + sources[k].size();
    const size_t n = at.back();
    from.resize(n);
    std::vector<std::pair<uint64_t, uint32_t>>& keys = s.sortKeys;
    keys.resize(n);
    workers.forChunks(sources.size(), 1, [&](size_t k, size_t, int) {
        for (size_t i = 0; i < sources[k].size(); ++i) {
            const Contact& c = sources[k][i];
            from[at[k] + i] = &c;
            keys[at[k] + i] = {contactKey(c), uint32_t(at[k] + i)};
        }
    });
    const size_t pieces = size_t(workers.count());
    const size_t piece = std::max<size_t>((n + pieces - 1) / pieces, 1);
    workers.forChunks(n, piece, [&](size_t first, size_t last, int) {
        std::sort(keys.begin() + ptrdiff_t(first), keys.begin() + ptrdiff_t(last));
    });
    for (size_t middle = piece; middle < n; middle += piece)
        std::inplace_merge(keys.begin(), keys.begin() + ptrdiff_t(middle),
                           keys.begin() + ptrdiff_t(std::min(n, middle + piece)));
    std::vector<Contact>& sorted = s.sortScratch;
    sorted.resize(n);
    workers.forRange(n, [&](size_t first, size_t last, int) {
        for (size_t i = first; i < last; ++i) sorted[i] = *from[keys[i].second];
    });
    out.swap(sorted);
}

bool spheresOverlap(const CollisionWorld& w, uint32_t i, uint32_t j) {
    const CollisionBody& a = w.bodies[i];
    const CollisionBody& b = w.bodies[j];
    // The narrow phase accepts nodes up to one margin outside a box's node bounds, which is
    // within sqrt(3) margins of the sphere: allow twice the larger margin so the test stays
    // conservative and the modes find identical contacts.
    const float margin = 2.0f * maxNum(marginOf(w, a, b), marginOf(w, b, a));
    const float r = a.sphereRadius + b.sphereRadius + margin;
    return lengthSquared(a.sphereCentre - b.sphereCentre) < r * r;
}

} // namespace

void rebuildCollisionTopology(CollisionWorld& w) {
    CollisionState& s = w.collision;
    const size_t boxes = w.boxBounds.size();
    s.boxBody.resize(boxes);
    s.nodeBody.resize(boxes * 8);
    s.planes.resize(boxes);
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const CollisionBody& r = w.bodies[b];
        for (uint32_t k = r.firstBox; k < r.firstBox + r.boxCount; ++k) {
            s.boxBody[k] = b;
            for (int n = 0; n < 8; ++n) s.nodeBody[size_t(k) * 8 + n] = b;
        }
    }
    s.isCandidate.assign(w.bodies.size(), 0);
    s.bodyFirstParticle.resize(w.bodies.size());
    s.bodyParticleCount.resize(w.bodies.size());
    for (size_t b = 0; b < w.bodies.size(); ++b) {
        s.bodyFirstParticle[b] = w.bodies[b].firstParticle;
        s.bodyParticleCount[b] = w.bodies[b].particleCount;
    }
}

void forgetBoxes(CollisionWorld& w, uint32_t first, uint32_t count) {
    // Renumbering both boxes down by the same count (or only the higher one) keeps the order
    // of the keys, so they stay sorted.
    std::erase_if(w.collision.claims, [&](BoxPairClaim& c) {
        uint32_t box[2] = {uint32_t(c.key >> 32), uint32_t(c.key)};
        bool gone = false;
        for (uint32_t& b : box) {
            gone = gone || (b >= first && b < first + count);
            if (b >= first + count) b -= count;
        }
        c.key = uint64_t(box[0]) << 32 | box[1];
        return gone;
    });
}

void updateNodes(CollisionWorld& w, size_t firstBody, size_t lastBody) {
    for (size_t b = firstBody; b < lastBody; ++b) {
        CollisionBody& r = w.bodies[b];
        const Lattice& L = *r.lattice;
        std::span<const Vec3> x(w.x.data() + r.firstParticle, r.particleCount);
        std::span<Vec3> nodes(w.nodes.data() + size_t(r.firstBox) * 8, size_t(r.boxCount) * 8);
        updateBoxNodes(L, x, nodes);
        float speed2 = 0;
        Vec3 momentum{};
        float mass = 0;
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i) {
            speed2 = maxNum(speed2, lengthSquared(w.v[i]));
            const float m = 1.0f / w.invMass[i];
            momentum += w.v[i] * m;
            mass += m;
        }
        r.maxSpeed = std::sqrt(speed2);
        r.meanVelocity = momentum / mass;
        float spread2 = 0;
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i)
            spread2 = maxNum(spread2, lengthSquared(w.v[i] - r.meanVelocity));
        r.spread = std::sqrt(spread2);
        Aabb body;
        for (uint32_t k = 0; k < r.boxCount; ++k) {
            Aabb box;
            for (int n = 0; n < 8; ++n) box.add(nodes[size_t(k) * 8 + n]);
            w.boxBounds[r.firstBox + k] = box;
            body.add(box);
        }
        r.bounds = body;
    }
}

void sphereTestAllPairs(CollisionWorld& w, std::vector<CandidatePair>& out) {
    out.clear();
    const uint32_t n = uint32_t(w.bodies.size());
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = i + 1; j < n; ++j)
            if (spheresOverlap(w, i, j)) out.push_back({i, j});
}

void sphereTestSweep(CollisionWorld& w, std::vector<CandidatePair>& out) {
    out.clear();
    const uint32_t n = uint32_t(w.bodies.size());
    std::vector<uint32_t>& order = w.collision.sweepOrder;
    std::vector<float>& lo = w.collision.sweepLo;
    std::vector<float>& hi = w.collision.sweepHi;
    order.resize(n);
    lo.resize(n);
    hi.resize(n);
    // Each body's extent along x: its sphere grown by its own share of the largest margin
    // (sweepMargin), so two spheres that pass the test always have overlapping extents,
    // however uneven their particles' velocities. The extents are padded by a little more than
    // the rounding of either computation can shift them.
    for (uint32_t i = 0; i < n; ++i) {
        const CollisionBody& r = w.bodies[i];
        const float half = r.sphereRadius + sweepMargin(w, r);
        const float pad = 1e-5f * (half + std::abs(r.sphereCentre.x));
        order[i] = i;
        lo[i] = r.sphereCentre.x - half - pad;
        hi[i] = r.sphereCentre.x + half + pad;
    }
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return lo[a] < lo[b] || (lo[a] == lo[b] && a < b); });
    // The sweep in chunks of the sorted order on the threads, each chunk's pairs on their own.
    constexpr uint32_t kPerChunk = 64;
    const size_t chunks = (n + kPerChunk - 1) / kPerChunk;
    std::vector<std::vector<CandidatePair>>& found = w.collision.sweepChunks;
    if (found.size() < chunks) found.resize(chunks);
    w.workers.forChunks(n, kPerChunk, [&](size_t first, size_t last, int) {
        std::vector<CandidatePair>& pairs = found[first / kPerChunk];
        pairs.clear();
        for (size_t k = first; k < last; ++k) {
            const uint32_t i = order[k];
            for (size_t m = k + 1; m < n && lo[order[m]] <= hi[i]; ++m) {
                const uint32_t j = order[m];
                if (spheresOverlap(w, i, j)) pairs.push_back({std::min(i, j), std::max(i, j)});
            }
        }
    });
    for (size_t c = 0; c < chunks; ++c) out.insert(out.end(), found[c].begin(), found[c].end());
    std::sort(out.begin(), out.end(), [](const CandidatePair& a, const CandidatePair& b) {
        return a.a < b.a || (a.a == b.a && a.b < b.b);
    });
}

void computeSpheres(CollisionWorld& w) {
    // Spheres: centre of the node bounds, radius to the farthest corner of any box's bounds.
    w.workers.forRange(w.bodies.size(), [&](size_t first, size_t last, int) {
        for (size_t i = first; i < last; ++i) {
            CollisionBody& r = w.bodies[i];
            const Vec3 c = r.bounds.centre();
            float r2 = 0;
            for (uint32_t k = r.firstBox; k < r.firstBox + r.boxCount; ++k) {
                const Aabb& b = w.boxBounds[k];
                const Vec3 d = max(b.hi - c, c - b.lo);
                r2 = maxNum(r2, lengthSquared(d));
            }
            r.sphereCentre = c;
            r.sphereRadius = std::sqrt(r2);
        }
    });
}

void sphereTest(CollisionWorld& w) {
    computeSpheres(w);
    CollisionState& s = w.collision;
    if (int(w.bodies.size()) > w.settings.sweepThreshold)
        sphereTestSweep(w, s.pairs);
    else
        sphereTestAllPairs(w, s.pairs);
    // Pairs placed one inside the other find no object contacts (overlap_recovery.h).
    if (!s.wholePairs.empty())
        std::erase_if(s.pairs, [&](const CandidatePair& p) { return isWhole(w, p.a, p.b); });

    // Partners of each body (CSR), for the hash phase's pair check.
    const size_t n = w.bodies.size();
    s.isCandidate.assign(n, 0);
    s.partnerStart.assign(n + 1, 0);
    for (const CandidatePair& p : s.pairs) ++s.partnerStart[p.a + 1], ++s.partnerStart[p.b + 1];
    for (size_t i = 0; i < n; ++i) s.partnerStart[i + 1] += s.partnerStart[i];
    s.partners.resize(s.pairs.size() * 2);
    std::vector<uint32_t>& fill = s.sweepOrder;
    fill.assign(s.partnerStart.begin(), s.partnerStart.end() - 1);
    for (const CandidatePair& p : s.pairs) {
        s.partners[fill[p.a]++] = p.b;
        s.partners[fill[p.b]++] = p.a;
        s.isCandidate[p.a] = s.isCandidate[p.b] = 1;
    }
}

void findFloorContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    s.all.resize(s.objectCount);
    w.profile.floorContacts = 0;
    if (!w.settings.floor) return;
    // On one thread: the contacts are few per body and cheap to make, and on several threads
    // their copies into place cost more than making them (measured on alphabets).
    const float floorY = w.settings.floorHeight;
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const CollisionBody& r = w.bodies[b];
        const float skin = skinOf(w, r) + w.substep * r.maxSpeed;
        if (r.bounds.lo.y >= floorY + skin) continue;
        const Lattice& L = *r.lattice;
        for (uint32_t k = 0; k < r.boxCount; ++k) {
            if (w.boxBounds[r.firstBox + k].lo.y >= floorY + skin) continue;
            const CellBox& box = L.boxes[k];
            for (int n = 0; n < 8; ++n) {
                const uint32_t node = (r.firstBox + k) * 8 + uint32_t(n);
                const float y = w.nodes[node].y;
                if (y >= floorY + skin) continue;
                Contact c;
                c.bodyA = b;
                c.nodeA = node;
                c.normal = {0, 1, 0};
                c.offset = floorY;
                c.distance = y - floorY;
                setPushOut(w, r, b, kFloorBody, c);
                c.friction = r.friction;
                c.restitution = r.restitution;
                c.rigidity = r.contactRigidity;
                makeContactPoint(L.cellParticles[box.cell].data(), r.firstParticle,
                                 box.nodeLocal(n), w.invMass, c.a, c.invMassA);
                s.all.push_back(c);
            }
        }
    }
    w.profile.floorContacts = int(s.all.size() - s.objectCount);
}

void findObjectContacts(CollisionWorld& w, CollisionMode mode, std::vector<Contact>& out,
                        int& outPotential) {
    out.clear();
    outPotential = 0;
    CollisionState& s = w.collision;
    const uint32_t n = uint32_t(w.bodies.size());
    s.nextClaims.clear();
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
            std::sort(q.begin(), q.end());
            q.erase(std::unique(q.begin(), q.end()), q.end());
        });
        std::vector<uint64_t>& keys = s.boxPairKeys;
        keys.clear();
        for (size_t k = 0; k < slots; ++k) {
            const CollisionState::QueryScratch& q = s.queryScratch[k];
            const size_t middle = keys.size();
            keys.insert(keys.end(), q.keys.begin(), q.keys.end());
            std::inplace_merge(keys.begin(), keys.begin() + ptrdiff_t(middle), keys.end());
            outPotential += q.potential;
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
        if (slots == 1) { // in place
            emitPairs(w, keys, out, s.nextClaims);
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
            emitPairs(w, std::span(keys).subspan(first, end - first), chunk.contacts, chunk.claims);
        });
        for (size_t c = 0; c < chunks; ++c) {
            const CollisionState::PairChunk& chunk = s.pairChunks[c];
            s.sortSpans.push_back(chunk.contacts);
            s.nextClaims.insert(s.nextClaims.end(), chunk.claims.begin(), chunk.claims.end());
        }
    };
    // Node `node` of body A at p, whose cube of A's reach meets box `box` of body B grown by
    // B's skin and reach (SpatialHash::cubeMeets: the one test every mode applies before
    // this): when it lies within the box's node bounds grown by the pair's margin
    // (marginOf(A, B)), the box pair of its own box and `box` is one to test (emitBoxPairs).
    auto testBox = [&](CollisionState::QueryScratch& q, uint32_t bodyB, uint32_t box,
                       uint32_t bodyA, uint32_t node, Vec3 p, float margin) {
        if (isWhole(w, bodyA, bodyB)) return; // never in enhanced (pairs left out)
        ++q.potential;
        if (!w.boxBounds[box].contains(p, margin)) return;
        const uint32_t own = node / 8;
        const uint64_t key = own < box ? (uint64_t(own) << 32 | box) : (uint64_t(box) << 32 | own);
        // A box's nodes come in order from each hash cell: most repeats are the last key.
        if (q.keys.empty() || q.keys.back() != key) q.keys.push_back(key);
    };
    auto grow = [](const Aabb& a, float r) {
        return Aabb{a.lo - Vec3{r, r, r}, a.hi + Vec3{r, r, r}};
    };

    if (mode == CollisionMode::Brute) {
        for (uint32_t b = 0; b < n; ++b) {
            const CollisionBody& B = w.bodies[b];
            for (uint32_t box = B.firstBox; box < B.firstBox + B.boxCount; ++box) {
                const Aabb grown = grow(w.boxBounds[box], s.skin[b] + s.reach[b]);
                for (uint32_t a = 0; a < n; ++a) {
                    if (a == b) continue;
                    const CollisionBody& A = w.bodies[a];
                    const float margin = marginOf(w, A, B);
                    for (uint32_t node = A.firstBox * 8; node < (A.firstBox + A.boxCount) * 8;
                         ++node)
                        if (SpatialHash::cubeMeets(w.nodes[node], s.reach[a], grown))
                            testBox(s.queryScratch[0], b, box, a, node, w.nodes[node], margin);
                }
            }
        }
        emitBoxPairs();
        sortContacts(s.sortSpans, out, s, w.workers);
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
    constexpr uint32_t kIndividual = 8; // partners' bounds tested one by one up to this many
    // Body b's partners: their reach and query bounds, one by one or as unions (into the
    // thread's scratch).
    auto gatherPartners = [&](uint32_t b, CollisionState::QueryScratch& q) {
        q.partnerBounds.clear();
        q.partnerQueryBounds.clear();
        if (enhanced) {
            for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k) {
                q.partnerBounds.push_back(s.reachBounds[s.partners[k]]);
                q.partnerQueryBounds.push_back(s.queryBounds[s.partners[k]]);
            }
            q.individual = q.partnerBounds.size() <= kIndividual;
        } else {
            q.individual = n - 1 <= kIndividual;
            for (uint32_t a = 0; q.individual && a < n; ++a)
                if (a != b) {
                    q.partnerBounds.push_back(s.reachBounds[a]);
                    q.partnerQueryBounds.push_back(s.queryBounds[a]);
                }
        }
        q.reachUnion = q.queryUnion = Aabb{};
        if (q.individual) return;
        if (enhanced) {
            for (const Aabb& a : q.partnerBounds) q.reachUnion.add(a);
            for (const Aabb& a : q.partnerQueryBounds) q.queryUnion.add(a);
        } else {
            q.reachUnion = s.prefixBounds[b], q.reachUnion.add(s.suffixBounds[b + 1]);
            q.queryUnion = s.prefixQueryBounds[b], q.queryUnion.add(s.suffixQueryBounds[b + 1]);
        }
    };
    auto near = [&](const CollisionState::QueryScratch& q, const Aabb& grown,
                    const std::vector<Aabb>& each, const Aabb& all) {
        if (!q.individual) return grown.overlaps(all);
        for (const Aabb& a : each)
            if (grown.overlaps(a)) return true;
        return false;
    };
    constexpr uint8_t kQuery = 1, kHash = 2;
    s.boxFlags.resize(w.boxBounds.size());
    s.hashedNodes.assign(n, 0);
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
                    near(q, grow(bb, s.skin[b] + s.reach[b]), q.partnerBounds, q.reachUnion);
                const bool hash = near(q, grow(bb, s.reach[b]), q.partnerQueryBounds, q.queryUnion);
                s.boxFlags[box] = uint8_t((query ? kQuery : 0) | (hash ? kHash : 0));
                if (hash) s.hashedNodes[b] += 8;
            }
        }
    });
    size_t nodeCount = 0;
    float cell = 0;
    for (uint32_t b = 0; b < n; ++b)
        if (isCandidate(b))
            nodeCount += s.hashedNodes[b], cell = maxNum(cell, w.bodies[b].cellSize);
    if (nodeCount == 0) return;
    s.hash.begin(nodeCount, cell, s.reach, kReachAllowance * cell);
    // The hashed boxes' nodes staged in batches of bodies on the threads, added in body order.
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
                    for (uint32_t node = box * 8; node < box * 8 + 8; ++node)
                        // The position too: no random reads later.
                        s.hash.add(batch, node, b, w.nodes[node]);
        }
    });
    s.hash.addBatches(std::span(s.hashBatches).first(batches), w.workers);
    s.hash.reserveTable(s.hash.stagedCount()); // nodes of fast bodies lie in several cells
    s.hash.build(&w.workers);
    // Each object's boxes query the table on the world's threads (the table is read only).
    w.workers.forRange(n, [&](size_t firstBody, size_t lastBody, int slot) {
        CollisionState::QueryScratch& q = s.queryScratch[size_t(slot)];
        for (uint32_t b = uint32_t(firstBody); b < lastBody; ++b) {
            if (!isCandidate(b)) continue;
            const CollisionBody& B = w.bodies[b];
            // Each partner's margin against b's boxes (every other object's for `previous`).
            if (enhanced) {
                for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k) {
                    const uint32_t a = s.partners[k];
                    q.partnerMark[a] = 1;
                    q.partnerMargin[a] = marginOf(w, w.bodies[a], B);
                }
            } else {
                for (uint32_t a = 0; a < n; ++a)
                    if (a != b) q.partnerMargin[a] = marginOf(w, w.bodies[a], B);
            }
            for (uint32_t box = B.firstBox; box < B.firstBox + B.boxCount; ++box) {
                if (!(s.boxFlags[box] & kQuery)) continue;
                const Aabb grown = grow(w.boxBounds[box], s.skin[b] + s.reach[b]);
                s.hash.forEachNear(grown, b, [&](const SpatialHash::Entry& e) {
                    if (!enhanced || q.partnerMark[e.owner])
                        testBox(q, b, box, e.owner, e.item, e.position, q.partnerMargin[e.owner]);
                });
            }
            if (enhanced)
                for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k)
                    q.partnerMark[s.partners[k]] = 0;
        }
    });
    emitBoxPairs();
    sortContacts(s.sortSpans, out, s, w.workers);
}

void findAllObjectContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    findObjectContacts(w, w.settings.mode, s.all, w.profile.potentialPairs);
    std::swap(s.claims, s.nextClaims);
    s.objectCount = s.all.size();
    w.profile.contacts = int(s.objectCount);
}

namespace {

// The solver's zones (contact.h, buildSolverSchedule): each body's cell on a grid over x and
// z as wide as the widest body, so that bodies in contact lie in the same or neighbouring
// cells. It depends on the positions alone, never on the thread count.
void scheduleContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    float width = 0;
    for (const CollisionBody& r : w.bodies) {
        const Vec3 e = r.bounds.extent();
        width = maxNum(width, maxNum(e.x, e.z));
    }
    if (!(width > 0) || !std::isfinite(width)) width = 1;
    const float inverse = 1.0f / width;
    std::vector<ZoneCell>& cells = s.solver.cells;
    cells.resize(w.bodies.size());
    for (size_t b = 0; b < w.bodies.size(); ++b) {
        const Vec3 c = w.bodies[b].bounds.centre() * inverse;
        constexpr float kRange = 1 << 29;
        if (std::abs(c.x) < kRange && std::abs(c.z) < kRange)
            cells[b] = {int32_t(std::floor(c.x)), int32_t(std::floor(c.z))};
        else
            cells[b] = {ZoneCell::kNowhere, ZoneCell::kNowhere};
    }
    buildSolverSchedule(s.all, cells, s.solver.schedule, w.workers);
}

} // namespace

void respondBeforeMove(CollisionWorld& w, float dt) {
    CollisionState& s = w.collision;
    if (s.all.empty()) return;
    scheduleContacts(w);
#if FFD_CHECKS
    const std::string contacts =
        contactProblem(s.all, w.bodies.size(), s.bodyFirstParticle, s.bodyParticleCount);
    FFD_CHECK(contacts.empty(), "contacts: " + contacts);
    const std::string schedule = scheduleProblem(s.all, s.solver.schedule, w.bodies.size());
    FFD_CHECK(schedule.empty(), "solver schedule: " + schedule);
#endif
    const int iterations = w.settings.solverIterations;
    solveContactPositions(s.all, w.x, {}, w.invMass, dt, iterations, w.bodies.size(), s.solver,
                          w.workers);
    const float impact = 2.0f * length(w.settings.gravity) * dt;
    solveRigidPhase(s.all, s.rigid, s.rigidPoints, w.x, w.v, w.invMass, s.bodyFirstParticle,
                    s.bodyParticleCount, dt, impact, w.settings.maxSeparationSpeed, iterations,
                    s.solver, w.workers);
}

float respondAfterMove(CollisionWorld& w, float dt) {
    CollisionState& s = w.collision;
    if (s.all.empty()) return 0;
    const int iterations = w.settings.solverIterations;
    const float impact = 2.0f * length(w.settings.gravity) * dt;
    solveContactPositions(s.all, w.x, w.v, w.invMass, dt, iterations, w.bodies.size(), s.solver,
                          w.workers);
    return solveContactVelocities(s.all, w.x, w.v, w.invMass, dt, impact, iterations,
                                  w.bodies.size(), s.solver, w.workers);
}

} // namespace ffd::detail
