// sphere_test, phase 1: each body's bounding sphere and the candidate pairs, by all pairs or by
// sort-and-sweep on x (collision/pipeline.h).
// Reference: Jeon, Choi, Hong, "Enhanced FFD-AABB Collision Algorithm for Deformable Objects",
// 2012 (the bounding-sphere test).
#include "collision/margins.h"
#include "collision/overlap_recovery.h"
#include "collision/pipeline.h"

#include <algorithm>
#include <cmath>

namespace ffd::detail {

namespace {

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

void sphereTestAllPairs(CollisionWorld& w, std::vector<CandidatePair>& out) {
    out.clear();
    const uint32_t n = uint32_t(w.bodies.size());
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = i + 1; j < n; ++j)
            if (!bothImmovable(w, i, j) && spheresOverlap(w, i, j)) out.push_back({i, j});
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
    std::vector<std::array<float, 4>>& across = w.collision.sweepAcross;
    across.resize(n);
    // Each body's extents: its sphere grown by its own share of the largest margin
    // (sweepMargin), so two spheres that pass the test always have overlapping extents along
    // every axis, however uneven their particles' velocities. The extents are padded by a
    // little more than the rounding of either computation can shift them. The sweep runs along
    // x; the extents along y and z reject most of the pairs it meets before their spheres are
    // tested (on a floor of 19 x 18 columns, a body's x extent meets the bodies of a whole
    // column of rows).
    for (uint32_t i = 0; i < n; ++i) {
        const CollisionBody& r = w.bodies[i];
        const float half = r.sphereRadius + sweepMargin(w, r);
        auto extent = [&](float centre, float& from, float& to) {
            const float pad = 1e-5f * (half + std::abs(centre));
            from = centre - half - pad;
            to = centre + half + pad;
        };
        order[i] = i;
        extent(r.sphereCentre.x, lo[i], hi[i]);
        extent(r.sphereCentre.y, across[i][0], across[i][1]);
        extent(r.sphereCentre.z, across[i][2], across[i][3]);
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
            const std::array<float, 4>& a = across[i];
            for (size_t m = k + 1; m < n && lo[order[m]] <= hi[i]; ++m) {
                const uint32_t j = order[m];
                const std::array<float, 4>& b = across[j];
                if (b[0] > a[1] || a[0] > b[1] || b[2] > a[3] || a[2] > b[3]) continue;
                if (!bothImmovable(w, i, j) && spheresOverlap(w, i, j))
                    pairs.push_back({std::min(i, j), std::max(i, j)});
            }
        }
    });
    for (size_t c = 0; c < chunks; ++c) out.insert(out.end(), found[c].begin(), found[c].end());
    std::sort(out.begin(), out.end(), [](const CandidatePair& a, const CandidatePair& b) {
        return a.a < b.a || (a.a == b.a && a.b < b.b);
    });
}

void computeSphere(CollisionWorld& w, size_t i) {
    // The centre of the node bounds, the radius to the farthest corner of any box's bounds.
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

void computeSpheres(CollisionWorld& w) {
    w.workers.forRange(w.bodies.size(), [&](size_t first, size_t last, int) {
        for (size_t i = first; i < last; ++i)
            if (!w.bodies[i].asleep) computeSphere(w, i);
    });
}

void sphereTestPairs(CollisionWorld& w, std::vector<CandidatePair>& out) {
    if (int(w.bodies.size()) > w.settings.sweepThreshold)
        sphereTestSweep(w, out);
    else
        sphereTestAllPairs(w, out);
}

void sphereTest(CollisionWorld& w) {
    computeSpheres(w);
    CollisionState& s = w.collision;
    sphereTestPairs(w, s.pairs);
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

} // namespace ffd::detail
