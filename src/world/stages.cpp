// The world's own stages of World::step (ffdaabb/profile.h names them all): the lattice
// dynamics, the position update and the mesh update, per body on the world's workers, and the
// node update's split of the bodies across them.
#include "world/stages.h"

#include "collision/pipeline.h"
#include "dynamics/mass_spring.h"
#include "dynamics/shape_matching.h"
#include "world/world_data.h"

#include <map>

namespace ffd::detail {

namespace {

// Runs fn(first, last, scratch) over the items [0, n), split across the world's threads.
template <class F>
void forEachItem(WorldData& w, size_t n, F&& fn) {
    const size_t slots = size_t(w.workers.count());
    if (w.scratch.size() < slots) w.scratch.resize(slots);
    // Items are independent in these stages, so any split gives bit-identical results.
    w.workers.forRange(
        n, [&](size_t first, size_t last, int slot) { fn(first, last, w.scratch[size_t(slot)]); });
}

// Runs fn(body, scratch) for each awake body (a sleeping body does not move: world/sleeping.h)
// and each moving kinematic body (static bodies never move), split across the worker threads.
template <class F>
void forEachAwakeBody(WorldData& w, F&& fn) {
    const size_t awake = w.awake.size();
    forEachItem(w, awake + w.moving.size(), [&](size_t first, size_t last, ThreadScratch& scratch) {
        for (size_t k = first; k < last; ++k)
            fn(size_t(k < awake ? w.awake[k] : w.moving[k - awake]), scratch);
    });
}

// The external part of a body's substep: point forces through the particles' own masses, and
// the uniform acceleration (gravity, body forces) the model applies with its internal forces.
Vec3 externalKick(WorldData& w, BodyRecord& r, float dt) {
    const size_t p0 = r.firstParticle;
    for (size_t i = 0; i < r.particleCount; ++i) {
        const Vec3 f = w.particleForce[p0 + i];
        if (f.x != 0 || f.y != 0 || f.z != 0) w.v[p0 + i] += f * (dt * w.invMass[p0 + i]);
    }
    // Leapfrog start for the constant acceleration (gravity); user forces act in full.
    const Vec3 accel = w.settings.gravity * (r.halfKick ? 0.5f : 1.0f) + r.force / r.mass;
    r.halfKick = false;
    return accel;
}

} // namespace

void latticeDynamicsStage(WorldData& w, float dt) {
    const int rotationIterations = ShapeMatchingStep{}.rotationIterations;
    forEachItem(
        w, w.dynamicsBatches.size(), [&](size_t first, size_t last, ThreadScratch& scratch) {
            for (size_t k = first; k < last; ++k) {
                const DynamicsBatch& batch = w.dynamicsBatches[k];
                if (batch.lanes) {
                    ShapeMatchingLane lanes[4];
                    for (uint32_t l = 0; l < batch.count; ++l) {
                        BodyRecord& r = w.bodies[batch.body[l]];
                        const size_t p0 = r.firstParticle, np = r.particleCount;
                        lanes[l].acceleration = externalKick(w, r, dt);
                        lanes[l].x = std::span<const Vec3>(w.x.data() + p0, np);
                        lanes[l].v = std::span<Vec3>(w.v.data() + p0, np);
                        lanes[l].rotations = std::span<Quat>(w.rotations.data() + p0, np);
                        lanes[l].rotationSteps = std::span<Quat>(w.rotationSteps.data() + p0, np);
                        lanes[l].stiffness = r.settings.stiffness;
                        lanes[l].damping = 1.0f - std::exp(-r.settings.damping * dt);
                    }
                    stepShapeMatching4(w.bodies[batch.body[0]].model->shapeMatching, dt,
                                       rotationIterations, lanes, int(batch.count),
                                       scratch.shapeMatching);
                    continue;
                }
                BodyRecord& r = w.bodies[batch.body[0]];
                const size_t p0 = r.firstParticle, np = r.particleCount;
                std::span<Vec3> x(w.x.data() + p0, np), v(w.v.data() + p0, np);
                const Vec3 accel = externalKick(w, r, dt);
                const float damping = 1.0f - std::exp(-r.settings.damping * dt);
                if (r.model->dynamics == DynamicsModel::ShapeMatching) {
                    ShapeMatchingStep step;
                    step.dt = dt;
                    step.stiffness = r.settings.stiffness;
                    step.damping = damping;
                    step.regionDamping = r.settings.regionDamping;
                    step.acceleration = accel;
                    step.integratePositions = false;
                    stepShapeMatching(r.model->shapeMatching, step, x, v,
                                      std::span<Quat>(w.rotations.data() + p0, np),
                                      scratch.shapeMatching);
                } else {
                    MassSpringStep step;
                    step.dt = dt;
                    step.youngsModulus = r.settings.youngsModulus;
                    step.damping = damping;
                    step.acceleration = accel;
                    step.iterations = r.settings.springIterations;
                    step.integratePositions = false;
                    stepMassSpring(r.model->springs, step,
                                   std::span<const float>(w.invMass.data() + p0, np), x, v,
                                   scratch.massSpring);
                }
            }
        });
}

// Groups the awake shape-matching bodies of each model (without region damping) four at a time,
// in body order; every other awake body is a batch of its own.
void rebuildDynamicsBatches(WorldData& w) {
    w.dynamicsBatches.clear();
    std::map<const BodyModel*, size_t> open; // model -> its batch still filling
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& r = w.bodies[b];
        if (r.asleep || r.settings.motion != BodyMotion::Dynamic) continue;
        const bool lanes =
            r.model->dynamics == DynamicsModel::ShapeMatching && !r.settings.regionDamping;
        if (lanes) {
            auto it = open.find(r.model.get());
            if (it != open.end() && w.dynamicsBatches[it->second].count < 4) {
                DynamicsBatch& batch = w.dynamicsBatches[it->second];
                batch.body[batch.count++] = b;
                continue;
            }
            open[r.model.get()] = w.dynamicsBatches.size();
        }
        DynamicsBatch batch;
        batch.body[0] = b;
        batch.count = 1;
        batch.lanes = lanes;
        w.dynamicsBatches.push_back(batch);
    }
}

void nodeUpdateStage(WorldData& w, CollisionWorld& view) {
    forEachAwakeBody(w, [&](size_t b, ThreadScratch&) { updateNodes(view, b, b + 1); });
}

void positionUpdateStage(WorldData& w, float dt) {
    forEachAwakeBody(w, [&](size_t b, ThreadScratch&) {
        const BodyRecord& r = w.bodies[b];
        for (uint32_t i = r.firstParticle; i < r.firstParticle + r.particleCount; ++i)
            w.x[i] += w.v[i] * dt;
    });
}

void meshUpdateStage(WorldData& w) {
    forEachAwakeBody(w, [&](size_t b, ThreadScratch&) {
        const BodyRecord& r = w.bodies[b];
        deformVertices(r.model->lattice,
                       std::span<const Vec3>(w.x.data() + r.firstParticle, r.particleCount),
                       std::span<Vec3>(w.vertices.data() + r.firstVertex, r.vertexCount));
    });
}

} // namespace ffd::detail
