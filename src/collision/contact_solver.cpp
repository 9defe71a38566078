// Contact response on lattice particles: a rigid phase on the bodies' rigid modes, position
// projection with velocities following, then friction and restitution; Gauss-Seidel over the
// contacts in a fixed order.
// References: Mueller, Heidelberger, Hennix, Ratcliff, "Position Based Dynamics", 2006;
// E. Catto, Box2D (speculative contacts, accumulated impulses with clamping).
#include "collision/contact.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ffd::detail {

namespace {

// A point's particles and trilinear weights with the weights in vector lanes (0-3, 4-7): the
// products of trilinearWeights, in the same order.
struct Point4 {
    const uint32_t* particle = nullptr;
    F4 weight[2];
};
Point4 point4(const ContactPoint& p, std::span<const BoxParticles> boxes) {
    const float s = p.local.x, t = p.local.y, u = p.local.z;
    const float s0 = 1 - s, t0 = 1 - t, u0 = 1 - u;
    const F4 st = F4{s0, s, s0, s} * F4{t0, t0, t, t};
    return {boxes[p.box].data(), {st * u0, st * u}};
}

// The sweeps' particles (SolverScratch::x4, v4): `values` copied into 4-lane vectors, and back.
// Lane by lane the vector operations below are the Vec3 ones (Vec3 has no fused or reordered
// arithmetic either), so the results are bit for bit those of sweeps on Vec3, and a point's
// blend and push are a load, a multiply and an add per particle instead of three of each, with
// each particle's store and the next sweep's load of it the same 16 bytes.
void toLanes(std::span<const Vec3> values, std::vector<F4>& out, Workers& workers) {
    out.resize(values.size());
    workers.forRange(values.size(), [&](size_t first, size_t last, int) {
        for (size_t i = first; i < last; ++i) out[i] = F4{values[i].x, values[i].y, values[i].z, 0};
    });
}
void fromLanes(std::span<const F4> lanes, std::span<Vec3> out, Workers& workers) {
    workers.forRange(out.size(), [&](size_t first, size_t last, int) {
        for (size_t i = first; i < last; ++i) out[i] = {lanes[i][0], lanes[i][1], lanes[i][2]};
    });
}
Vec3 toVec3(F4 v) {
    return {v[0], v[1], v[2]};
}
// dot(toVec3(v), n), the same sum.
float dot(F4 v, Vec3 n) {
    return v[0] * n.x + v[1] * n.y + v[2] * n.z;
}
F4 lanes(Vec3 v) {
    return F4{v.x, v.y, v.z, 0};
}

// blend() on vector lanes.
F4 blend4(const Point4& p, const F4* values) {
    F4 r{};
    for (int h = 0; h < 2; ++h)
        for (int k = 0; k < 4; ++k) r += values[p.particle[4 * h + k]] * p.weight[h][k];
    return r;
}

// A contact's points (b only when it has one) and its constraint (pA - pB) . n - offset on the
// positions in lanes: separation() in the same arithmetic.
float separation4(const Contact& c, std::span<const BoxParticles> boxes, const F4* x, Point4& a,
                  Point4& b) {
    a = point4(c.a, boxes);
    F4 d = blend4(a, x);
    if (c.hasB) {
        b = point4(c.b, boxes);
        d -= blend4(b, x);
    }
    return dot(d, c.normal) - c.offset;
}

// Moves the point by `delta`, generalised-inverse-mass weighted: each particle by `delta` times
// its share (its weight over its mass, shares()).
void push4(const Point4& p, F4* values, const float* share, F4 delta) {
    for (int k = 0; k < 8; ++k) values[p.particle[k]] += delta * share[k];
}
void shares(const Point4& p, const float* invMass, float* share) {
    for (int h = 0; h < 2; ++h)
        for (int k = 0; k < 4; ++k)
            share[4 * h + k] = p.weight[h][k] * invMass[p.particle[4 * h + k]];
}

// Calls fn(z) for the zones z of block `block` of the schedule whose subset [zoneStart[z],
// end[z]) is not empty (`end`: the schedule's zoneStart shifted by one, or a subset's ends):
// colour after colour, the block's zones of a colour on the workers.
template <class F>
void forEachZone(const SolverSchedule& schedule, size_t block, std::span<const uint32_t> end,
                 Workers& workers, F&& fn) {
    // A colour with few contacts to visit runs on the calling thread: handing it out would
    // cost more than it saves.
    constexpr uint32_t kParallelWork = 512;
    for (size_t c = 0; c < schedule.colourCount(); ++c) {
        const uint32_t first = schedule.blockZone(block, c),
                       last = schedule.blockZone(block + 1, c);
        if (first == last) continue;
        uint32_t work = 0;
        for (uint32_t z = first; z < last && work < kParallelWork; ++z)
            work += end[z] - schedule.zoneStart[z];
        if (last - first == 1 || workers.count() == 1 || work < kParallelWork) {
            for (uint32_t z = first; z < last; ++z)
                if (schedule.zoneStart[z] < end[z]) fn(z);
            continue;
        }
        // Largest zones first, so that no thread is left with a large one at the end.
        workers.forChunks(last - first, 1, [&](size_t from, size_t to, int) {
            for (size_t k = first + from; k < first + to; ++k) {
                const uint32_t z = schedule.bySize[k];
                if (schedule.zoneStart[z] < end[z]) fn(z);
            }
        });
    }
}

// Calls fn(m) for the positions m of the block's zones' subsets [zoneStart[z], end[z]), each
// zone's in order, the zones as forEachZone visits them: one Gauss-Seidel sweep over a
// selection.
template <class F>
void sweepZones(const SolverSchedule& schedule, size_t block, std::span<const uint32_t> end,
                Workers& workers, F&& fn) {
    forEachZone(schedule, block, end, workers, [&](uint32_t z) {
        for (uint32_t m = schedule.zoneStart[z]; m < end[z]; ++m) fn(m);
    });
}

// Every zone's contacts: its range of the schedule's order.
std::span<const uint32_t> zoneEnds(const SolverSchedule& schedule) {
    return std::span<const uint32_t>(schedule.zoneStart).subspan(1);
}

// Calls fn(z) for every zone z of block `block`, on the workers (in any order): the block's
// zones of each colour one after the other, handed out in one loop (for one block, every zone
// in order).
template <class F>
void inBlock(const SolverSchedule& schedule, size_t block, Workers& workers, F&& fn) {
    auto zonesOf = [&](size_t c) {
        return schedule.blockZone(block + 1, c) - schedule.blockZone(block, c);
    };
    size_t count = 0;
    for (size_t c = 0; c < schedule.colourCount(); ++c) count += zonesOf(c);
    workers.forChunks(count, 4, [&](size_t from, size_t to, int) {
        size_t c = 0, before = 0; // the colour of zone k, and the block's zones before it
        for (size_t k = from; k < to; ++k) {
            while (k - before >= zonesOf(c)) before += zonesOf(c++);
            fn(uint32_t(schedule.blockZone(block, c) + (k - before)));
        }
    });
}

// Keeps, zone by zone on the workers, the contacts of the block's zones for which keep(n)
// holds: zone z's at [zoneStart[z], end[z]) of `kept` (in the schedule's order).
template <class F>
void selectInZones(const SolverSchedule& schedule, size_t block, Workers& workers,
                   std::vector<uint32_t>& kept, std::vector<uint32_t>& end, F&& keep) {
    kept.resize(schedule.order.size());
    end.resize(schedule.zoneCount());
    inBlock(schedule, block, workers, [&](uint32_t z) {
        uint32_t out = schedule.zoneStart[z];
        for (uint32_t m = schedule.zoneStart[z]; m < schedule.zoneStart[z + 1]; ++m)
            if (keep(schedule.order[m])) kept[out++] = schedule.order[m];
        end[z] = out;
    });
}

// The contacts of the block that the later sweeps visit, zone by zone: those whose slack
// (separation, or velocity slack) is under twice the reach of their two bodies (how far the
// first sweep moved them).
void selectReachable(std::span<const Contact> contacts, SolverScratch& s, size_t block,
                     Workers& workers) {
    selectInZones(s.schedule, block, workers, s.active, s.activeEnd, [&](uint32_t n) {
        const Contact& c = contacts[n];
        const float reach = 2.0f * (s.bodyReach[c.bodyA] + (c.hasB ? s.bodyReach[c.bodyB] : 0.0f));
        return s.slack[n] < reach;
    });
}

// The deepest of the block's zones' `deepest`.
float blockDeepest(const SolverSchedule& schedule, size_t block, std::span<const float> deepest) {
    float d = 0;
    for (size_t c = 0; c < schedule.colourCount(); ++c)
        for (uint32_t z = schedule.blockZone(block, c); z < schedule.blockZone(block + 1, c); ++z)
            d = maxNum(d, deepest[z]);
    return d;
}

// The normal's arms, angular responses, inverse masses and effective mass of contact c's
// rigid point p, its points at pa and pb (pb unused for the floor).
void setNormalResponse(const Contact& c, std::span<const RigidState> states, Vec3 pa, Vec3 pb,
                       RigidPoint& p) {
    const RigidState& A = states[c.bodyA];
    p.armA = cross(pa - A.centre, c.normal);
    p.turnA = A.invInertia * p.armA;
    p.invMassA = A.invMass;
    float K = A.invMass + dot(p.armA, p.turnA);
    if (c.hasB) {
        const RigidState& B = states[c.bodyB];
        p.armB = cross(pb - B.centre, c.normal);
        p.turnB = B.invInertia * p.armB;
        p.invMassB = B.invMass;
        K += B.invMass + dot(p.armB, p.turnB);
    } else {
        p.armB = p.turnB = Vec3{};
        p.invMassB = 0;
    }
    p.invK = K > 0 ? 1.0f / K : 0.0f;
}

} // namespace

void makeContactPoint(uint32_t box, Vec3 local, std::span<const BoxParticles> boxes,
                      std::span<const float> invMass, ContactPoint& out, float& outInvMass) {
    out.box = box;
    out.local = local;
    const PointWeights p(out, boxes);
    outInvMass = 0;
    for (int k = 0; k < 8; ++k) outInvMass += p.weight[k] * p.weight[k] * invMass[p.particle[k]];
}

void lowestZoneCell(std::span<const ZoneCell> cells, int32_t& i0, int32_t& k0) {
    i0 = k0 = INT32_MAX;
    for (const ZoneCell& c : cells)
        if (c.i != ZoneCell::kNowhere) i0 = std::min(i0, c.i), k0 = std::min(k0, c.k);
}

uint32_t zoneKey(ZoneCell a, ZoneCell b, int32_t i0, int32_t k0) {
    // The tail, colour 4, is one zone: the contacts between bodies more than a cell apart
    // (which may share bodies with any zone), and blocks beyond the indices' range.
    constexpr int64_t kBlocks = int64_t(1) << kZoneIndexBits;
    const int64_t i = int64_t(std::min(a.i, b.i)) - i0;
    const int64_t k = int64_t(std::min(a.k, b.k)) - k0;
    if (std::abs(int64_t(a.i) - b.i) <= 1 && std::abs(int64_t(a.k) - b.k) <= 1 && i >= 0 &&
        k >= 0 && i < kBlocks && k < kBlocks)
        return uint32_t((i & 1) | (k & 1) << 1) << 2 * kZoneIndexBits |
               uint32_t(i) << kZoneIndexBits | uint32_t(k);
    return kTailZone;
}

void buildSolverSchedule(std::span<const Contact> contacts, std::span<const ZoneCell> cells,
                         SolverSchedule& out, Workers& workers, uint32_t bandContacts) {
    out.order.clear();
    out.zoneStart.clear();
    out.colourStart.clear();
    out.bySize.clear();
    if (contacts.empty()) return;
    int32_t i0, k0;
    lowestZoneCell(cells, i0, k0);
    std::vector<uint32_t>& zoneOf = out.zoneOf;
    zoneOf.resize(contacts.size());
    workers.forRange(contacts.size(), [&](size_t first, size_t last, int) {
        for (size_t n = first; n < last; ++n) {
            const Contact& c = contacts[n];
            zoneOf[n] = zoneKey(cells[c.bodyA], c.hasB ? cells[c.bodyB] : cells[c.bodyA], i0, k0);
        }
    });
    // The zones in key order (few: sorted directly), then the contacts counted into them in
    // their order: a counting sort in fixed chunks of contacts, each chunk counted and placed
    // on a thread.
    constexpr size_t kChunk = 4096;
    const size_t chunks = (contacts.size() + kChunk - 1) / kChunk;
    std::vector<std::vector<uint32_t>>& seen = out.chunkZones;
    if (seen.size() < chunks) seen.resize(chunks);
    workers.forChunks(contacts.size(), kChunk, [&](size_t first, size_t last, int) {
        std::vector<uint32_t>& mine = seen[first / kChunk];
        mine.clear();
        for (size_t n = first; n < last; ++n) // runs of one zone are common: a body's contacts
            if (mine.empty() || mine.back() != zoneOf[n]) mine.push_back(zoneOf[n]);
        std::sort(mine.begin(), mine.end());
        mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
    });
    std::vector<uint32_t>& zones = out.zones;
    zones.clear();
    for (size_t c = 0; c < chunks; ++c) zones.insert(zones.end(), seen[c].begin(), seen[c].end());
    std::sort(zones.begin(), zones.end());
    zones.erase(std::unique(zones.begin(), zones.end()), zones.end());
    const size_t zoneCount = zones.size();
    // count[c * zoneCount + z]: chunk c's contacts in zone z, then where they go.
    std::vector<uint32_t>& count = out.next;
    count.assign(chunks * zoneCount, 0);
    workers.forChunks(contacts.size(), kChunk, [&](size_t first, size_t last, int) {
        uint32_t* mine = count.data() + first / kChunk * zoneCount;
        for (size_t n = first; n < last; ++n) {
            zoneOf[n] =
                uint32_t(std::lower_bound(zones.begin(), zones.end(), zoneOf[n]) - zones.begin());
            ++mine[zoneOf[n]];
        }
    });
    out.zoneStart.assign(zoneCount + 1, 0);
    uint32_t at = 0;
    for (size_t z = 0; z < zoneCount; ++z) {
        out.zoneStart[z] = at;
        for (size_t c = 0; c < chunks; ++c) {
            const uint32_t here = count[c * zoneCount + z];
            count[c * zoneCount + z] = at;
            at += here;
        }
        if (z == 0 || zones[z] >> 2 * kZoneIndexBits != zones[z - 1] >> 2 * kZoneIndexBits)
            out.colourStart.push_back(uint32_t(z));
    }
    out.zoneStart[zoneCount] = at;
    out.colourStart.push_back(uint32_t(zoneCount));
    out.order.resize(contacts.size());
    workers.forChunks(contacts.size(), kChunk, [&](size_t first, size_t last, int) {
        uint32_t* next = count.data() + first / kChunk * zoneCount;
        for (size_t n = first; n < last; ++n) out.order[next[zoneOf[n]]++] = uint32_t(n);
    });
    // The blocks: bands of zone rows of bandContacts contacts or more each (the last may hold
    // fewer), cut before the row after a band reaches it; the tail in the last.
    out.blockStart.clear();
    const size_t colours = out.colourCount();
    if (contacts.size() > bandContacts) {
        auto rowOf = [](uint32_t key) { return key >> kZoneIndexBits & kZoneIndexMask; };
        auto colourOf = [](uint32_t key) { return key >> 2 * kZoneIndexBits; };
        std::vector<uint32_t>& rows = out.next; // contacts per row (count is spent)
        rows.assign(size_t(kZoneIndexMask) + 1, 0);
        for (size_t z = 0; z < zoneCount; ++z)
            if (zones[z] != kTailZone)
                rows[rowOf(zones[z])] += out.zoneStart[z + 1] - out.zoneStart[z];
        std::vector<uint32_t> cuts; // each block's first row after the first
        uint32_t held = 0;
        for (uint32_t r = 0; r < rows.size(); ++r) {
            if (held >= bandContacts && rows[r] > 0) cuts.push_back(r), held = 0;
            held += rows[r];
        }
        if (!cuts.empty()) {
            out.blockStart.resize((cuts.size() + 2) * colours);
            for (size_t c = 0; c < colours; ++c) {
                const uint32_t first = out.colourStart[c], last = out.colourStart[c + 1];
                const uint32_t colour = colourOf(zones[first]);
                out.blockStart[c] = first;
                out.blockStart[(cuts.size() + 1) * colours + c] = last;
                for (size_t b = 0; b < cuts.size(); ++b) {
                    const uint32_t key = colour << 2 * kZoneIndexBits | cuts[b] << kZoneIndexBits;
                    out.blockStart[(b + 1) * colours + c] =
                        zones[first] == kTailZone
                            ? first // the tail: in the last block
                            : uint32_t(std::lower_bound(zones.begin() + first, zones.begin() + last,
                                                        key) -
                                       zones.begin());
                }
            }
        }
    }
    // Within each block's colour, its zones by decreasing size (ties by index).
    out.bySize.resize(zoneCount);
    for (size_t b = 0; b < out.blockCount(); ++b)
        for (size_t c = 0; c < colours; ++c) {
            const uint32_t from = out.blockZone(b, c);
            const auto first = out.bySize.begin() + from;
            const auto last = out.bySize.begin() + out.blockZone(b + 1, c);
            std::iota(first, last, from);
            std::sort(first, last, [&](uint32_t x, uint32_t y) {
                const uint32_t sx = out.zoneStart[x + 1] - out.zoneStart[x];
                const uint32_t sy = out.zoneStart[y + 1] - out.zoneStart[y];
                return sx > sy || (sx == sy && x < y);
            });
        }
}

std::string scheduleProblem(std::span<const Contact> contacts, const SolverSchedule& schedule,
                            size_t bodyCount) {
    auto say = [](const char* what, size_t a, size_t b = 0) {
        return std::string(what) + " (" + std::to_string(a) + ", " + std::to_string(b) + ")";
    };
    const size_t n = contacts.size();
    if (n == 0) return schedule.order.empty() ? std::string() : say("order without contacts", 0);
    if (schedule.order.size() != n) return say("order size != contacts", schedule.order.size(), n);
    const size_t zones = schedule.zoneCount();
    if (zones == 0 || schedule.zoneStart.front() != 0 || schedule.zoneStart.back() != n)
        return say("zone starts do not span the order", zones, n);
    for (size_t z = 0; z < zones; ++z)
        if (schedule.zoneStart[z] > schedule.zoneStart[z + 1])
            return say("zone starts decrease", z);
    const std::vector<uint32_t>& colours = schedule.colourStart;
    if (colours.size() < 2 || colours.front() != 0 || colours.back() != zones)
        return say("colour starts do not span the zones", colours.size(), zones);
    if (schedule.bySize.size() != zones) return say("bySize size != zones", schedule.bySize.size());
    const size_t colourCount = schedule.colourCount();
    if (!schedule.blockStart.empty()) {
        if (colourCount == 0 || schedule.blockStart.size() % colourCount != 0 ||
            schedule.blockStart.size() < 2 * colourCount)
            return say("block starts not rows of colours", schedule.blockStart.size(), colourCount);
        const size_t blocks = schedule.blockCount();
        for (size_t c = 0; c < colourCount; ++c) {
            if (schedule.blockZone(0, c) != schedule.colourStart[c] ||
                schedule.blockZone(blocks, c) != schedule.colourStart[c + 1])
                return say("blocks do not span the colour", c);
            for (size_t b = 0; b < blocks; ++b)
                if (schedule.blockZone(b, c) > schedule.blockZone(b + 1, c))
                    return say("block starts decrease", b, c);
        }
    }
    for (size_t b = 0; b < schedule.blockCount(); ++b)
        for (size_t c = 0; c < colourCount; ++c)
            for (uint32_t k = schedule.blockZone(b, c); k < schedule.blockZone(b + 1, c); ++k)
                if (schedule.bySize[k] < schedule.blockZone(b, c) ||
                    schedule.bySize[k] >= schedule.blockZone(b + 1, c))
                    return say("bySize leaves its block's colour", k, schedule.bySize[k]);
    std::vector<uint8_t> seen(n, 0);
    for (const uint32_t c : schedule.order) {
        if (c >= n) return say("contact index out of range", c, n);
        if (seen[c]++) return say("contact scheduled twice", c);
    }
    // owner[b]: the zone of the current colour that touched body b (kNone: none yet).
    constexpr uint32_t kNone = UINT32_MAX;
    std::vector<uint32_t> owner(bodyCount, kNone), touched;
    for (size_t c = 0; c + 1 < colours.size(); ++c) {
        if (colours[c] > colours[c + 1]) return say("colour starts decrease", c);
        const bool tail = c + 2 == colours.size() && colours[c + 1] - colours[c] == 1;
        for (uint32_t z = colours[c]; z < colours[c + 1]; ++z)
            for (uint32_t m = schedule.zoneStart[z]; m < schedule.zoneStart[z + 1]; ++m) {
                const Contact& k = contacts[schedule.order[m]];
                const uint32_t bodies[2] = {k.bodyA, k.hasB ? k.bodyB : k.bodyA};
                for (const uint32_t b : bodies) {
                    if (b >= bodyCount) return say("body out of range", b, bodyCount);
                    if (owner[b] == kNone)
                        owner[b] = z, touched.push_back(b);
                    else if (owner[b] != z && !tail)
                        return say("body in two zones of one colour", b, c);
                }
            }
        for (const uint32_t b : touched) owner[b] = kNone;
        touched.clear();
    }
    return {};
}

std::string contactProblem(std::span<const Contact> contacts, std::span<const BoxParticles> boxes,
                           size_t bodyCount, std::span<const uint32_t> firstParticle,
                           std::span<const uint32_t> particleCount) {
    auto say = [](const char* what, size_t n, size_t v) {
        return std::string(what) + " (contact " + std::to_string(n) + ": " + std::to_string(v) +
               ")";
    };
    auto pointProblem = [&](const ContactPoint& p, uint32_t body) -> const char* {
        if (p.box >= boxes.size()) return "box out of range";
        if (!std::isfinite(p.local.x) || !std::isfinite(p.local.y) || !std::isfinite(p.local.z))
            return "local coordinates not finite";
        for (const uint32_t i : boxes[p.box])
            if (i < firstParticle[body] || i >= firstParticle[body] + particleCount[body])
                return "point on another body's particle";
        return nullptr;
    };
    for (size_t n = 0; n < contacts.size(); ++n) {
        const Contact& c = contacts[n];
        if (c.bodyA >= bodyCount) return say("body A out of range", n, c.bodyA);
        if (c.hasB && (c.bodyB >= bodyCount || c.bodyB == c.bodyA))
            return say("body B out of range or A", n, c.bodyB);
        if (const char* p = pointProblem(c.a, c.bodyA)) return say(p, n, c.bodyA);
        if (c.hasB)
            if (const char* p = pointProblem(c.b, c.bodyB)) return say(p, n, c.bodyB);
    }
    return {};
}

void prepareRigidStates(std::span<const Vec3> x, std::span<const Vec3> v,
                        std::span<const float> invMass, std::span<const uint32_t> firstParticle,
                        std::span<const uint32_t> particleCount, std::span<RigidState> states,
                        size_t firstBody) {
    for (size_t j = 0; j < states.size(); ++j) {
        RigidState& s = states[j];
        const size_t b = firstBody + j;
        if (!s.active) continue;
        s.firstParticle = firstParticle[b];
        s.particleCount = particleCount[b];
        const bool velocities = !v.empty();
        double M = 0;
        Vec3 c{}, p{};
        for (uint32_t i = s.firstParticle; i < s.firstParticle + s.particleCount; ++i) {
            const float m = 1.0f / invMass[i];
            M += double(m);
            c += x[i] * m;
            if (velocities) p += v[i] * m;
        }
        c = c / float(M);
        float xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
        Vec3 L{};
        for (uint32_t i = s.firstParticle; i < s.firstParticle + s.particleCount; ++i) {
            const float m = 1.0f / invMass[i];
            const Vec3 r = x[i] - c;
            xx += m * r.x * r.x, yy += m * r.y * r.y, zz += m * r.z * r.z;
            xy += m * r.x * r.y, xz += m * r.x * r.z, yz += m * r.y * r.z;
            if (velocities) L += cross(r, v[i]) * m;
        }
        const float trace = xx + yy + zz;
        const Mat3 I{{{trace - xx, -xy, -xz}, {-xy, trace - yy, -yz}, {-xz, -yz, trace - zz}}};
        s.centre = c;
        s.invMass = float(1.0 / M);
        if (!inverse(I, s.invInertia, 1e-12f * trace * trace * trace)) s.invInertia = Mat3{};
        s.velocity = p * s.invMass;
        s.angularVelocity = s.invInertia * L;
    }
}

void solveRigidPhase(std::span<Contact> contacts, std::span<const BoxParticles> boxes,
                     std::vector<RigidState>& states, std::vector<RigidPoint>& points,
                     std::span<const Vec3> x, std::span<Vec3> v, std::span<const float> invMass,
                     std::span<const uint32_t> firstParticle,
                     std::span<const uint32_t> particleCount, float dt, float impactThreshold,
                     float maxSeparationSpeed, int iterations, SolverScratch& scratch,
                     Workers& workers) {
    const SolverSchedule& schedule = scratch.schedule;
    std::vector<uint32_t>& impacts = scratch.impacts;
    std::vector<uint32_t>& impactEnd = scratch.impactEnd; // per zone, as the schedule's
    states.assign(firstParticle.size(), RigidState{});

    // Impacts only, ramped in smoothly: a resting contact (approaching at about g dt) is left to
    // the particle level, where a partial rigid target that many contacts share could not be
    // met by one rigid motion and would leave a spurious rotation behind; a hard threshold
    // would make contacts near it flicker.
    auto rigidityOf = [&](const Contact& c) {
        const float ramp =
            std::clamp((-c.approachSpeed - impactThreshold) / (3.0f * impactThreshold), 0.0f, 1.0f);
        return c.rigidity * ramp;
    };
    // Every contact's approach (the velocity pass reads it too), and the impacts kept.
    toLanes(v, scratch.v4, workers);
    const F4* const V = scratch.v4.data();
    for (size_t block = 0; block < schedule.blockCount(); ++block)
        selectInZones(schedule, block, workers, impacts, impactEnd, [&](uint32_t k) {
            Contact& c = contacts[k];
            F4 rel = blend4(point4(c.a, boxes), V);
            if (c.hasB) rel -= blend4(point4(c.b, boxes), V);
            c.approachSpeed = dot(rel, c.normal);
            c.rigidImpulse = 0;
            c.rigidFriction = 0;
            // A deep contact's approach is its bodies restoring the dent the last push-out
            // left: read as an impact, it would be turned into rigid motion (margins.h,
            // push-out).
            return !c.pushedOut && rigidityOf(c) > 0;
        });
    bool any = false;
    for (size_t z = 0; z < schedule.zoneCount(); ++z)
        for (uint32_t j = schedule.zoneStart[z]; j < impactEnd[z]; ++j) {
            const Contact& c = contacts[impacts[j]];
            // A body of infinite mass (asleep) has no rigid modes to move: its state stays
            // inactive, with zero inverse mass and inertia.
            states[c.bodyA].active = invMass[firstParticle[c.bodyA]] > 0;
            if (c.hasB) states[c.bodyB].active = invMass[firstParticle[c.bodyB]] > 0;
            any = true;
        }
    if (!any) return; // at rest: nothing for the rigid modes to do
    const bool bounded = maxSeparationSpeed > 0;
    // The rigid velocities serve only the separation bound.
    workers.forRange(states.size(), [&](size_t first, size_t last, int) {
        prepareRigidStates(x, bounded ? std::span<const Vec3>(v) : std::span<const Vec3>{}, invMass,
                           firstParticle, particleCount,
                           std::span(states).subspan(first, last - first), first);
    });
    // What does not change over the iterations, once per impact (points[j] for impacts[j]): the
    // arms' angular directions, the effective mass and the target normal velocity.
    const float invDt = 1.0f / dt;
    points.resize(impacts.size());
    auto prepare = [&](uint32_t j) {
        const Contact& c = contacts[impacts[j]];
        RigidPoint& p = points[j];
        p.rigidity = rigidityOf(c);
        p.normalImpulse = 0;
        p.normal = c.normal;
        p.approachSpeed = c.approachSpeed;
        p.bodyA = c.bodyA;
        p.bodyB = c.hasB ? c.bodyB : UINT32_MAX;
        const RigidState& A = states[c.bodyA];
        const Vec3 pa = blend(c.a, boxes, x), pb = c.hasB ? blend(c.b, boxes, x) : Vec3{};
        setNormalResponse(c, states, pa, pb, p);
        // The approach that would close more than the gap this substep, scaled by the
        // rigidity: the rest is left to the particle-level projection (deformation). Normal
        // only: friction is force-limited, so the particle-level pass removes the same momentum
        // once its limit counts this phase's normal impulse (a rigid-level friction with the
        // body's anisotropic response was found to feed a slow spin).
        //
        // With a separation bound (WorldSettings::maxSeparationSpeed > 0) the phase may bring
        // the rigid modes' relative normal velocity at the contact (`base`, before the phase)
        // up to the allowed approach plus the bound, not beyond. Particle velocity can be
        // mostly deformation (shape matching restoring a dent, bodies created overlapping):
        // read at the particle level alone, that speed is turned into rigid motion, which
        // throws such bodies apart at tens of m/s. The phase's changes move the particle and
        // the rigid normal velocity by the same amount, so the bound is one more target.
        const float gap = dot(pa - pb, c.normal) - c.offset;
        const float allowed = -maxNum(gap, 0.0f) * invDt;
        p.target = c.approachSpeed < allowed
                       ? c.approachSpeed + p.rigidity * (allowed - c.approachSpeed)
                       : c.approachSpeed;
        if (bounded) {
            float base = dot(A.velocity + cross(A.angularVelocity, pa - A.centre), c.normal);
            if (c.hasB) {
                const RigidState& B = states[c.bodyB];
                base -= dot(B.velocity + cross(B.angularVelocity, pb - B.centre), c.normal);
            }
            p.target = minNum(p.target, c.approachSpeed + (allowed + maxSeparationSpeed - base));
        }
    };
    // Every zone's impacts at once (their points are their own).
    auto inEveryZone = [&](auto&& fn) {
        workers.forChunks(schedule.zoneCount(), 4, [&](size_t first, size_t last, int) {
            for (size_t z = first; z < last; ++z)
                for (uint32_t j = schedule.zoneStart[z]; j < impactEnd[z]; ++j) fn(j);
        });
    };
    inEveryZone(prepare);
    auto sweep = [&](uint32_t j) {
        RigidPoint& p = points[j];
        if (p.invK == 0) return;
        RigidState& A = states[p.bodyA];
        // Normal relative velocity: base + (dv_A + dw_A x r_A) . n - (B's), with
        // (w x r) . n = w . (r x n).
        float vn = p.approachSpeed + dot(A.dv, p.normal) + dot(A.dw, p.armA);
        RigidState* B = p.bodyB != UINT32_MAX ? &states[p.bodyB] : nullptr;
        if (B) vn -= dot(B->dv, p.normal) + dot(B->dw, p.armB);
        const float old = p.normalImpulse;
        p.normalImpulse = maxNum(old + (p.target - vn) * p.invK, 0.0f);
        const float d = p.normalImpulse - old;
        A.dv += p.normal * (d * p.invMassA);
        A.dw += p.turnA * d;
        if (B) {
            B->dv -= p.normal * (d * p.invMassB);
            B->dw -= p.turnB * d;
        }
    };
    for (size_t block = 0; block < schedule.blockCount(); ++block)
        for (int it = 0; it < iterations; ++it)
            sweepZones(schedule, block, impactEnd, workers, sweep);
    inEveryZone([&](uint32_t j) { contacts[impacts[j]].rigidImpulse = points[j].normalImpulse; });
    workers.forRange(states.size(), [&](size_t first, size_t last, int) {
        for (size_t b = first; b < last; ++b) {
            RigidState& s = states[b];
            if (!s.active) continue;
            for (uint32_t i = s.firstParticle; i < s.firstParticle + s.particleCount; ++i)
                v[i] += s.dv + cross(s.dw, x[i] - s.centre);
            s.dv = s.dw = {};
        }
    });
}

void projectRigidModes(std::span<Contact> contacts, std::span<const BoxParticles> boxes,
                       std::vector<RigidState>& states, std::vector<RigidPoint>& points,
                       std::span<Vec3> x, std::span<Vec3> v, std::span<const float> invMass,
                       std::span<const uint32_t> firstParticle,
                       std::span<const uint32_t> particleCount, float dt, float share,
                       int iterations, SolverScratch& scratch, Workers& workers) {
    const SolverSchedule& schedule = scratch.schedule;
    const size_t bodyCount = firstParticle.size();
    states.assign(bodyCount, RigidState{});
    for (const Contact& c : contacts) {
        states[c.bodyA].active = invMass[firstParticle[c.bodyA]] > 0;
        if (c.hasB) states[c.bodyB].active = invMass[firstParticle[c.bodyB]] > 0;
    }
    workers.forRange(states.size(), [&](size_t first, size_t last, int) {
        prepareRigidStates(x, v, invMass, firstParticle, particleCount,
                           std::span(states).subspan(first, last - first), first);
    });
    const float invDt = 1.0f / dt;
    points.resize(contacts.size());
    // One Gauss-Seidel step for contact n: its violation with the bodies' rigid moves so far
    // (linear in them; p.target when they are zero) undone through the two bodies' rigid modes,
    // then its tangential slip within the friction limit.
    auto sweep = [&](uint32_t n) {
        const Contact& c = contacts[n];
        RigidPoint& p = points[n];
        if (p.invK == 0) return INFINITY;
        RigidState& A = states[c.bodyA];
        float C = p.target + dot(A.dv, c.normal) + dot(A.dw, p.armA);
        RigidState* B = c.hasB ? &states[c.bodyB] : nullptr;
        if (B) C -= dot(B->dv, c.normal) + dot(B->dw, p.armB);
        if (C < 0) {
            const float lambda = -C * p.invK;
            p.normalImpulse += lambda;
            A.dv += c.normal * (lambda * p.invMassA);
            A.dw += p.turnA * lambda;
            if (B) {
                B->dv -= c.normal * (lambda * p.invMassB);
                B->dw -= p.turnB * lambda;
            }
        }
        // Static friction on the rigid modes: the tangential slip of the contact's points
        // (the rigid motions' in the move and the moves since) undone within the Coulomb
        // limit of the normal correction, as a load is (position-based friction, Mueller et
        // al. 2020, "Detailed Rigid Body Simulation with Extended Position Based Dynamics").
        const float limit = c.friction * p.normalImpulse;
        if (limit > 0) {
            Vec3 d = p.slip + A.dv + cross(A.dw, p.rA);
            if (B) d -= B->dv + cross(B->dw, p.rB);
            d -= c.normal * dot(d, c.normal);
            const float slip = length(d);
            if (slip > 0) {
                const Vec3 t = d / slip;
                const Vec3 ta = cross(p.rA, t);
                float K = p.invMassA + dot(ta, A.invInertia * ta);
                Vec3 tb{};
                if (B) {
                    tb = cross(p.rB, t);
                    K += p.invMassB + dot(tb, B->invInertia * tb);
                }
                if (K > 0) {
                    Vec3 total = p.tangent - t * (slip / K);
                    const float size = length(total);
                    if (size > limit) total = total * (limit / size);
                    const Vec3 P = total - p.tangent;
                    p.tangent = total;
                    A.dv += P * p.invMassA;
                    A.dw += A.invInertia * cross(p.rA, P);
                    if (B) {
                        B->dv -= P * p.invMassB;
                        B->dw -= B->invInertia * cross(p.rB, P);
                    }
                }
            }
        }
        return C;
    };
    std::vector<float>& slack = scratch.slack;
    std::vector<float>& depth = scratch.bodyReach;
    slack.resize(contacts.size());
    depth.assign(bodyCount, 0.0f);
    // Block by block: its first sweep, then its later sweeps.
    for (size_t block = 0; block < schedule.blockCount(); ++block) {
        forEachZone(schedule, block, zoneEnds(schedule), workers, [&](uint32_t z) {
            for (uint32_t m = schedule.zoneStart[z]; m < schedule.zoneStart[z + 1]; ++m) {
                const uint32_t n = schedule.order[m];
                const Contact& c = contacts[n];
                RigidPoint& p = points[n];
                const RigidState& A = states[c.bodyA];
                const ContactWeights cw(c, boxes);
                const Vec3 pa = blend(cw.a, x), pb = c.hasB ? blend(cw.b, x) : Vec3{};
                p.normalImpulse = 0;
                p.tangent = {};
                p.rA = pa - A.centre;
                p.rB = c.hasB ? pb - states[c.bodyB].centre : Vec3{};
                // The rigid modes take the share `share` of the violation that the bodies'
                // rigid motion made in this substep's move (dt times their approach at the
                // contact), no more: the rest is deformation (shape matching restoring a dent,
                // bodies created overlapping), which the particle-level passes push out without
                // throwing the bodies apart (margins.h, push-out; overlap_recovery.h).
                auto rigidVelocity = [&](const RigidState& r, const PointWeights& q, Vec3 at) {
                    return r.active ? r.velocity + cross(r.angularVelocity, at - r.centre)
                                    : blend(q, v); // immovable: its particles move rigidly
                };
                Vec3 rel = rigidVelocity(A, cw.a, pa);
                if (c.hasB) rel -= rigidVelocity(states[c.bodyB], cw.b, pb);
                const float C = dot(pa - pb, c.normal) - c.offset;
                const float closing = maxNum(-dot(rel, c.normal), 0.0f) * dt;
                p.slip = (rel - c.normal * dot(rel, c.normal)) * dt;
                p.target = C - minNum(c.tolerated, C + share * closing);
                setNormalResponse(c, states, pa, pb, p);
                const float violated = sweep(n);
                slack[n] = violated;
                if (!(violated < 0)) continue;
                depth[c.bodyA] = maxNum(depth[c.bodyA], -violated);
                if (c.hasB) depth[c.bodyB] = maxNum(depth[c.bodyB], -violated);
            }
        });
        if (iterations > 1) {
            selectReachable(contacts, scratch, block, workers);
            for (int it = 1; it < iterations; ++it)
                sweepZones(schedule, block, scratch.activeEnd, workers,
                           [&](uint32_t m) { sweep(scratch.active[m]); });
        }
    }
    workers.forRange(contacts.size(), [&](size_t first, size_t last, int) {
        for (size_t n = first; n < last; ++n) {
            contacts[n].rigidImpulse += points[n].normalImpulse * invDt;
            contacts[n].rigidFriction = length(points[n].tangent) * invDt;
        }
    });
    // The moves, rotations exact about each body's centre; the velocities follow.
    workers.forRange(states.size(), [&](size_t first, size_t last, int) {
        for (size_t b = first; b < last; ++b) {
            RigidState& s = states[b];
            if (!s.active) continue;
            const float angle = length(s.dw);
            const Mat3 R = angle > 0 ? toMat3(Quat::fromAxisAngle(s.dw, angle)) : Mat3::identity();
            for (uint32_t i = s.firstParticle; i < s.firstParticle + s.particleCount; ++i) {
                const Vec3 moved = s.centre + s.dv + R * (x[i] - s.centre);
                v[i] += (moved - x[i]) * invDt;
                x[i] = moved;
            }
            s.dv = s.dw = {};
        }
    });
}

void solveContactPositions(std::span<Contact> contacts, std::span<const BoxParticles> boxes,
                           std::span<Vec3> x, std::span<Vec3> v, std::span<const float> invMass,
                           float dt, int iterations, size_t bodyCount, SolverScratch& scratch,
                           Workers& workers) {
    const SolverSchedule& schedule = scratch.schedule;
    const float invDt = 1.0f / dt;
    const bool follow = !v.empty();
    toLanes(x, scratch.x4, workers);
    if (follow) toLanes(v, scratch.v4, workers);
    F4* const X = scratch.x4.data();
    F4* const V = scratch.v4.data();
    const float* const im = invMass.data();
    auto sweep = [&](Contact& c) {
        Point4 a, b;
        const float C = separation4(c, boxes, X, a, b) - c.tolerated;
        const float W = c.invMassA + c.invMassB;
        if (C >= 0 || !(W > 0)) return C;
        const float lambda = -C / W;
        float shareA[8], shareB[8];
        shares(a, im, shareA);
        if (c.hasB) shares(b, im, shareB);
        const F4 n = lanes(c.normal);
        push4(a, X, shareA, n * lambda);
        if (c.hasB) push4(b, X, shareB, n * -lambda);
        if (follow) {
            c.positionImpulse += lambda * invDt;
            push4(a, V, shareA, n * (lambda * invDt));
            if (c.hasB) push4(b, V, shareB, n * (-lambda * invDt));
        }
        return C;
    };
    // The first sweep visits every contact and keeps its separation, and each body's deepest
    // violation. The later sweeps visit the contacts found violated and those that the
    // corrections could close: a body is pushed by about its deepest violation at most, so a
    // contact further apart than twice the deepest violations of its two bodies stays apart.
    // Most contacts are speculative and well apart; a contact just touching a body that is
    // pushed is kept, so chains (a heavy body on a light one on the floor) are corrected
    // through.
    std::vector<float>& separation = scratch.slack;
    std::vector<float>& depth = scratch.bodyReach;
    separation.resize(contacts.size());
    depth.assign(bodyCount, 0.0f);
    scratch.zoneDeepest.assign(schedule.zoneCount(), 0.0f);
    // Block by block: its first sweep, then its later sweeps.
    bool moved = false;
    for (size_t block = 0; block < schedule.blockCount(); ++block) {
        forEachZone(schedule, block, zoneEnds(schedule), workers, [&](uint32_t z) {
            float deepest = 0;
            for (uint32_t m = schedule.zoneStart[z]; m < schedule.zoneStart[z + 1]; ++m) {
                const uint32_t n = schedule.order[m];
                Contact& c = contacts[n];
                c.positionImpulse = 0;
                const float C = sweep(c);
                separation[n] = C;
                if (C >= 0) continue;
                deepest = maxNum(deepest, -C);
                depth[c.bodyA] = maxNum(depth[c.bodyA], -C);
                if (c.hasB) depth[c.bodyB] = maxNum(depth[c.bodyB], -C);
            }
            scratch.zoneDeepest[z] = deepest;
        });
        const float deepest = blockDeepest(schedule, block, scratch.zoneDeepest);
        if (iterations > 1 && deepest > 0) {
            selectReachable(contacts, scratch, block, workers);
            for (int it = 1; it < iterations; ++it)
                sweepZones(schedule, block, scratch.activeEnd, workers,
                           [&](uint32_t m) { sweep(contacts[scratch.active[m]]); });
        }
        moved = moved || deepest > 0;
    }
    if (!moved) return; // nothing moved
    fromLanes(scratch.x4, x, workers);
    if (follow) fromLanes(scratch.v4, v, workers);
}

float solveContactVelocities(std::span<Contact> contacts, std::span<const BoxParticles> boxes,
                             std::span<const Vec3> x, std::span<Vec3> v,
                             std::span<const float> invMass, float dt, float bounceThreshold,
                             int iterations, size_t bodyCount, SolverScratch& scratch,
                             Workers& workers) {
    const SolverSchedule& schedule = scratch.schedule;
    const float invDt = 1.0f / dt;
    // One sweep step for contact c; returns its slack: how much faster its points would have to
    // approach before it acted (-infinity when it acts: an impulse, or a friction budget).
    std::vector<float>& change = scratch.bodyReach; // per body, the largest in the first sweep
    change.assign(bodyCount, 0.0f);
    toLanes(x, scratch.x4, workers);
    toLanes(v, scratch.v4, workers);
    const F4* const X = scratch.x4.data();
    F4* const V = scratch.v4.data();
    const float* const im = invMass.data();
    bool firstSweep = true;
    auto sweep = [&](Contact& c, const Point4& a, const Point4& b) {
        const float W = c.invMassA + c.invMassB;
        if (!(W > 0)) return INFINITY;
        F4 rel = blend4(a, V);
        if (c.hasB) rel -= blend4(b, V);
        const F4 n = lanes(c.normal);
        const float vn = dot(rel, c.normal);
        // Close at most the remaining gap next substep (speculative); bounce back fast
        // impacts by the restitution.
        float target = -c.gap * invDt;
        if (c.restitution > 0 && c.approachSpeed < -bounceThreshold)
            target = maxNum(target, -c.restitution * c.approachSpeed);
        const float oldNormal = c.normalImpulse;
        c.normalImpulse = maxNum(oldNormal + (target - vn) / W, 0.0f);
        F4 impulse = n * (c.normalImpulse - oldNormal);
        const float limit = maxNum(
            c.friction * (c.rigidImpulse + c.positionImpulse + c.normalImpulse) - c.rigidFriction,
            0.0f);
        if (limit > 0) {
            const F4 vt = rel - n * vn;
            const F4 oldTangent = lanes(c.tangentImpulse);
            F4 t = oldTangent - vt / W;
            const float tl = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
            if (tl > limit) t = t * (limit / tl);
            c.tangentImpulse = toVec3(t);
            impulse += t - oldTangent;
        }
        const bool acts = c.normalImpulse > 0 || limit > 0;
        if (!acts && oldNormal == 0) return vn - target; // nothing to apply
        float share[8];
        shares(a, im, share);
        push4(a, V, share, impulse);
        if (c.hasB) {
            shares(b, im, share);
            push4(b, V, share, -impulse);
        }
        if (firstSweep) {
            const float dv = length(toVec3(impulse)) * W;
            change[c.bodyA] = maxNum(change[c.bodyA], dv);
            if (c.hasB) change[c.bodyB] = maxNum(change[c.bodyB], dv);
        }
        return acts ? -INFINITY : vn - target;
    };
    // The first sweep visits every contact; the later ones those that act and those near
    // enough to acting that the impulses on their bodies could tip them (slack under twice the
    // largest changes of their bodies' contacts in the first sweep): most contacts are
    // speculative, apart and not approaching.
    std::vector<float>& slack = scratch.slack;
    slack.resize(contacts.size());
    // The first sweep visits every contact once: the positions are final here, so its gap, and
    // the deepest violation left, are found then.
    std::vector<float>& zoneDeepest = scratch.zoneDeepest;
    zoneDeepest.assign(schedule.zoneCount(), 0.0f);
    // Block by block: its first sweep, then its later sweeps.
    for (size_t block = 0; block < schedule.blockCount(); ++block) {
        firstSweep = true;
        forEachZone(schedule, block, zoneEnds(schedule), workers, [&](uint32_t z) {
            float d = 0;
            for (uint32_t m = schedule.zoneStart[z]; m < schedule.zoneStart[z + 1]; ++m) {
                Contact& c = contacts[schedule.order[m]];
                c.normalImpulse = 0;
                c.tangentImpulse = {};
                Point4 a, b;
                const float C = separation4(c, boxes, X, a, b);
                c.gap = maxNum(C, 0.0f);
                d = maxNum(d, -C);
                slack[schedule.order[m]] = sweep(c, a, b);
            }
            zoneDeepest[z] = d;
        });
        if (iterations > 1) {
            selectReachable(contacts, scratch, block, workers);
            firstSweep = false;
            for (int it = 1; it < iterations; ++it)
                sweepZones(schedule, block, scratch.activeEnd, workers, [&](uint32_t m) {
                    Contact& c = contacts[scratch.active[m]];
                    sweep(c, point4(c.a, boxes), c.hasB ? point4(c.b, boxes) : Point4{});
                });
        }
    }
    float deepest = 0;
    for (const float d : zoneDeepest) deepest = maxNum(deepest, d);
    fromLanes(scratch.v4, v, workers);
    return deepest;
}

} // namespace ffd::detail
