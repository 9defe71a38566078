// World: bodies, the staged step and its profile.
#include "ffdaabb/world.h"

#include "collision/overlap_recovery.h"
#include "collision/pipeline.h"
#include "ffdaabb/error.h"
#include "util/check.h"
#include "world/input_checks.h"
#include "world/settings_table.h"
#include "world/sleeping.h"
#include "world/stage_checks.h"
#include "world/stages.h"
#include "world/world_data.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

namespace ffd {

using detail::BodyModel;
using detail::BodyRecord;
using detail::WorldData;

const char* toString(CollisionMode mode) {
    switch (mode) {
    case CollisionMode::Enhanced:
        return "enhanced";
    case CollisionMode::Previous:
        return "previous";
    case CollisionMode::Brute:
        return "brute";
    case CollisionMode::None:
        return "none";
    }
    return "?";
}

const char* toString(DynamicsModel model) {
    return model == DynamicsModel::ShapeMatching ? "shape-matching" : "mass-spring";
}

bool parseCollisionMode(std::string_view text, CollisionMode& out) {
    for (CollisionMode m : {CollisionMode::Enhanced, CollisionMode::Previous, CollisionMode::Brute,
                            CollisionMode::None})
        if (text == toString(m)) {
            out = m;
            return true;
        }
    return false;
}

bool parseDynamicsModel(std::string_view text, DynamicsModel& out) {
    for (DynamicsModel m : {DynamicsModel::ShapeMatching, DynamicsModel::MassSpring})
        if (text == toString(m)) {
            out = m;
            return true;
        }
    return false;
}

const char* toString(BodyMotion motion) {
    switch (motion) {
    case BodyMotion::Dynamic:
        return "dynamic";
    case BodyMotion::Static:
        return "static";
    case BodyMotion::Kinematic:
        return "kinematic";
    }
    return "?";
}

bool parseBodyMotion(std::string_view text, BodyMotion& out) {
    for (BodyMotion m : {BodyMotion::Dynamic, BodyMotion::Static, BodyMotion::Kinematic})
        if (text == toString(m)) {
            out = m;
            return true;
        }
    return false;
}

using detail::requireFinite;
using detail::requireRange;

namespace {

uint64_t fnv1a(uint64_t h, const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

// The cache key of a model: the mesh's exact bytes (hashed) and everything that shapes the
// shared data.
std::string modelKey(const TriangleMesh& mesh, const BodySettings& s) {
    uint64_t h = 14695981039346656037ull;
    h = fnv1a(h, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
    h = fnv1a(h, mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]));
    char buf[256];
    std::snprintf(buf, sizeof buf, "%016llx/%zu/%zu/%a/%a/%d/%d/%a/%d/%d",
                  static_cast<unsigned long long>(h), mesh.positions.size(), mesh.triangles.size(),
                  double(s.lattice.cellSize), double(s.lattice.resolution), s.lattice.targetCells,
                  int(s.lattice.fillInterior), double(s.lattice.boxSkin), int(s.model),
                  s.regionHalfWidth);
    return buf;
}

std::shared_ptr<const BodyModel> buildModel(const TriangleMesh& mesh, const BodySettings& s) {
    auto model = std::make_shared<BodyModel>();
    model->mesh = mesh;
    model->lattice = buildLattice(mesh, s.lattice);
    model->dynamics = s.model;
    if (s.model == DynamicsModel::ShapeMatching)
        model->shapeMatching = detail::buildShapeMatching(model->lattice, s.regionHalfWidth);
    else
        model->springs = detail::buildMassSpring(model->lattice);
    const double meshVolume = isClosed(mesh) ? signedVolume(mesh) : 0.0;
    const double h = model->lattice.cellSize;
    model->volume =
        meshVolume > 0 ? float(meshVolume) : float(double(model->lattice.cellCount()) * h * h * h);
    return model;
}

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

} // namespace

namespace {

// Every numeric setting against the table (ffdaabb/world.h: SettingRange), named "prefix.field".
template <class Settings>
void requireRanges(const char* prefix, const Settings& s, std::span<const SettingRange> ranges,
                   std::span<const detail::SettingMember<Settings>> members) {
    for (size_t i = 0; i < ranges.size(); ++i) {
        const SettingRange& r = ranges[i];
        const std::string field = std::string(prefix) + "." + r.field;
        // A float setting is compared with its bounds as floats: the bound a scene file gives
        // (read as a double, then stored as a float) is accepted here too.
        const double lo = r.integer ? r.min : double(float(r.min));
        const double hi = r.integer ? r.max : double(float(r.max));
        requireRange(field.c_str(), detail::settingValue(s, members[i]), lo, hi, r.expected);
    }
}

} // namespace

void validate(const WorldSettings& s) {
    requireRanges("world", s, worldSettingRanges(), detail::worldSettingMembers());
    requireFinite("world.gravity", s.gravity);
    if (s.mode != CollisionMode::Enhanced && s.mode != CollisionMode::Previous &&
        s.mode != CollisionMode::Brute && s.mode != CollisionMode::None)
        throw InputError("world.mode", "unknown collision mode");
}

void validate(const BodySettings& s) {
    requireRanges("body", s, bodySettingRanges(), detail::bodySettingMembers());
    requireFinite("body.position", s.position);
    requireFinite("body.velocity", s.velocity);
    requireFinite("body.angularVelocity", s.angularVelocity);
    if (s.motion != BodyMotion::Dynamic && s.motion != BodyMotion::Static &&
        s.motion != BodyMotion::Kinematic)
        throw InputError("body.motion", "unknown motion (expected dynamic, static or kinematic)");
    const Quat& q = s.rotation;
    const float n = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
    if (!(std::isfinite(n) && n > 1e-12f))
        throw InputError("body.rotation",
                         "rotation is not a valid quaternion (zero or non-finite)");
}

namespace detail {

CollisionWorld collisionView(WorldData& w) {
    return CollisionWorld{w.settings,       w.substep,   w.x,         w.v,
                          w.contactInvMass, w.nodes,     w.boxBounds, w.collision.bodies,
                          w.planes,         w.collision, w.workers,   w.profile};
}

void syncCollisionBodies(WorldData& w) {
    for (size_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& r = w.bodies[b];
        CollisionBody& c = w.collision.bodies[b];
        c.lattice = &r.model->lattice;
        c.massFraction = r.model->lattice.massFraction;
        c.firstParticle = r.firstParticle, c.particleCount = r.particleCount;
        c.firstBox = r.firstBox, c.boxCount = r.boxCount;
        c.cellSize = r.cellSize;
        c.mass = r.mass;
        c.friction = r.settings.friction;
        c.restitution = r.settings.restitution;
        c.contactRigidity = r.settings.contactRigidity;
    }
    CollisionWorld view = collisionView(w);
    rebuildCollisionTopology(view);
}

} // namespace detail

World::World(const WorldSettings& settings) : state_(std::make_unique<State>()) {
    validate(settings);
    state_->settings = settings;
    state_->workers.setThreads(settings.threads);
}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

BodyId World::addBody(const TriangleMesh& mesh, const BodySettings& settings) {
    validate(settings);
    validate(mesh, mesh.name.empty() ? "mesh" : mesh.name);
    WorldData& w = *state_;
    const std::string key = modelKey(mesh, settings);
    auto cached = w.modelCache.find(key);
    std::shared_ptr<const BodyModel> model =
        cached != w.modelCache.end() ? cached->second : buildModel(mesh, settings);
    if (cached == w.modelCache.end()) w.modelCache.emplace(key, model);

    const Lattice& L = model->lattice;
    BodyRecord r;
    r.model = model;
    r.settings = settings;
    r.settings.rotation = normalize(settings.rotation);
    r.mass = settings.mass > 0 ? settings.mass : settings.density * model->volume;
    r.cellSize = L.cellSize;
    r.firstParticle = uint32_t(w.x.size());
    r.particleCount = uint32_t(L.particleCount());
    r.firstBox = uint32_t(w.boxBounds.size());
    r.boxCount = uint32_t(L.boxes.size());
    r.firstVertex = uint32_t(w.vertices.size());
    r.vertexCount = uint32_t(mesh.positions.size());

    const Mat3 R = toMat3(r.settings.rotation);
    Vec3 centre{};
    for (uint32_t p = 0; p < r.particleCount; ++p)
        centre += (R * L.restParticles[p]) * model->lattice.massFraction[p];
    for (uint32_t p = 0; p < r.particleCount; ++p) {
        const Vec3 arm = R * L.restParticles[p];
        w.x.push_back(arm + settings.position);
        w.v.push_back(settings.velocity + cross(settings.angularVelocity, arm - centre));
        w.invMass.push_back(1.0f / (r.mass * model->lattice.massFraction[p]));
        w.particleForce.push_back({});
        w.rotations.push_back(r.settings.rotation);
        w.rotationSteps.push_back(Quat{});
    }
    w.nodes.resize(w.nodes.size() + size_t(r.boxCount) * 8);
    w.boxBounds.resize(w.boxBounds.size() + r.boxCount);
    w.vertices.resize(w.vertices.size() + r.vertexCount);

    uint32_t slot;
    if (!w.freeSlots.empty()) {
        slot = w.freeSlots.back();
        w.freeSlots.pop_back();
    } else {
        slot = uint32_t(w.slots.size());
        w.slots.push_back({});
    }
    r.slot = slot;
    w.slots[slot].dense = uint32_t(w.bodies.size());
    w.bodies.push_back(std::move(r));
    w.collision.bodies.emplace_back(); // placed: its overlaps will be remembered
    detail::syncCollisionBodies(w);
    detail::refreshAwake(w);
    const BodyId id{slot, w.slots[slot].generation};
    updateMesh(id);
    return id;
}

bool World::removeBody(BodyId id) {
    WorldData& w = *state_;
    const BodyRecord* found = w.find(id);
    if (!found) return false;
    detail::forgetPins(w, id);
    const uint32_t dense = w.slots[id.index].dense;
    detail::wakeIsland(w, dense); // the bodies it held up
    const BodyRecord r = *found;
    auto eraseRange = [](auto& vec, size_t first, size_t count) {
        vec.erase(vec.begin() + ptrdiff_t(first), vec.begin() + ptrdiff_t(first + count));
    };
    eraseRange(w.x, r.firstParticle, r.particleCount);
    eraseRange(w.v, r.firstParticle, r.particleCount);
    eraseRange(w.invMass, r.firstParticle, r.particleCount);
    eraseRange(w.contactInvMass, r.firstParticle, r.particleCount);
    eraseRange(w.particleForce, r.firstParticle, r.particleCount);
    eraseRange(w.rotations, r.firstParticle, r.particleCount);
    eraseRange(w.rotationSteps, r.firstParticle, r.particleCount);
    eraseRange(w.nodes, size_t(r.firstBox) * 8, size_t(r.boxCount) * 8);
    eraseRange(w.boxBounds, r.firstBox, r.boxCount);
    eraseRange(w.vertices, r.firstVertex, r.vertexCount);
    w.bodies.erase(w.bodies.begin() + dense);
    for (size_t b = dense; b < w.bodies.size(); ++b) {
        BodyRecord& later = w.bodies[b];
        later.firstParticle -= r.particleCount;
        later.firstBox -= r.boxCount;
        later.firstVertex -= r.vertexCount;
        w.slots[later.slot].dense = uint32_t(b);
    }
    w.slots[id.index].dense = UINT32_MAX;
    ++w.slots[id.index].generation;
    w.freeSlots.push_back(id.index);
    w.collision.pairs.clear();
    w.collision.all.clear(); // its contacts name the bodies' old ranges
    w.collision.objectCount = 0;
    detail::CollisionWorld view = detail::collisionView(w);
    detail::forgetBody(view, dense);
    detail::forgetBoxes(view, r.firstBox, r.boxCount);
    w.collision.bodies.erase(w.collision.bodies.begin() + dense);
    detail::syncCollisionBodies(w);
    detail::refreshAwake(w);
    detail::meshesChanged(w.queries);
    return true;
}

bool World::isValid(BodyId id) const {
    return state_->find(id) != nullptr;
}
size_t World::bodyCount() const {
    return state_->bodies.size();
}

std::vector<BodyId> World::bodies() const {
    std::vector<BodyId> ids;
    for (uint32_t b = 0; b < state_->bodies.size(); ++b) ids.push_back(state_->handleOf(b));
    return ids;
}

namespace {

const BodyRecord& get(const WorldData& w, BodyId id) {
    const BodyRecord* r = w.find(id);
    if (!r)
        throw InputError("body", "stale or invalid body handle (index " + std::to_string(id.index) +
                                     ", generation " + std::to_string(id.generation) + ")");
    return *r;
}

// What the collision stages know of the body (valid handle checked).
const detail::CollisionBody& collisionBody(const WorldData& w, BodyId id) {
    get(w, id);
    return w.collision.bodies[w.slots[id.index].dense];
}

// The body was added, moved or set: its overlaps are remembered at the next substep
// (collision/overlap_recovery.h).
void markPlaced(WorldData& w, BodyId id) {
    get(w, id);
    w.collision.bodies[w.slots[id.index].dense].placed = true;
}

// Something was done to the body: it wakes, with the bodies it fell asleep with, and its quiet
// time starts again (world/sleeping.h).
void wake(WorldData& w, BodyId id) {
    get(w, id);
    detail::wakeIsland(w, w.slots[id.index].dense);
}

void requireParticle(const BodyRecord& r, uint32_t particle) {
    if (particle >= r.particleCount)
        throw InputError("particle", "index " + std::to_string(particle) +
                                         " is out of range (body has " +
                                         std::to_string(r.particleCount) + " particles)");
}

} // namespace

namespace {

// Runs one stage, adds its time to the profile's field and tells the observer, if any.
template <class F>
void timed(WorldData& w, Stage stage, F&& run) {
    const auto start = Clock::now();
    run();
    w.profile.stageMs[size_t(stage)] += msSince(start);
    if (w.stageObserver) w.stageObserver(stage);
}

// Phase 1 in enhanced mode; the other modes pass every pair on (and spend nothing here).
void sphereTestStage(WorldData& w, detail::CollisionWorld& view) {
    if (w.settings.mode == CollisionMode::Enhanced) {
        timed(w, Stage::SphereTest, [&] { detail::sphereTest(view); });
        w.profile.candidatePairs = int(w.collision.pairs.size());
    } else if (w.settings.mode != CollisionMode::None) {
        const size_t n = w.bodies.size();
        w.profile.candidatePairs = int(n * (n - (n > 0)) / 2);
    }
}

} // namespace

// The stages in the order they run (ffdaabb/profile.h's table): each substep moves the
// lattices, finds the contacts on the current positions, speculatively (within what the bodies
// can travel this substep), and responds partly before the positions move and partly after
// (collision/contact.h).
void World::step() {
    WorldData& w = *state_;
    Profile& prof = w.profile;
    prof = Profile{};
    const auto frameStart = Clock::now();
    const float dt = w.settings.frameStep / float(w.settings.substeps);
    w.substep = dt;
    w.moving.clear(); // the kinematic bodies given a motion for this step
    for (const uint32_t b : w.kinematic) {
        const BodyRecord& r = w.bodies[b];
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i)
            if (lengthSquared(w.v[i]) > 0) {
                w.moving.push_back(b);
                break;
            }
    }
    timed(w, Stage::Sleeping, [&] { detail::wakeWithinReach(w); });
    detail::CollisionWorld view = detail::collisionView(w);
    float deepest = 0;
    for (int sub = 0; sub < w.settings.substeps; ++sub) {
        timed(w, Stage::Dynamics, [&] { detail::latticeDynamicsStage(w, dt); });
        FFD_CHECK(detail::particleProblem(w).empty(),
                  "after lattice_dynamics: " + detail::particleProblem(w));
        timed(w, Stage::NodeUpdate, [&] { detail::nodeUpdateStage(w, view); });
        FFD_CHECK(detail::nodeProblem(w).empty(), "after node_update: " + detail::nodeProblem(w));
        timed(w, Stage::OverlapRecovery, [&] {
            w.collision.pairs.clear();
            detail::trackOverlaps(view);
            detail::pushPairsApart(view, dt);
        });
        sphereTestStage(w, view);
        FFD_CHECK(w.settings.mode != CollisionMode::Enhanced || detail::sphereProblem(w).empty(),
                  "after sphere_test: " + detail::sphereProblem(w));
        timed(w, Stage::ObjectContacts, [&] { detail::findAllObjectContacts(view); });
        timed(w, Stage::FloorContacts, [&] { detail::findFloorContacts(view); });
        timed(w, Stage::OverlapSettling, [&] {
            detail::settleOverlaps(view);
            prof.overlapPairs = int(w.collision.overlaps.size());
            prof.wholePairs = int(w.collision.wholePairs.size());
        });
        timed(w, Stage::ResponseBeforeMove, [&] { detail::respondBeforeMove(view, dt); });
        timed(w, Stage::PositionUpdate, [&] {
            detail::positionUpdateStage(w, dt);
            detail::pinStage(w, dt, sub, w.settings.substeps); // nothing without pins
        });
        timed(w, Stage::ResponseAfterMove,
              [&] { deepest = maxNum(deepest, detail::respondAfterMove(view, dt)); });
        detail::tallyContacts(w);
    }
    detail::finishContactTally(w);
    for (BodyRecord& r : w.bodies) r.force = {};
    std::fill(w.particleForce.begin(), w.particleForce.end(), Vec3{});
    if (w.settings.meshUpdate) timed(w, Stage::MeshUpdate, [&] { detail::meshUpdateStage(w); });
    FFD_CHECK(detail::meshProblem(w).empty(), "after mesh_update: " + detail::meshProblem(w));
    timed(w, Stage::Sleeping, [&] { detail::fallAsleep(w); });
    for (const uint32_t b : w.moving) { // a kinematic body moves only as far as it is sent
        const BodyRecord& r = w.bodies[b];
        std::fill(w.v.begin() + r.firstParticle, w.v.begin() + r.firstParticle + r.particleCount,
                  Vec3{});
    }
    w.moving.clear();
    prof.sleepingBodies = int(w.sleeping);
    prof.maxContactDepth = deepest;
    prof.total = msSince(frameStart);
    ++w.frame;
    detail::meshesChanged(w.queries);
}

std::span<const Vec3> World::vertices(BodyId id) const {
    const BodyRecord& r = get(*state_, id);
    return {state_->vertices.data() + r.firstVertex, r.vertexCount};
}

std::span<const std::array<uint32_t, 3>> World::triangles(BodyId id) const {
    return get(*state_, id).model->mesh.triangles;
}

std::span<const Vec3> World::particles(BodyId id) const {
    const BodyRecord& r = get(*state_, id);
    return {state_->x.data() + r.firstParticle, r.particleCount};
}

std::span<const Vec3> World::velocities(BodyId id) const {
    const BodyRecord& r = get(*state_, id);
    return {state_->v.data() + r.firstParticle, r.particleCount};
}

std::span<const Vec3> World::allVertices() const {
    return state_->vertices;
}

std::span<const Vec3> World::allParticles() const {
    return state_->x;
}

std::span<const Vec3> World::allVelocities() const {
    return state_->v;
}

World::Ranges World::ranges(BodyId id) const {
    const BodyRecord& r = get(*state_, id);
    return {r.firstVertex, r.vertexCount, r.firstParticle, r.particleCount};
}

std::span<const Vec3> World::boxNodes(BodyId id) const {
    const BodyRecord& r = get(*state_, id);
    return {state_->nodes.data() + size_t(r.firstBox) * 8, size_t(r.boxCount) * 8};
}

const Lattice& World::lattice(BodyId id) const {
    return get(*state_, id).model->lattice;
}
Aabb World::bounds(BodyId id) const {
    return collisionBody(std::as_const(*state_), id).bounds;
}

void World::boundingSphere(BodyId id, Vec3& centre, float& radius) const {
    const detail::CollisionBody& r = collisionBody(std::as_const(*state_), id);
    centre = r.sphereCentre;
    radius = r.sphereRadius;
}

Vec3 World::centreOfMass(BodyId id) const {
    return detail::massWeightedMean(get(*state_, id), state_->x);
}

Vec3 World::linearVelocity(BodyId id) const {
    return detail::massWeightedMean(get(*state_, id), state_->v);
}

BodyInfo World::info(BodyId id) const {
    const BodyRecord& r = get(*state_, id);
    const Lattice& L = r.model->lattice;
    BodyInfo i;
    i.vertices = r.model->mesh.positions.size();
    i.triangles = r.model->mesh.triangles.size();
    i.cells = L.cellCount();
    i.surfaceCells = L.surfaceCellCount();
    i.particles = L.particleCount();
    i.cellSize = L.cellSize;
    i.mass = r.mass;
    return i;
}

void World::contacts(std::vector<ContactInfo>& out) const {
    const WorldData& w = *state_;
    out.clear();
    out.reserve(w.collision.all.size());
    for (const detail::Contact& c : w.collision.all) {
        ContactInfo info;
        info.bodyA = w.handleOf(c.bodyA);
        if (c.hasB) info.bodyB = w.handleOf(c.bodyB);
        info.point = detail::blend(c.a, w.collision.boxParticles, w.x);
        info.normal = c.normal;
        info.depth = c.depth();
        info.impulse = c.totalNormalImpulse();
        out.push_back(info);
    }
}

float World::particleMass(BodyId id, uint32_t particle) const {
    const BodyRecord& r = get(*state_, id);
    requireParticle(r, particle);
    return 1.0f / state_->invMass[r.firstParticle + particle];
}

const BodySettings& World::settings(BodyId id) const {
    return get(*state_, id).settings;
}

namespace {
bool isDynamic(const WorldData& w, BodyId id) {
    return get(w, id).settings.motion == BodyMotion::Dynamic;
}
} // namespace

void World::applyForce(BodyId id, Vec3 force) {
    requireFinite("force", force);
    if (!isDynamic(*state_, id)) return; // a collider takes no forces
    wake(*state_, id);
    state_->find(id)->force += force;
}

void World::applyImpulse(BodyId id, Vec3 impulse) {
    requireFinite("impulse", impulse);
    if (!isDynamic(*state_, id)) return;
    wake(*state_, id);
    const BodyRecord& r = get(*state_, id);
    const Vec3 dv = impulse / r.mass;
    for (uint32_t i = 0; i < r.particleCount; ++i) state_->v[r.firstParticle + i] += dv;
}

void World::applyParticleForce(BodyId id, uint32_t particle, Vec3 force) {
    requireFinite("force", force);
    const BodyRecord& r = get(*state_, id);
    requireParticle(r, particle);
    if (!isDynamic(*state_, id)) return;
    wake(*state_, id);
    state_->particleForce[r.firstParticle + particle] += force;
}

void World::translate(BodyId id, Vec3 offset) {
    requireFinite("offset", offset);
    wake(*state_, id);
    const BodyRecord& r = get(*state_, id);
    for (uint32_t i = 0; i < r.particleCount; ++i) state_->x[r.firstParticle + i] += offset;
    markPlaced(*state_, id);
    updateMesh(id);
}

void World::setVelocity(BodyId id, Vec3 velocity) {
    requireFinite("velocity", velocity);
    if (!isDynamic(*state_, id)) return;
    wake(*state_, id);
    const BodyRecord& r = get(*state_, id);
    for (uint32_t i = 0; i < r.particleCount; ++i) state_->v[r.firstParticle + i] = velocity;
    state_->find(id)->halfKick = true;
}

void World::setParticles(BodyId id, std::span<const Vec3> positions, bool resetVelocity) {
    const BodyRecord& r = get(*state_, id);
    if (positions.size() != r.particleCount)
        throw InputError("particles", "got " + std::to_string(positions.size()) +
                                          " positions, the body has " +
                                          std::to_string(r.particleCount) + " particles");
    for (uint32_t i = 0; i < r.particleCount; ++i) {
        if (!isFinite(positions[i]))
            throw InputError("particles", "position " + std::to_string(i) + " is not finite");
    }
    wake(*state_, id);
    for (uint32_t i = 0; i < r.particleCount; ++i) {
        state_->x[r.firstParticle + i] = positions[i];
        if (resetVelocity) state_->v[r.firstParticle + i] = {};
        state_->rotationSteps[r.firstParticle + i] = Quat{}; // a jump is not a steady turn
    }
    if (resetVelocity) state_->find(id)->halfKick = true;
    markPlaced(*state_, id);
    updateMesh(id);
}

void World::updateMesh(BodyId id) {
    WorldData& w = *state_;
    const BodyRecord& r = get(w, id);
    if (r.asleep) return; // its particles have not moved since it fell asleep
    const uint32_t dense = w.slots[id.index].dense;
    detail::CollisionWorld view = detail::collisionView(w);
    detail::updateNodes(view, dense, dense + 1);
    deformVertices(r.model->lattice,
                   std::span<const Vec3>(w.x.data() + r.firstParticle, r.particleCount),
                   std::span<Vec3>(w.vertices.data() + r.firstVertex, r.vertexCount));
    detail::meshesChanged(w.queries);
}

const WorldSettings& World::settings() const {
    return state_->settings;
}

void World::setSettings(const WorldSettings& settings) {
    validate(settings);
    WorldData& w = *state_;
    const WorldSettings& old = w.settings;
    // What holds a sleeping body where it is may have changed: everybody wakes.
    const bool disturbed = settings.gravity != old.gravity || settings.floor != old.floor ||
                           settings.floorHeight != old.floorHeight || settings.sleepSpeed == 0;
    w.settings = settings;
    w.workers.setThreads(settings.threads);
    if (disturbed) detail::wakeEverybody(w);
}

bool World::isAwake(BodyId id) const {
    return !get(*state_, id).asleep;
}

void World::setAwake(BodyId id, bool awake) {
    WorldData& w = *state_;
    const BodyRecord& r = get(w, id);
    const uint32_t dense = w.slots[id.index].dense;
    if (awake)
        detail::wakeIsland(w, dense);
    else if (!r.asleep && r.settings.allowSleep && r.settings.motion == BodyMotion::Dynamic)
        detail::putToSleep(w, &dense, 1);
}

size_t World::awakeCount() const {
    return state_->awake.size();
}

void World::setKinematicParticles(BodyId id, std::span<const Vec3> targets) {
    WorldData& w = *state_;
    const BodyRecord& r = get(w, id);
    if (r.settings.motion != BodyMotion::Kinematic)
        throw InputError("body.motion", std::string("the body is ") + toString(r.settings.motion) +
                                            " (expected kinematic)");
    if (targets.size() != r.particleCount)
        throw InputError("targets", "got " + std::to_string(targets.size()) +
                                        " targets, the body has " +
                                        std::to_string(r.particleCount) + " particles");
    for (uint32_t i = 0; i < r.particleCount; ++i)
        if (!isFinite(targets[i]))
            throw InputError("targets", "target " + std::to_string(i) + " is not finite");
    const float invT = 1.0f / w.settings.frameStep;
    for (uint32_t i = 0; i < r.particleCount; ++i)
        w.v[r.firstParticle + i] = (targets[i] - w.x[r.firstParticle + i]) * invT;
}

void World::setKinematicTarget(BodyId id, Vec3 position, Quat rotation) {
    requireFinite("position", position);
    const float n = rotation.w * rotation.w + rotation.x * rotation.x + rotation.y * rotation.y +
                    rotation.z * rotation.z;
    if (!(std::isfinite(n) && n > 1e-12f))
        throw InputError("rotation", "rotation is not a valid quaternion (zero or non-finite)");
    const BodyRecord& r = get(*state_, id);
    const Mat3 R = toMat3(normalize(rotation));
    const std::vector<Vec3>& rest = r.model->lattice.restParticles;
    std::vector<Vec3> targets(r.particleCount);
    for (uint32_t p = 0; p < r.particleCount; ++p) targets[p] = R * rest[p] + position;
    setKinematicParticles(id, targets);
}

PlaneId World::addPlane(Vec3 normal, float offset) {
    requireFinite("plane.normal", normal);
    if (!std::isfinite(offset))
        throw InputError("plane.offset", "value " + detail::valueText(offset) + " is not finite");
    const float len = length(normal);
    if (!(len > 1e-12f)) throw InputError("plane.normal", "the normal is zero");
    WorldData& w = *state_;
    w.planeSlots.push_back({Plane{normal / len, offset}, true});
    w.planes.push_back(w.planeSlots.back().first);
    detail::wakeEverybody(w); // a sleeper the plane cuts must be pushed out of it
    return PlaneId{uint32_t(w.planeSlots.size() - 1), 1};
}

bool World::isValid(PlaneId id) const {
    const WorldData& w = *state_;
    return id.generation == 1 && id.index < w.planeSlots.size() && w.planeSlots[id.index].second;
}

bool World::removePlane(PlaneId id) {
    if (!isValid(id)) return false;
    WorldData& w = *state_;
    w.planeSlots[id.index].second = false;
    w.planes.clear();
    for (const auto& [plane, live] : w.planeSlots)
        if (live) w.planes.push_back(plane);
    detail::wakeEverybody(w); // what held a sleeping body up may be gone
    return true;
}

std::vector<Plane> World::planes() const {
    return state_->planes;
}

void World::setTaskSystem(std::shared_ptr<TaskSystem> tasks) {
    state_->workers.setTaskSystem(std::move(tasks));
}

const std::shared_ptr<TaskSystem>& World::taskSystem() const {
    return state_->workers.taskSystem();
}

void World::setMode(CollisionMode mode) {
    WorldSettings s = state_->settings;
    s.mode = mode;
    setSettings(s);
}

const Profile& World::profile() const {
    return state_->profile;
}
uint64_t World::frame() const {
    return state_->frame;
}

uint64_t World::stateHash() const {
    uint64_t h = 14695981039346656037ull;
    h = fnv1a(h, state_->x.data(), state_->x.size() * sizeof(Vec3));
    h = fnv1a(h, state_->v.data(), state_->v.size() * sizeof(Vec3));
    return h;
}

double World::kineticEnergy() const {
    double e = 0;
    for (size_t i = 0; i < state_->v.size(); ++i)
        e += 0.5 * double(lengthSquared(state_->v[i])) / double(state_->invMass[i]);
    return e;
}

} // namespace ffd
