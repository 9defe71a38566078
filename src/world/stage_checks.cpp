#include "world/stage_checks.h"

#include "world/world_data.h"

#include <cmath>
#include <span>

namespace ffd::detail {

namespace {

std::string firstNonFinite(std::span<const Vec3> values, const char* what) {
    for (size_t i = 0; i < values.size(); ++i)
        if (!isFinite(values[i]))
            return std::string(what) + " " + std::to_string(i) + " is not finite";
    return {};
}

bool inside(const Aabb& outer, const Aabb& inner) {
    return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
           inner.hi.x <= outer.hi.x && inner.hi.y <= outer.hi.y && inner.hi.z <= outer.hi.z;
}

} // namespace

std::string particleProblem(const WorldData& w) {
    std::string p = firstNonFinite(w.x, "particle position");
    return p.empty() ? firstNonFinite(w.v, "particle velocity") : p;
}

std::string nodeProblem(const WorldData& w) {
    if (w.collision.bodies.size() != w.bodies.size())
        return "the collision state has " + std::to_string(w.collision.bodies.size()) +
               " bodies, the world " + std::to_string(w.bodies.size());
    if (std::string p = firstNonFinite(w.nodes, "box node"); !p.empty()) return p;
    for (size_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& r = w.bodies[b];
        for (uint32_t k = r.firstBox; k < r.firstBox + r.boxCount; ++k) {
            for (int n = 0; n < 8; ++n)
                if (!w.boxBounds[k].contains(w.nodes[size_t(k) * 8 + n], 0.0f))
                    return "node " + std::to_string(n) + " of box " + std::to_string(k) +
                           " is outside the box's bounds";
            if (!inside(w.collision.bodies[b].bounds, w.boxBounds[k]))
                return "box " + std::to_string(k) + " is outside the bounds of body " +
                       std::to_string(b);
        }
    }
    return {};
}

std::string sphereProblem(const WorldData& w) {
    const auto& pairs = w.collision.pairs;
    const size_t n = w.bodies.size();
    for (size_t i = 0; i < pairs.size(); ++i) {
        const CandidatePair& p = pairs[i];
        if (!(p.a < p.b && p.b < n))
            return "pair " + std::to_string(i) + " (" + std::to_string(p.a) + ", " +
                   std::to_string(p.b) + ") is not two bodies a < b";
        if (i > 0 && !(pairs[i - 1].a < p.a || (pairs[i - 1].a == p.a && pairs[i - 1].b < p.b)))
            return "pair " + std::to_string(i) + " is out of order or repeated";
    }
    for (size_t b = 0; b < n; ++b) {
        if (!w.collision.isCandidate[b]) continue;
        const CollisionBody& c = w.collision.bodies[b];
        const float reach = c.sphereRadius * (1 + 1e-5f) + 1e-6f;
        for (uint32_t box = c.firstBox; box < c.firstBox + c.boxCount; ++box) {
            const Aabb& a = w.boxBounds[box];
            for (int k = 0; k < 8; ++k) {
                const Vec3 corner{(k & 1) ? a.hi.x : a.lo.x, (k & 2) ? a.hi.y : a.lo.y,
                                  (k & 4) ? a.hi.z : a.lo.z};
                if (!(length(corner - c.sphereCentre) <= reach))
                    return "the bounding sphere of body " + std::to_string(b) +
                           " misses a corner of box " + std::to_string(box);
            }
        }
    }
    return {};
}

std::string meshProblem(const WorldData& w) {
    return firstNonFinite(w.vertices, "mesh vertex");
}

} // namespace ffd::detail
