// Sleeping: quiet islands fall asleep after a frame, sleeping bodies within an awake body's
// reach wake before one (world/sleeping.h).
#include "world/sleeping.h"

#include "collision/overlap_recovery.h"
#include "collision/pipeline.h"
#include "world/stages.h"
#include "world/world_data.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ffd::detail {

namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t b) {
    while (parent[b] != b) b = parent[b] = parent[parent[b]];
    return b;
}

void join(std::vector<uint32_t>& parent, uint32_t a, uint32_t b) {
    a = findRoot(parent, a), b = findRoot(parent, b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b); // the lowest index is the root
}

} // namespace

void refreshAwake(WorldData& w) {
    w.awake.clear();
    w.kinematic.clear();
    w.sleeping = 0;
    w.contactInvMass.resize(w.invMass.size());
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& r = w.bodies[b];
        const bool dynamic = r.settings.motion == BodyMotion::Dynamic;
        if (!r.asleep && dynamic) w.awake.push_back(b);
        if (r.settings.motion == BodyMotion::Kinematic) w.kinematic.push_back(b);
        w.sleeping += r.asleep;
        const auto first = w.invMass.begin() + r.firstParticle;
        const auto to = w.contactInvMass.begin() + r.firstParticle;
        if (r.asleep || !dynamic)
            std::fill(to, to + r.particleCount, 0.0f);
        else
            std::copy(first, first + r.particleCount, to);
        w.collision.bodies[b].asleep = r.asleep;
        w.collision.bodies[b].immovable = r.asleep || !dynamic;
    }
    rebuildDynamicsBatches(w);
}

namespace {

// wakeIsland without refreshAwake (one refresh serves many islands).
bool wakeWithoutRefresh(WorldData& w, uint32_t dense) {
    BodyRecord& body = w.bodies[dense];
    body.quietTime = 0;
    if (!body.asleep) return false;
    const uint32_t island = body.island;
    for (BodyRecord& r : w.bodies) {
        if (!r.asleep || (&r != &body && (island == 0 || r.island != island))) continue;
        r.asleep = false;
        r.island = 0;
        r.quietTime = 0;
        r.halfKick = true; // at rest: its velocity was just set (to 0)
    }
    return true;
}

} // namespace

bool wakeIsland(WorldData& w, uint32_t dense) {
    if (!wakeWithoutRefresh(w, dense)) return false;
    refreshAwake(w);
    return true;
}

void wakeEverybody(WorldData& w) {
    if (w.sleeping == 0) return;
    for (BodyRecord& r : w.bodies)
        if (r.asleep) r.asleep = false, r.island = 0, r.quietTime = 0, r.halfKick = true;
    refreshAwake(w);
}

namespace {

// putToSleep without refreshAwake (one refresh serves many islands).
void sleepIsland(WorldData& w, const uint32_t* bodies, uint32_t count) {
    const uint32_t island = w.nextIsland++;
    if (w.nextIsland == 0) w.nextIsland = 1;
    CollisionWorld view = collisionView(w); // the awake inverse masses: nodes before the flag
    for (uint32_t k = 0; k < count; ++k) {
        const uint32_t b = bodies[k];
        BodyRecord& r = w.bodies[b];
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i) {
            w.v[i] = {};
            w.rotationSteps[i] = Quat{};
        }
        r.asleep = true;
        r.island = island;
        r.quietTime = 0;
        updateNodes(view, b, b + 1); // no motion, and the nodes of the positions it keeps
        computeSphere(view, b);
    }
}

} // namespace

void putToSleep(WorldData& w, const uint32_t* bodies, uint32_t count) {
    if (count == 0) return;
    sleepIsland(w, bodies, count);
    refreshAwake(w);
}

namespace {

// What a body is to the sleeping: asleep, awake (dynamic), a collider that does not move in the
// frame (static, or kinematic and still: nobody's reason to stay awake or to wake) or a moving
// kinematic body (a reason to stay awake and to wake, like an awake body).
enum Role : uint8_t { Sleeper, Awake, Still, Moving };

// Each body's reach in a frame: a sleeping body's bounds grown by its skin; an awake body's
// grown by twice what it can travel in the frame under gravity from its fastest particle's
// speed (its bounds are a substep old), and by its skin; a collider's by its skin and, moving,
// twice what it travels. Calls fn(i, j) for each pair of bodies whose reaches overlap, one of
// them at least awake or moving (sort and sweep on x, in a fixed order).
template <class F>
void forBodiesWithinReach(WorldData& w, const std::vector<Role>& role, F&& fn) {
    const WorldSettings& s = w.settings;
    const size_t n = w.bodies.size();
    const float T = s.frameStep;
    const float fall = length(s.gravity) * T;
    std::vector<Aabb> extent(n);
    std::vector<uint32_t> order(n);
    for (uint32_t b = 0; b < n; ++b) {
        const BodyRecord& r = w.bodies[b];
        const CollisionBody& c = w.collision.bodies[b];
        float grow = s.contactSkin * r.cellSize;
        if (role[b] == Awake || role[b] == Moving) {
            float speed2 = 0;
            for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i)
                speed2 = maxNum(speed2, lengthSquared(w.v[i]));
            grow += 2.0f * T * (std::sqrt(speed2) + (role[b] == Awake ? fall : 0.0f));
        }
        extent[b] = {c.bounds.lo - Vec3{grow, grow, grow}, c.bounds.hi + Vec3{grow, grow, grow}};
        order[b] = b;
    }
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return extent[a].lo.x < extent[b].lo.x || (extent[a].lo.x == extent[b].lo.x && a < b);
    });
    auto active = [&](uint32_t b) { return role[b] == Awake || role[b] == Moving; };
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = order[k];
        for (size_t m = k + 1; m < n && extent[order[m]].lo.x <= extent[i].hi.x; ++m) {
            const uint32_t j = order[m];
            if ((active(i) || active(j)) && extent[i].overlaps(extent[j]))
                fn(std::min(i, j), std::max(i, j));
        }
    }
}

// Every body's role in the step in progress (the kinematic bodies given a motion for it are
// WorldData::moving).
std::vector<Role> roles(const WorldData& w) {
    std::vector<Role> role(w.bodies.size());
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& r = w.bodies[b];
        role[b] = r.asleep ? Sleeper : r.settings.motion == BodyMotion::Dynamic ? Awake : Still;
    }
    for (const uint32_t b : w.moving) role[b] = Moving;
    return role;
}

} // namespace

void wakeWithinReach(WorldData& w) {
    const WorldSettings& s = w.settings;
    if (s.sleepSpeed > 0) w.frameStartX.assign(w.x.begin(), w.x.end());
    const size_t n = w.bodies.size();
    if (w.sleeping == 0) return;
    if (s.sleepSpeed == 0) { // sleeping was turned off (World::setSettings wakes everybody)
        wakeEverybody(w);
        return;
    }
    std::vector<uint8_t> reached(n, 0);
    const std::vector<Role> role = roles(w);
    forBodiesWithinReach(w, role, [&](uint32_t i, uint32_t j) {
        if (role[i] == Sleeper && role[j] != Still) reached[i] = 1;
        if (role[j] == Sleeper && role[i] != Still) reached[j] = 1;
    });
    bool woke = false;
    for (uint32_t b = 0; b < n; ++b)
        if (reached[b] && w.bodies[b].asleep) woke = wakeWithoutRefresh(w, b) || woke;
    if (woke) refreshAwake(w);
}

void fallAsleep(WorldData& w) {
    const WorldSettings& s = w.settings;
    if (s.sleepSpeed == 0 || w.awake.empty()) return;
    const float T = s.frameStep;
    const float limit2 = s.sleepSpeed * s.sleepSpeed;
    const float invT2 = 1.0f / (T * T);
    // Quiet times, body by body (each its own: any split of the bodies gives the same result).
    std::vector<uint8_t> candidate(w.bodies.size(), 0);
    w.workers.forRange(w.awake.size(), [&](size_t first, size_t last, int) {
        for (size_t k = first; k < last; ++k) {
            const uint32_t b = w.awake[k];
            BodyRecord& r = w.bodies[b];
            float speed2 = 0, motion2 = 0;
            for (uint32_t p = 0; p < r.particleCount; ++p) {
                const uint32_t i = r.firstParticle + p;
                const float f = r.model->lattice.massFraction[p];
                speed2 += f * lengthSquared(w.v[i]);
                motion2 += f * lengthSquared(w.x[i] - w.frameStartX[i]);
            }
            const bool quiet = r.settings.allowSleep && speed2 < limit2 && motion2 * invT2 < limit2;
            r.quietTime = quiet ? r.quietTime + T : 0.0f;
            candidate[b] = quiet && r.quietTime >= s.sleepTime;
        }
    });
    if (std::find(candidate.begin(), candidate.end(), 1) == candidate.end()) return;
    // Islands of the awake bodies within reach of each other (forBodiesWithinReach: the
    // relation that wakes a sleeping body, so that no two quiet neighbours keep waking each
    // other) or in contact in the last substep. An island sleeps when every body of it is a
    // candidate; one within reach of a sleeping body (to be woken before the next frame) or
    // recovering from a placed overlap does not.
    std::vector<uint32_t>& parent = w.islandParent;
    parent.resize(w.bodies.size());
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<uint8_t> blocked(w.bodies.size(), 0);
    const std::vector<Role> role = roles(w);
    // Two awake bodies join; an awake body beside a sleeper or a moving collider is blocked;
    // a still collider is nobody's neighbour.
    auto link = [&](uint32_t a, uint32_t b) {
        const Role ra = role[a], rb = role[b];
        if (ra == Awake && rb == Awake)
            join(parent, a, b);
        else if (ra == Awake && (rb == Sleeper || rb == Moving))
            blocked[a] = 1;
        else if (rb == Awake && (ra == Sleeper || ra == Moving))
            blocked[b] = 1;
    };
    forBodiesWithinReach(w, role, link);
    for (const Contact& c : w.collision.objectContacts())
        if (c.hasB) link(c.bodyA, c.bodyB);
    for (const OverlapPair& p : w.collision.overlaps) {
        blocked[p.a] = 1;
        if (p.b != kFloorBody) blocked[p.b] = 1;
    }
    std::vector<uint8_t> ready(w.bodies.size(), 1);
    for (const uint32_t b : w.awake) {
        const uint32_t root = findRoot(parent, b);
        if (!candidate[b] || blocked[b]) ready[root] = 0;
    }
    // The ready islands' bodies, island by island (by their lowest body), each in body order.
    std::vector<std::pair<uint32_t, uint32_t>> members; // (root, body)
    for (const uint32_t b : w.awake) {
        const uint32_t root = findRoot(parent, b);
        if (ready[root]) members.push_back({root, b});
    }
    if (members.empty()) return;
    std::stable_sort(members.begin(), members.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<uint32_t> island;
    for (size_t k = 0; k < members.size();) {
        island.clear();
        const uint32_t root = members[k].first;
        for (; k < members.size() && members[k].first == root; ++k)
            island.push_back(members[k].second);
        sleepIsland(w, island.data(), uint32_t(island.size()));
    }
    refreshAwake(w);
}

} // namespace ffd::detail
