// Reference: Jeon, Choi, Hong, "Enhanced FFD-AABB Collision Algorithm for Deformable Objects",
// 2012; Jung, Hong, Choi, "Collision Handling for Free-Form Deformation Embedded Surface", IET
// Image Processing 5(4), 2011; Teschner et al., VMV 2003 (spatial hashing).
#include "collision/pipeline.h"

#include "collision/overlap_recovery.h"
#include "world/world_data.h"

#include <algorithm>
#include <cmath>

namespace ffd::detail {

float skinOf(const WorldData& w, const BodyRecord& b) {
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
float reachOf(const WorldData& w, const BodyRecord& b) {
    return w.substep * (length(b.meanVelocity) + b.spread);
}

// Contact margin between a node of A and a box of B: B's skin plus how far the two can close
// in one substep (speculative contacts: found before they touch, so the velocity solve can
// stop them at the surface however fast they come). Any point of A moves relative to any point
// of B by at most |V_A - V_B| + D_A + D_B (mean velocities and largest deviations from them):
// bodies falling together get a thin margin.
float marginOf(const WorldData& w, const BodyRecord& a, const BodyRecord& b) {
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
float sweepMargin(const WorldData& w, const BodyRecord& b) {
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
float toleratedOverlap(const WorldData& w, const BodyRecord& b, float distance, uint32_t bodyA,
                       uint32_t bodyB) {
    // Pairs placed overlapping: at most the recovery speed x substep of overlap per substep.
    const float recovery = w.settings.overlapRecoverySpeed * w.substep;
    if (recovery > 0 && distance < -recovery && isRecovering(w, bodyA, bodyB))
        return distance + recovery;
    if (w.settings.pushOutSpeed == 0) return 0.0f;
    const float depth = skinOf(w, b) + w.settings.pushOutSpeed * w.substep;
    return distance < -depth ? distance + depth : 0.0f;
}

// Sets the contact's push-out: the overlap it keeps for later substeps and whether it does.
void setPushOut(const WorldData& w, const BodyRecord& b, uint32_t bodyA, uint32_t bodyB,
                Contact& c) {
    c.tolerated = toleratedOverlap(w, b, c.distance, bodyA, bodyB);
    c.pushedOut = c.tolerated < 0;
}

float combineFriction(const BodyRecord& a, const BodyRecord& b) {
    return std::sqrt(a.settings.friction * b.settings.friction);
}

// Local coordinates, in the cell of box `box` of body B, of point q (on or near the box):
// the box's trilinear map inverted by Newton, started from its linearised map (close for all
// but thin, strongly deformed boxes), kept within the box.
Vec3 locateInBox(const WorldData& w, const BodyRecord& B, uint32_t box, const BoxPlanes& planes,
                 Vec3 q) {
    const Lattice& LB = B.model->lattice;
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
Contact makeObjectContact(const WorldData& w, uint32_t bodyA, uint32_t boxA, Vec3 localA,
                          uint32_t bodyB, uint32_t box, Vec3 normal, float distance, Vec3 q,
                          const BoxPlanes& planes) {
    const BodyRecord& A = w.bodies[bodyA];
    const BodyRecord& B = w.bodies[bodyB];
    Contact c;
    c.bodyA = bodyA;
    c.bodyB = bodyB;
    c.boxB = box;
    c.hasB = true;
    c.normal = normal;
    c.distance = distance;
    setPushOut(w, B, bodyA, bodyB, c);
    c.friction = combineFriction(A, B);
    c.restitution = maxNum(A.settings.restitution, B.settings.restitution);
    c.rigidity = 0.5f * (A.settings.contactRigidity + B.settings.contactRigidity);
    const Lattice& LA = A.model->lattice;
    makeContactPoint(LA.cellParticles[LA.boxes[boxA - A.firstBox].cell].data(), A.firstParticle,
                     localA, w.invMass, c.a, c.invMassA);
    const Lattice& LB = B.model->lattice;
    makeContactPoint(LB.cellParticles[LB.boxes[box - B.firstBox].cell].data(), B.firstParticle,
                     locateInBox(w, B, box, planes, q), w.invMass, c.b, c.invMassB);
    return c;
}

// Canonical order whatever found them: sorts small (key, index) pairs, then moves each contact
// once, rather than shuffling the large contacts themselves. Node-major (contactKey): ordering
// the Gauss-Seidel sweeps box by box instead left the paper's piles measurably more entangled
// (docs/ALGORITHM.md).
void sortContacts(std::vector<Contact>& contacts, std::vector<std::pair<uint64_t, uint32_t>>& keys,
                  std::vector<Contact>& scratch) {
    keys.resize(contacts.size());
    for (uint32_t i = 0; i < contacts.size(); ++i) keys[i] = {contactKey(contacts[i]), i};
    std::sort(keys.begin(), keys.end());
    scratch.resize(contacts.size());
    for (size_t i = 0; i < keys.size(); ++i) scratch[i] = contacts[keys[i].second];
    contacts.swap(scratch);
}

bool spheresOverlap(const WorldData& w, uint32_t i, uint32_t j) {
    const BodyRecord& a = w.bodies[i];
    const BodyRecord& b = w.bodies[j];
    // The narrow phase accepts nodes up to one margin outside a box's node bounds, which is
    // within sqrt(3) margins of the sphere: allow twice the larger margin so the test stays
    // conservative and the modes find identical contacts.
    const float margin = 2.0f * maxNum(marginOf(w, a, b), marginOf(w, b, a));
    const float r = a.sphereRadius + b.sphereRadius + margin;
    return lengthSquared(a.sphereCentre - b.sphereCentre) < r * r;
}

} // namespace

void rebuildCollisionTopology(WorldData& w) {
    CollisionState& s = w.collision;
    const size_t boxes = w.boxBounds.size();
    s.boxBody.resize(boxes);
    s.nodeBody.resize(boxes * 8);
    s.planes.resize(boxes);
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& r = w.bodies[b];
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

void forgetBoxes(WorldData& w, uint32_t first, uint32_t count) {
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

void updateNodes(WorldData& w, size_t firstBody, size_t lastBody) {
    for (size_t b = firstBody; b < lastBody; ++b) {
        BodyRecord& r = w.bodies[b];
        const Lattice& L = r.model->lattice;
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

void sphereTestAllPairs(WorldData& w, std::vector<CandidatePair>& out) {
    out.clear();
    const uint32_t n = uint32_t(w.bodies.size());
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = i + 1; j < n; ++j)
            if (spheresOverlap(w, i, j)) out.push_back({i, j});
}

void sphereTestSweep(WorldData& w, std::vector<CandidatePair>& out) {
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
        const BodyRecord& r = w.bodies[i];
        const float half = r.sphereRadius + sweepMargin(w, r);
        const float pad = 1e-5f * (half + std::abs(r.sphereCentre.x));
        order[i] = i;
        lo[i] = r.sphereCentre.x - half - pad;
        hi[i] = r.sphereCentre.x + half + pad;
    }
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return lo[a] < lo[b] || (lo[a] == lo[b] && a < b); });
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t i = order[k];
        for (uint32_t m = k + 1; m < n && lo[order[m]] <= hi[i]; ++m) {
            const uint32_t j = order[m];
            if (spheresOverlap(w, i, j)) out.push_back({std::min(i, j), std::max(i, j)});
        }
    }
    std::sort(out.begin(), out.end(), [](const CandidatePair& a, const CandidatePair& b) {
        return a.a < b.a || (a.a == b.a && a.b < b.b);
    });
}

void computeSpheres(WorldData& w) {
    // Spheres: centre of the node bounds, radius to the farthest corner of any box's bounds.
    for (BodyRecord& r : w.bodies) {
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
}

void sphereTest(WorldData& w) {
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

void findFloorContacts(WorldData& w) {
    CollisionState& s = w.collision;
    s.all.resize(s.objectCount);
    w.profile.floorContacts = 0;
    if (!w.settings.floor) return;
    const float floorY = w.settings.floorHeight;
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& r = w.bodies[b];
        const float skin = skinOf(w, r) + w.substep * r.maxSpeed;
        if (r.bounds.lo.y >= floorY + skin) continue;
        const Lattice& L = r.model->lattice;
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
                c.friction = r.settings.friction;
                c.restitution = r.settings.restitution;
                c.rigidity = r.settings.contactRigidity;
                makeContactPoint(L.cellParticles[box.cell].data(), r.firstParticle,
                                 box.nodeLocal(n), w.invMass, c.a, c.invMassA);
                s.all.push_back(c);
            }
        }
    }
    w.profile.floorContacts = int(s.all.size() - s.objectCount);
}

void findObjectContacts(WorldData& w, CollisionMode mode, std::vector<Contact>& out,
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
    s.boxPairKeys.clear();
    auto planesOf = [&](uint32_t box) -> const BoxPlanes& {
        if (s.planeStamp[box] != s.stamp) {
            s.planes[box] = boxPlanes(&w.nodes[size_t(box) * 8]);
            s.planeStamp[box] = s.stamp;
        }
        return s.planes[box];
    };
    // The box pairs found (a node of one within the other's node bounds grown by the pair's
    // margin), each tested once as a pair: its manifold's points become contacts.
    auto emitBoxPairs = [&] {
        std::vector<uint64_t>& keys = s.boxPairKeys;
        std::sort(keys.begin(), keys.end());
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        size_t last = 0; // into the last substep's claims, sorted like keys
        for (const uint64_t key : keys) {
            const uint32_t box[2] = {uint32_t(key >> 32), uint32_t(key)};
            uint32_t body[2];
            BoxView view[2];
            for (int k = 0; k < 2; ++k) {
                body[k] = s.boxBody[box[k]];
                const BodyRecord& r = w.bodies[body[k]];
                const CellBox& cb = r.model->lattice.boxes[box[k] - r.firstBox];
                view[k].nodes = &w.nodes[size_t(box[k]) * 8];
                for (int j = 0; j < 8; ++j) view[k].local[j] = cb.nodeLocal(j);
                view[k].planes = &planesOf(box[k]);
                view[k].outsideFaces = cb.outsideFaces;
            }
            const BodyRecord& P = w.bodies[body[0]];
            const BodyRecord& Q = w.bodies[body[1]];
            const float margin = maxNum(marginOf(w, P, Q), marginOf(w, Q, P));
            const float tolerance = kReferenceTolerance * minNum(s.skin[body[0]], s.skin[body[1]]);
            const BoxPairManifold m = boxPairManifold(view[0], view[1], margin, tolerance);
            if (m.reference < 0) continue;
            const int ref = m.reference, inc = 1 - m.reference;
            // What the pair may claim: all its overlap, unless its boxes overlap least across
            // a face into a neighbouring cell; then that overlap, or what it claimed in the last
            // substep plus how much deeper its deepest point has got since, whichever is more.
            // A box grazing such a face can lie a cell deep along the normal: claimed at once,
            // that depth threw resting letters into the air, while a pair that deepens under a
            // load keeps up with it (docs/ALGORITHM.md, section 5).
            float deepest = 0;
            for (int k = 0; k < m.count; ++k) deepest = maxNum(deepest, -m.point[k].distance);
            while (last < s.claims.size() && s.claims[last].key < key) ++last;
            const BoxPairClaim* before =
                last < s.claims.size() && s.claims[last].key == key ? &s.claims[last] : nullptr;
            const float grown =
                before ? before->claimed + maxNum(0.0f, deepest - before->deepest) : 0.0f;
            const float allowed = m.depthBound < INFINITY ? maxNum(m.depthBound, grown) : INFINITY;
            s.nextClaims.push_back({key, minNum(deepest, allowed), deepest});
            for (int k = 0; k < m.count; ++k) {
                const ManifoldPoint& pt = m.point[k];
                Contact c = makeObjectContact(
                    w, body[inc], box[inc], pt.local, body[ref], box[ref], m.normal, pt.distance,
                    pt.position - m.normal * pt.distance, *view[ref].planes);
                c.nodeA = box[inc] * 8 + uint32_t(k);
                // The rest of the point's overlap is kept for later substeps.
                c.tolerated = minNum(c.tolerated, minNum(0.0f, pt.distance + allowed));
                out.push_back(c);
            }
        }
    };
    // Node `node` of body A at p, whose cube of A's reach meets box `box` of body B grown by
    // B's skin and reach (SpatialHash::cubeMeets: the one test every mode applies before
    // this): when it lies within the box's node bounds grown by the pair's margin
    // (marginOf(A, B)), the box pair of its own box and `box` is one to test (emitBoxPairs).
    auto testBox = [&](uint32_t bodyB, uint32_t box, uint32_t bodyA, uint32_t node, Vec3 p,
                       float margin) {
        if (isWhole(w, bodyA, bodyB)) return; // never in enhanced (pairs left out)
        ++outPotential;
        if (!w.boxBounds[box].contains(p, margin)) return;
        const uint32_t own = node / 8;
        const uint64_t key = own < box ? (uint64_t(own) << 32 | box) : (uint64_t(box) << 32 | own);
        // A box's nodes come in order from each hash cell: most repeats are the last key.
        if (s.boxPairKeys.empty() || s.boxPairKeys.back() != key) s.boxPairKeys.push_back(key);
    };
    auto grow = [](const Aabb& a, float r) {
        return Aabb{a.lo - Vec3{r, r, r}, a.hi + Vec3{r, r, r}};
    };

    if (mode == CollisionMode::Brute) {
        for (uint32_t b = 0; b < n; ++b) {
            const BodyRecord& B = w.bodies[b];
            for (uint32_t box = B.firstBox; box < B.firstBox + B.boxCount; ++box) {
                const Aabb grown = grow(w.boxBounds[box], s.skin[b] + s.reach[b]);
                for (uint32_t a = 0; a < n; ++a) {
                    if (a == b) continue;
                    const BodyRecord& A = w.bodies[a];
                    const float margin = marginOf(w, A, B);
                    for (uint32_t node = A.firstBox * 8; node < (A.firstBox + A.boxCount) * 8;
                         ++node)
                        if (SpatialHash::cubeMeets(w.nodes[node], s.reach[a], grown))
                            testBox(b, box, a, node, w.nodes[node], margin);
                }
            }
        }
        emitBoxPairs();
        sortContacts(out, s.sortKeys, s.sortScratch);
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
    s.partnerMark.assign(n, 0);
    s.partnerMargin.resize(n);
    constexpr uint32_t kIndividual = 8; // partners' bounds tested one by one up to this many
    // Body b's partners: their reach and query bounds, one by one or as unions.
    bool individual = true;
    Aabb reachUnion, queryUnion;
    auto gatherPartners = [&](uint32_t b) {
        s.partnerBounds.clear();
        s.partnerQueryBounds.clear();
        if (enhanced) {
            for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k) {
                s.partnerBounds.push_back(s.reachBounds[s.partners[k]]);
                s.partnerQueryBounds.push_back(s.queryBounds[s.partners[k]]);
            }
            individual = s.partnerBounds.size() <= kIndividual;
        } else {
            individual = n - 1 <= kIndividual;
            for (uint32_t a = 0; individual && a < n; ++a)
                if (a != b) {
                    s.partnerBounds.push_back(s.reachBounds[a]);
                    s.partnerQueryBounds.push_back(s.queryBounds[a]);
                }
        }
        reachUnion = queryUnion = Aabb{};
        if (individual) return;
        if (enhanced) {
            for (const Aabb& a : s.partnerBounds) reachUnion.add(a);
            for (const Aabb& a : s.partnerQueryBounds) queryUnion.add(a);
        } else {
            reachUnion = s.prefixBounds[b], reachUnion.add(s.suffixBounds[b + 1]);
            queryUnion = s.prefixQueryBounds[b], queryUnion.add(s.suffixQueryBounds[b + 1]);
        }
    };
    auto near = [&](const Aabb& grown, const std::vector<Aabb>& each, const Aabb& all) {
        if (!individual) return grown.overlaps(all);
        for (const Aabb& a : each)
            if (grown.overlaps(a)) return true;
        return false;
    };
    constexpr uint8_t kQuery = 1, kHash = 2;
    s.boxFlags.resize(w.boxBounds.size());
    size_t nodeCount = 0;
    float cell = 0;
    for (uint32_t b = 0; b < n; ++b) {
        if (!isCandidate(b)) continue;
        const BodyRecord& B = w.bodies[b];
        cell = maxNum(cell, B.cellSize);
        gatherPartners(b);
        for (uint32_t box = B.firstBox; box < B.firstBox + B.boxCount; ++box) {
            const Aabb& bb = w.boxBounds[box];
            // Queried when its query bounds meet a partner's nodes' cubes; hashed when its
            // nodes' cubes meet a partner's query bounds.
            const bool query = near(grow(bb, s.skin[b] + s.reach[b]), s.partnerBounds, reachUnion);
            const bool hash = near(grow(bb, s.reach[b]), s.partnerQueryBounds, queryUnion);
            s.boxFlags[box] = uint8_t((query ? kQuery : 0) | (hash ? kHash : 0));
            if (hash) nodeCount += 8;
        }
    }
    if (nodeCount == 0) return;
    s.hash.begin(nodeCount, cell, s.reach, kReachAllowance * cell);
    for (uint32_t b = 0; b < n; ++b) {
        if (!isCandidate(b)) continue;
        const BodyRecord& r = w.bodies[b];
        for (uint32_t box = r.firstBox; box < r.firstBox + r.boxCount; ++box)
            if (s.boxFlags[box] & kHash)
                for (uint32_t node = box * 8; node < box * 8 + 8; ++node)
                    // The position too: no random reads later.
                    s.hash.add(node, b, w.nodes[node]);
    }
    s.hash.reserveTable(s.hash.stagedCount()); // nodes of fast bodies lie in several cells
    s.hash.build();
    for (uint32_t b = 0; b < n; ++b) {
        if (!isCandidate(b)) continue;
        const BodyRecord& B = w.bodies[b];
        // Each partner's margin against b's boxes (every other object's for `previous`).
        if (enhanced) {
            for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k) {
                const uint32_t a = s.partners[k];
                s.partnerMark[a] = 1;
                s.partnerMargin[a] = marginOf(w, w.bodies[a], B);
            }
        } else {
            for (uint32_t a = 0; a < n; ++a)
                if (a != b) s.partnerMargin[a] = marginOf(w, w.bodies[a], B);
        }
        for (uint32_t box = B.firstBox; box < B.firstBox + B.boxCount; ++box) {
            if (!(s.boxFlags[box] & kQuery)) continue;
            const Aabb grown = grow(w.boxBounds[box], s.skin[b] + s.reach[b]);
            s.hash.forEachNear(grown, b, [&](const SpatialHash::Entry& e) {
                if (!enhanced || s.partnerMark[e.owner])
                    testBox(b, box, e.owner, e.item, e.position, s.partnerMargin[e.owner]);
            });
        }
        if (enhanced)
            for (uint32_t k = s.partnerStart[b]; k < s.partnerStart[b + 1]; ++k)
                s.partnerMark[s.partners[k]] = 0;
    }
    emitBoxPairs();
    sortContacts(out, s.sortKeys, s.sortScratch);
}

void findAllObjectContacts(WorldData& w) {
    CollisionState& s = w.collision;
    findObjectContacts(w, w.settings.mode, s.all, w.profile.potentialPairs);
    std::swap(s.claims, s.nextClaims);
    s.objectCount = s.all.size();
    w.profile.contacts = int(s.objectCount);
}

void respondBeforeMove(WorldData& w, float dt) {
    CollisionState& s = w.collision;
    if (s.all.empty()) return;
    const int iterations = w.settings.solverIterations;
    solveContactPositions(s.all, w.x, {}, w.invMass, dt, iterations, w.bodies.size(), s.solver);
    const float impact = 2.0f * length(w.settings.gravity) * dt;
    solveRigidPhase(s.all, s.rigid, s.rigidPoints, w.x, w.v, w.invMass, s.bodyFirstParticle,
                    s.bodyParticleCount, dt, impact, w.settings.maxSeparationSpeed, iterations,
                    s.impacts);
}

float respondAfterMove(WorldData& w, float dt) {
    CollisionState& s = w.collision;
    if (s.all.empty()) return 0;
    const int iterations = w.settings.solverIterations;
    const float impact = 2.0f * length(w.settings.gravity) * dt;
    solveContactPositions(s.all, w.x, w.v, w.invMass, dt, iterations, w.bodies.size(), s.solver);
    return solveContactVelocities(s.all, w.x, w.v, w.invMass, dt, impact, iterations,
                                  w.bodies.size(), s.solver);
}

} // namespace ffd::detail
