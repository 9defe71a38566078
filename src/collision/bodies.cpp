// node_update and the collision's lookups: box nodes and bounds from the particles, each body's
// bounds and motion (collision/pipeline.h).
#include "collision/pipeline.h"

#include <algorithm>
#include <cmath>

namespace ffd::detail {

void rebuildCollisionTopology(CollisionWorld& w) {
    CollisionState& s = w.collision;
    const size_t boxes = w.boxBounds.size();
    s.boxBody.resize(boxes);
    s.nodeBody.resize(boxes * 8);
    s.boxParticles.resize(boxes);
    s.planes.resize(boxes);
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const CollisionBody& r = w.bodies[b];
        for (uint32_t k = r.firstBox; k < r.firstBox + r.boxCount; ++k) {
            s.boxBody[k] = b;
            for (int n = 0; n < 8; ++n) s.nodeBody[size_t(k) * 8 + n] = b;
            const auto& corners = r.lattice->cellParticles[r.lattice->boxes[k - r.firstBox].cell];
            for (int n = 0; n < 8; ++n) s.boxParticles[k][n] = r.firstParticle + corners[n];
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
        // A body of infinite mass in the view (static, kinematic): weighted by its mass fractions.
        const bool infinite = w.invMass[r.firstParticle] == 0;
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i) {
            speed2 = maxNum(speed2, lengthSquared(w.v[i]));
            const float m = infinite ? r.massFraction[i - r.firstParticle] : 1.0f / w.invMass[i];
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

} // namespace ffd::detail
