// The contact queries (ffdaabb/queries.h): each substep's contacts summed per body pair over the
// step, the pairs' begin and end events against the step before.
//
// The contacts of a substep come in a canonical order (object contacts by A's node, then the
// floor's by body), so a pair's contacts mostly follow each other: a substep adds one run per
// stretch of a pair's contacts, and the step's end sorts the runs by pair and adds them up in
// the order they came. Nothing depends on the thread count, and a step pays one pass over its
// contacts per substep and a sort of the runs.
#include "ffdaabb/error.h"
#include "ffdaabb/queries.h"
#include "world/world_data.h"

#include <algorithm>
#include <string>

namespace ffd {

namespace detail {

namespace {

constexpr uint32_t kFloor = UINT32_MAX;

uint64_t pairKey(uint32_t a, uint32_t b) {
    return (uint64_t(a) << 32) | b;
}

// A body's dense index now, or kFloor for a null handle (the floor); false for a removed body.
bool denseNow(const WorldData& w, BodyId id, uint32_t& out) {
    if (id.isNull()) {
        out = kFloor;
        return true;
    }
    if (!w.find(id)) return false;
    out = w.slots[id.index].dense;
    return true;
}

} // namespace

void tallyContacts(WorldData& w) {
    ContactTally& t = w.contactTally;
    size_t current = SIZE_MAX;
    uint64_t currentKey = 0;
    for (const Contact& c : w.collision.all) {
        const uint32_t a = c.bodyA, b = c.hasB ? c.bodyB : kFloor;
        const bool flip = b < a; // the pair's A is the contact's B
        const uint64_t key = flip ? pairKey(b, a) : pairKey(a, b);
        if (current == SIZE_MAX || key != currentKey) {
            current = t.runs.size();
            currentKey = key;
            t.runs.push_back(ContactRun{key, 0, 0, 0, 0, 0});
        }
        ContactRun& run = t.runs[current];
        const float impulse = c.totalNormalImpulse();
        const double onA = flip ? -double(impulse) : double(impulse);
        run.impulse += double(impulse);
        run.vx += onA * double(c.normal.x);
        run.vy += onA * double(c.normal.y);
        run.vz += onA * double(c.normal.z);
        ++run.count;
    }
}

void finishContactTally(WorldData& w) {
    ContactTally& t = w.contactTally;
    t.previous.swap(t.pairs);
    t.pairs.clear();
    t.pairKeys.clear();

    // The step's pairs: runs sorted by pair, each pair's runs added in the order they came.
    t.sortKeys.resize(t.runs.size());
    for (size_t i = 0; i < t.runs.size(); ++i) t.sortKeys[i] = {t.runs[i].key, uint32_t(i)};
    std::sort(t.sortKeys.begin(), t.sortKeys.end());
    for (size_t i = 0; i < t.sortKeys.size();) {
        const uint64_t key = t.sortKeys[i].first;
        double impulse = 0, vx = 0, vy = 0, vz = 0;
        uint32_t count = 0;
        for (; i < t.sortKeys.size() && t.sortKeys[i].first == key; ++i) {
            const ContactRun& run = t.runs[t.sortKeys[i].second];
            impulse += run.impulse, vx += run.vx, vy += run.vy, vz += run.vz;
            count += run.count;
        }
        ContactPair p;
        p.bodyA = w.handleOf(uint32_t(key >> 32));
        const uint32_t b = uint32_t(key);
        if (b != kFloor) p.bodyB = w.handleOf(b);
        p.normalImpulse = float(impulse);
        p.impulse = Vec3{float(vx), float(vy), float(vz)};
        p.contactCount = count;
        t.pairs.push_back(p);
        t.pairKeys.push_back(key);
    }
    t.runs.clear();

    // Pairs at rest: a sleeping body makes no contacts with the floor or another sleeper, yet
    // it still lies on them. The previous step's pair of such bodies goes on as it was (no end
    // event when bodies fall asleep, and what a sleeper touches and bears stays known).
    std::vector<std::pair<uint64_t, ContactPair>> resting;
    for (const ContactPair& p : t.previous) {
        uint32_t a = 0, b = 0;
        if (!denseNow(w, p.bodyA, a) || !denseNow(w, p.bodyB, b)) continue;
        const bool floor = p.bodyB.isNull();
        // (A sleeper on a static or still kinematic body is such a pair too.)
        const detail::CollisionBody& A = w.collision.bodies[a];
        if (floor ? !A.asleep
                  : !(A.immovable && w.collision.bodies[b].immovable &&
                      (A.asleep || w.collision.bodies[b].asleep)))
            continue;
        const uint64_t key = floor ? pairKey(a, b) : pairKey(std::min(a, b), std::max(a, b));
        if (!std::binary_search(t.pairKeys.begin(), t.pairKeys.end(), key))
            resting.push_back({key, p});
    }
    if (!resting.empty()) {
        std::sort(resting.begin(), resting.end(),
                  [](const auto& x, const auto& y) { return x.first < y.first; });
        std::vector<ContactPair> pairs;
        std::vector<uint64_t> keys;
        size_t i = 0, j = 0;
        while (i < t.pairs.size() || j < resting.size()) {
            if (j == resting.size() || (i < t.pairs.size() && t.pairKeys[i] < resting[j].first)) {
                pairs.push_back(t.pairs[i]);
                keys.push_back(t.pairKeys[i++]);
            } else {
                pairs.push_back(resting[j].second);
                keys.push_back(resting[j++].first);
            }
        }
        t.pairs.swap(pairs);
        t.pairKeys.swap(keys);
    }

    // Events: the previous step's pairs named by their bodies' places now (bodies removed since
    // end their pairs), against this step's.
    t.begin.clear();
    t.end.clear();
    t.scratch.clear();
    for (const ContactPair& p : t.previous) {
        uint32_t a = 0, b = 0;
        const bool alive = denseNow(w, p.bodyA, a) && denseNow(w, p.bodyB, b);
        if (alive) t.scratch.push_back(pairKey(std::min(a, b), std::max(a, b)));
        if (!alive || !std::binary_search(t.pairKeys.begin(), t.pairKeys.end(),
                                          pairKey(std::min(a, b), std::max(a, b))))
            t.end.push_back({p.bodyA, p.bodyB});
    }
    std::sort(t.scratch.begin(), t.scratch.end());
    for (size_t i = 0; i < t.pairs.size(); ++i)
        if (!std::binary_search(t.scratch.begin(), t.scratch.end(), t.pairKeys[i]))
            t.begin.push_back({t.pairs[i].bodyA, t.pairs[i].bodyB});
}

} // namespace detail

std::span<const ContactPair> contactPairs(const World& world) {
    return detail::dataOf(world).contactTally.pairs;
}

void touchingBodies(const World& world, BodyId body, std::vector<BodyContact>& out) {
    out.clear();
    const detail::WorldData& w = detail::dataOf(world);
    if (!w.find(body))
        throw InputError("body", "stale or invalid body handle (index " +
                                     std::to_string(body.index) + ", generation " +
                                     std::to_string(body.generation) + ")");
    for (const ContactPair& p : w.contactTally.pairs) {
        if (p.bodyA == body)
            out.push_back({p.bodyB, p.normalImpulse, p.impulse, p.contactCount});
        else if (p.bodyB == body)
            out.push_back({p.bodyA, p.normalImpulse, -p.impulse, p.contactCount});
    }
}

ContactEvents contactEvents(const World& world) {
    const detail::ContactTally& t = detail::dataOf(world).contactTally;
    return {t.begin, t.end};
}

} // namespace ffd
