// Pins: an embedded point of a body (a particle, a mesh vertex, any point of its lattice) held
// at a target, hard or through an implicit spring. World's pin interface and the pins' stage
// of the substep (world/pins.h; docs/ALGORITHM.md, "Pins").
//
// A pin is a position constraint C = p - t on its point p = sum_k w_k x_k (its cell's 8
// particles, trilinear weights). It is projected after the position update, before the
// contacts' projection (which thus has the last word: a pin dragged into the floor or into
// another body does not push its point through), with velocities following the corrections
// (dv = dx / dt), like the contacts (collision/contact.h):
//   1. rigid phase: the share `rigidity` of the correction through the body's rigid motion, an
//      impulse P at the point, K = 1/M - [r]x I^-1 [r]x its inverse effective mass: the centre
//      moves by P / M and the body turns by I^-1 (r x P) about it (an exact rotation), so the
//      body follows a fast target as a whole instead of being torn by it;
//   2. particle phase: the rest through the point's particles, moved by w_k / m_k d / W
//      (W = sum w_k^2 / m_k), the least mass-weighted motion that moves the point by d;
//   3. swing damping: the body's rigid rotation about the target damped at `swingDamping` 1/s.
// A soft pin (stiffness k > 0) aims at p + s (t - p) instead, s = 1 / (1 + m / (k dt^2)) with m
// the point's effective mass (the two phases' masses in their shares): one step of an implicit
// spring (XPBD's compliance 1/k), the same sag m g / k at any substep.
#include "world/pins.h"

#include "ffdaabb/error.h"
#include "world/input_checks.h"
#include "world/sleeping.h"
#include "world/world_data.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace ffd {

using detail::Pin;
using detail::PinSlot;
using detail::WorldData;

namespace {

const detail::BodyRecord& bodyOf(const WorldData& w, BodyId id) {
    const detail::BodyRecord* r = w.find(id);
    if (!r)
        throw InputError("body", "stale or invalid body handle (index " + std::to_string(id.index) +
                                     ", generation " + std::to_string(id.generation) + ")");
    return *r;
}

const Pin& pinOf(const WorldData& w, PinId id) {
    const Pin* p = w.pins.find(id);
    if (!p)
        throw InputError("pin", "stale or invalid pin handle (index " + std::to_string(id.index) +
                                    ", generation " + std::to_string(id.generation) + ")");
    return *p;
}

// The point of a pin: its particles' blend of `x` (world-wide), the body starting at p0.
Vec3 pinPointOf(const Pin& pin, const std::vector<Vec3>& x, uint32_t p0) {
    Vec3 p{};
    for (int k = 0; k < 8; ++k) p += x[p0 + pin.particle[k]] * pin.weight[k];
    return p;
}

PinId addPin(WorldData& w, Pin pin) {
    const BodyMotion motion = w.find(pin.body)->settings.motion;
    if (motion != BodyMotion::Dynamic)
        throw InputError("body.motion", std::string("a ") + toString(motion) +
                                            " body cannot be pinned (expected dynamic)");
    detail::PinState& s = w.pins;
    uint32_t slot;
    if (!s.freeSlots.empty()) {
        slot = s.freeSlots.back();
        s.freeSlots.pop_back();
    } else {
        slot = uint32_t(s.slots.size());
        s.slots.push_back({});
    }
    pin.slot = slot;
    // The pin starts where its point is and goes to its target at maxSpeed at most, like a
    // target moved there: a point pinned far from its target is not yanked there at once.
    const detail::BodyRecord& r = bodyOf(w, pin.body);
    pin.start = pin.followed = pin.previous = pinPointOf(pin, w.x, r.firstParticle);
    detail::wakeIsland(w, w.slots[pin.body.index].dense); // a new pull
    s.slots[slot].dense = uint32_t(s.list.size());
    s.list.push_back(pin);
    return {slot, s.slots[slot].generation};
}

// A pin on the embedded point `e` of the body.
Pin embeddedPin(const detail::BodyRecord& r, BodyId body, const Embedding& e, Vec3 target,
                const PinSettings& settings) {
    Pin pin;
    pin.body = body;
    pin.target = target;
    pin.settings = settings;
    const auto& corner = r.model->lattice.cellParticles[e.cell];
    trilinearWeights(e.local, pin.weight);
    for (int k = 0; k < 8; ++k) pin.particle[k] = corner[size_t(k)];
    return pin;
}

} // namespace

void validate(const PinSettings& s) {
    detail::requireRange("pin.stiffness", s.stiffness, 0.0, 1e12, "N/m, 0 (hard) or 0 < k <= 1e12");
    detail::requireRange("pin.rigidity", s.rigidity, 0.0, 1.0, "0..1");
    detail::requireRange("pin.swingDamping", s.swingDamping, 0.0, 1000.0, "1/s, 0..1000");
    detail::requireRange("pin.maxSpeed", s.maxSpeed, 0.0, 1e6, "m/s, 0 (any) or 0 < v <= 1e6");
}

PinId World::pinParticle(BodyId body, uint32_t particle, Vec3 target, const PinSettings& s) {
    validate(s);
    detail::requireFinite("target", target);
    const detail::BodyRecord& r = bodyOf(*state_, body);
    if (particle >= r.particleCount)
        throw InputError("particle", "index " + std::to_string(particle) +
                                         " is out of range (body has " +
                                         std::to_string(r.particleCount) + " particles)");
    Pin pin;
    pin.body = body;
    pin.target = target;
    pin.settings = s;
    for (int k = 0; k < 8; ++k) pin.particle[k] = particle, pin.weight[k] = k == 0 ? 1.0f : 0.0f;
    return addPin(*state_, pin);
}

PinId World::pinVertex(BodyId body, uint32_t vertex, Vec3 target, const PinSettings& s) {
    validate(s);
    detail::requireFinite("target", target);
    const detail::BodyRecord& r = bodyOf(*state_, body);
    if (vertex >= r.vertexCount)
        throw InputError("vertex", "index " + std::to_string(vertex) +
                                       " is out of range (body has " +
                                       std::to_string(r.vertexCount) + " vertices)");
    return addPin(*state_, embeddedPin(r, body, r.model->lattice.vertices[vertex], target, s));
}

PinId World::pinRestPoint(BodyId body, Vec3 restPoint, Vec3 target, const PinSettings& s) {
    validate(s);
    detail::requireFinite("restPoint", restPoint);
    detail::requireFinite("target", target);
    const detail::BodyRecord& r = bodyOf(*state_, body);
    Embedding e = embedPoint(r.model->lattice, restPoint);
    // A point outside every cell is held by the nearest point of the nearest cell.
    for (int a = 0; a < 3; ++a) e.local[a] = std::clamp(e.local[a], 0.0f, 1.0f);
    return addPin(*state_, embeddedPin(r, body, e, target, s));
}

PinId World::pinPoint(BodyId body, Vec3 point, const PinSettings& s) {
    validate(s);
    detail::requireFinite("point", point);
    const detail::BodyRecord& r = bodyOf(*state_, body);
    const Embedding e = detail::embedDeformedPoint(
        r.model->lattice,
        std::span<const Vec3>(state_->x.data() + r.firstParticle, r.particleCount), point);
    return addPin(*state_, embeddedPin(r, body, e, point, s));
}

void World::setPinTarget(PinId id, Vec3 target) {
    detail::requireFinite("target", target);
    const Pin& pin = pinOf(*state_, id);
    if (pin.target != target) detail::wakeIsland(*state_, state_->slots[pin.body.index].dense);
    state_->pins.find(id)->target = target;
}

void World::setPinSettings(PinId id, const PinSettings& s) {
    validate(s);
    const Pin& pin = pinOf(*state_, id);
    detail::wakeIsland(*state_, state_->slots[pin.body.index].dense);
    state_->pins.find(id)->settings = s;
}

bool World::unpin(PinId id) {
    detail::PinState& s = state_->pins;
    if (!s.find(id)) return false;
    const uint32_t dense = s.slots[id.index].dense;
    detail::wakeIsland(*state_, state_->slots[s.list[dense].body.index].dense); // let go
    s.list.erase(s.list.begin() + dense);
    for (size_t i = dense; i < s.list.size(); ++i) s.slots[s.list[i].slot].dense = uint32_t(i);
    s.slots[id.index].dense = UINT32_MAX;
    ++s.slots[id.index].generation;
    s.freeSlots.push_back(id.index);
    return true;
}

bool World::isValid(PinId id) const {
    return state_->pins.find(id) != nullptr;
}

PinInfo World::pin(PinId id) const {
    const Pin& p = pinOf(*state_, id);
    const detail::BodyRecord& r = bodyOf(*state_, p.body);
    PinInfo info;
    info.body = p.body;
    info.target = p.target;
    info.point = pinPointOf(p, state_->x, r.firstParticle);
    info.followed = p.followed;
    info.force = p.force;
    info.lag = length(info.point - p.target);
    info.settings = p.settings;
    return info;
}

std::vector<PinId> World::pins() const {
    std::vector<PinId> ids;
    for (const Pin& p : state_->pins.list)
        ids.push_back({p.slot, state_->pins.slots[p.slot].generation});
    return ids;
}

namespace detail {

namespace {

// Corrections of the rigid phase at most (projectPin).
constexpr int kRigidIterations = 4;

// A body's rigid state for a projection: mass, centre of mass and inverse inertia about it.
struct Rigid {
    float mass = 0;
    Vec3 centre;
    Mat3 invInertia;
    bool turns = false; ///< the inertia could be inverted
};

Rigid rigidOf(const WorldData& w, const BodyRecord& r) {
    Rigid g;
    double M = 0, cx = 0, cy = 0, cz = 0;
    const uint32_t p0 = r.firstParticle, p1 = p0 + r.particleCount;
    for (uint32_t i = p0; i < p1; ++i) {
        const double m = 1.0 / double(w.invMass[i]);
        M += m, cx += m * w.x[i].x, cy += m * w.x[i].y, cz += m * w.x[i].z;
    }
    g.mass = float(M);
    g.centre = Vec3{float(cx / M), float(cy / M), float(cz / M)};
    double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
    for (uint32_t i = p0; i < p1; ++i) {
        const double m = 1.0 / double(w.invMass[i]);
        const Vec3 d = w.x[i] - g.centre;
        xx += m * d.x * d.x, yy += m * d.y * d.y, zz += m * d.z * d.z;
        xy += m * d.x * d.y, xz += m * d.x * d.z, yz += m * d.y * d.z;
    }
    const Mat3 I{{{float(yy + zz), float(-xy), float(-xz)},
                  {float(-xy), float(xx + zz), float(-yz)},
                  {float(-xz), float(-yz), float(xx + yy)}}};
    const float scale = float(xx + yy + zz);
    g.turns = scale > 0 && inverse(I, g.invInertia, 1e-9f * scale * scale * scale);
    return g;
}

Mat3 skew(Vec3 r) {
    return {{{0, -r.z, r.y}, {r.z, 0, -r.x}, {-r.y, r.x, 0}}};
}

// Moves every particle of the body rigidly: the centre by dc, a turn by the rotation vector dq
// about it; velocities follow.
void moveRigidly(WorldData& w, const BodyRecord& r, const Rigid& g, Vec3 dc, Vec3 dq, float invDt) {
    const float angle = length(dq);
    const bool turn = angle > 0;
    const Mat3 R = turn ? toMat3(Quat::fromAxisAngle(dq, angle)) : Mat3::identity();
    for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i) {
        const Vec3 arm = w.x[i] - g.centre;
        const Vec3 moved = (turn ? R * arm : arm) + g.centre + dc;
        const Vec3 dx = moved - w.x[i];
        w.x[i] = moved;
        w.v[i] += dx * invDt;
    }
}

// One projection of one pin toward `goalTarget`.
void projectPin(WorldData& w, Pin& pin, Vec3 target, float dt) {
    const BodyRecord& r = w.bodies[w.slots[pin.body.index].dense];
    const uint32_t p0 = r.firstParticle;
    const float invDt = 1.0f / dt;
    const Vec3 p = pinPointOf(pin, w.x, p0);
    const Vec3 d0 = target - p;
    const float distance = length(d0);
    if (!(distance > 0)) return;
    float W = 0; // the point's particles' generalised inverse mass
    for (int k = 0; k < 8; ++k)
        W += pin.weight[k] * pin.weight[k] * w.invMass[p0 + pin.particle[k]];
    const float rho = pin.settings.rigidity;
    Rigid g;
    Mat3 K;
    if (rho > 0) {
        g = rigidOf(w, r);
        const Mat3 rx = skew(p - g.centre);
        K = Mat3::identity() * (1.0f / g.mass);
        if (g.turns) K = K + (rx * g.invInertia * rx) * -1.0f;
    }
    // The goal: the target (hard), or one implicit spring step toward it (soft).
    Vec3 d = d0;
    if (pin.settings.stiffness > 0) {
        const Vec3 n = d0 / distance;
        const float rigidMass = rho > 0 ? 1.0f / dot(n, K * n) : 0.0f;
        const float mass = rho * rigidMass + (1.0f - rho) / W;
        d = d0 * (1.0f / (1.0f + mass / (pin.settings.stiffness * dt * dt)));
    }
    const Vec3 goal = p + d;
    if (rho > 0) {
        // The rigid share of the goal, Newton's way: the rotation is not linear in the
        // impulse, so the point lands short of a far goal in one go; a few more corrections
        // land it (a rigid body is not strained by them, as a particle correction would be).
        const Vec3 rigidGoal = p + d * rho;
        Vec3 at = p;
        for (int it = 0; it < kRigidIterations; ++it) {
            Mat3 invK;
            if (!inverse(K, invK)) break;
            const Vec3 P = invK * (rigidGoal - at); // kg m: the impulse times dt
            const Vec3 dq = g.turns ? g.invInertia * cross(at - g.centre, P) : Vec3{};
            moveRigidly(w, r, g, P / g.mass, dq, invDt);
            pin.impulse += P * invDt;
            at = pinPointOf(pin, w.x, p0);
            if (!(lengthSquared(rigidGoal - at) > 1e-12f * distance * distance)) break;
            g = rigidOf(w, r);
            const Mat3 rx = skew(at - g.centre);
            K = Mat3::identity() * (1.0f / g.mass);
            if (g.turns) K = K + (rx * g.invInertia * rx) * -1.0f;
        }
    }
    if (rho < 1 || pin.settings.stiffness == 0) {
        // What is left, through the point's particles (exact for a hard pin).
        const Vec3 rest = goal - pinPointOf(pin, w.x, p0);
        if (W > 0 && lengthSquared(rest) > 0) {
            for (int k = 0; k < 8; ++k) {
                const uint32_t i = p0 + pin.particle[k];
                const Vec3 dx = rest * (pin.weight[k] * w.invMass[i] / W);
                w.x[i] += dx;
                w.v[i] += dx * invDt;
            }
            pin.impulse += rest * (invDt / W);
        }
    }
}

// Damps by the share `share` the body's rigid rotation about the pin's target and, for a soft
// pin, its point's velocity relative to the target's (the spring's bounce; a hard pin's point
// moves with its target already).
void dampSwing(WorldData& w, const Pin& pin, Vec3 target, Vec3 targetVelocity, float share) {
    const BodyRecord& r = w.bodies[w.slots[pin.body.index].dense];
    const Rigid g = rigidOf(w, r);
    if (g.turns) {
        Vec3 L{};
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i)
            L += cross(w.x[i] - g.centre, w.v[i]) * (1.0f / w.invMass[i]);
        const Vec3 omega = g.invInertia * L * share;
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i)
            w.v[i] -= cross(omega, w.x[i] - target);
    }
    if (pin.settings.stiffness > 0) {
        const Vec3 dv = (pinPointOf(pin, w.v, r.firstParticle) - targetVelocity) * share;
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i) w.v[i] -= dv;
    }
}

} // namespace

void pinStage(WorldData& w, float dt, int substep, int substeps) {
    PinState& s = w.pins;
    if (s.list.empty()) return;
    // Several pins on one body pull against each other: Gauss-Seidel passes, as many as the
    // contacts get; one pin per body is done in one.
    s.passes.assign(w.bodies.size(), 0);
    bool shared = false;
    for (const Pin& pin : s.list) shared |= ++s.passes[w.slots[pin.body.index].dense] > 1;
    const int passes = shared ? std::max(1, w.settings.solverIterations) : 1;
    // Each substep's target: the step's path from where the target was to where it is set, in
    // equal parts, followed at maxSpeed at most.
    const float along = float(substep + 1) / float(substeps);
    // A sleeping body hangs still at its pins (a target that moves wakes it): they keep the
    // force of its last awake step.
    auto asleep = [&](const Pin& pin) { return w.bodies[w.slots[pin.body.index].dense].asleep; };
    for (Pin& pin : s.list) {
        if (asleep(pin)) continue;
        if (substep == 0) pin.impulse = {};
        pin.previous = pin.followed;
        const Vec3 aim = pin.start + (pin.target - pin.start) * along;
        const Vec3 ahead = aim - pin.followed;
        const float most = pin.settings.maxSpeed * dt, gap = length(ahead);
        pin.followed =
            pin.settings.maxSpeed > 0 && gap > most ? pin.followed + ahead * (most / gap) : aim;
    }
    for (int pass = 0; pass < passes; ++pass)
        for (Pin& pin : s.list)
            if (!asleep(pin)) projectPin(w, pin, pin.followed, dt);
    for (const Pin& pin : s.list)
        if (pin.settings.swingDamping > 0 && !asleep(pin))
            dampSwing(w, pin, pin.followed, (pin.followed - pin.previous) / dt,
                      1.0f - std::exp(-pin.settings.swingDamping * dt));
    if (substep + 1 == substeps)
        for (Pin& pin : s.list) {
            if (asleep(pin)) continue;
            pin.force = pin.impulse / (dt * float(substeps));
            pin.start = pin.target;
        }
}

void forgetPins(WorldData& w, BodyId body) {
    PinState& s = w.pins;
    size_t kept = 0;
    for (size_t i = 0; i < s.list.size(); ++i) {
        Pin& pin = s.list[i];
        if (pin.body == body) {
            s.slots[pin.slot].dense = UINT32_MAX;
            ++s.slots[pin.slot].generation;
            s.freeSlots.push_back(pin.slot);
            continue;
        }
        s.slots[pin.slot].dense = uint32_t(kept);
        s.list[kept++] = pin;
    }
    s.list.resize(kept);
}

Embedding embedDeformedPoint(const Lattice& L, std::span<const Vec3> x, Vec3 point) {
    Embedding best;
    float bestDistance = std::numeric_limits<float>::max();
    for (uint32_t c = 0; c < L.cellCount(); ++c) {
        const auto& corner = L.cellParticles[c];
        Aabb box;
        for (int k = 0; k < 8; ++k) box.add(x[corner[size_t(k)]]);
        const float reach = length(box.extent());
        const Vec3 nearest = min(max(point, box.lo), box.hi);
        const float away = length(point - nearest);
        if (away > reach || away > bestDistance) continue; // cannot beat the best
        // Newton on f(l) = sum_k w_k(l) x_k - point, from the cell's middle.
        Vec3 l{0.5f, 0.5f, 0.5f};
        for (int it = 0; it < 12; ++it) {
            float w8[8];
            trilinearWeights(l, w8);
            Vec3 f = -point;
            for (int k = 0; k < 8; ++k) f += x[corner[size_t(k)]] * w8[k];
            // Columns: df/ds, df/dt, df/du.
            Vec3 J[3];
            for (int a = 0; a < 3; ++a) {
                Vec3 col{};
                for (int k = 0; k < 8; ++k) {
                    const int bit = (k >> a) & 1;
                    float dw = bit ? 1.0f : -1.0f;
                    for (int b = 0; b < 3; ++b)
                        if (b != a) dw *= ((k >> b) & 1) ? l[b] : 1.0f - l[b];
                    col += x[corner[size_t(k)]] * dw;
                }
                J[a] = col;
            }
            Mat3 inv;
            if (!inverse(Mat3::fromColumns(J[0], J[1], J[2]), inv)) break;
            l = l - inv * f;
            for (int a = 0; a < 3; ++a) l[a] = std::clamp(l[a], -0.5f, 1.5f);
        }
        for (int a = 0; a < 3; ++a) l[a] = std::clamp(l[a], 0.0f, 1.0f);
        float w8[8];
        trilinearWeights(l, w8);
        Vec3 at{};
        for (int k = 0; k < 8; ++k) at += x[corner[size_t(k)]] * w8[k];
        const float distance = length(at - point);
        if (distance < bestDistance) {
            bestDistance = distance;
            best.cell = c;
            best.local = l;
            if (distance < 1e-5f * reach) break; // inside this cell
        }
    }
    return best;
}

} // namespace detail
} // namespace ffd
