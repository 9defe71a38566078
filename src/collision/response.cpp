// response_before_move and response_after_move: the solver schedule, pre-stabilisation, the
// rigid impact phase, the projection and the velocity pass over all contacts (collision/contact.h,
// collision/pipeline.h).
#include "collision/pipeline.h"
#include "util/check.h"

#include <algorithm>
#include <cmath>

namespace ffd::detail {

namespace {

// The solver's zones (contact.h, buildSolverSchedule): each body's cell on a grid over x and
// z as wide as the widest body, so that bodies in contact lie in the same or neighbouring
// cells. It depends on the positions alone, never on the thread count.
void scheduleContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    float width = 0;
    for (const CollisionBody& r : w.bodies) {
        const Vec3 e = r.bounds.extent();
        width = maxNum(width, maxNum(e.x, e.z));
    }
    if (!(width > 0) || !std::isfinite(width)) width = 1;
    const float inverse = 1.0f / width;
    std::vector<ZoneCell>& cells = s.solver.cells;
    cells.resize(w.bodies.size());
    for (size_t b = 0; b < w.bodies.size(); ++b) {
        const Vec3 c = w.bodies[b].bounds.centre() * inverse;
        constexpr float kRange = 1 << 29;
        if (std::abs(c.x) < kRange && std::abs(c.z) < kRange)
            cells[b] = {int32_t(std::floor(c.x)), int32_t(std::floor(c.z))};
        else
            cells[b] = {ZoneCell::kNowhere, ZoneCell::kNowhere};
    }
    buildSolverSchedule(s.all, cells, s.solver.schedule, w.workers);
}

// Turns each object contact's normal to its face of B's box (Contact::face) as the move left
// it: the normal boxPlanes gives that face, from the box's nodes as node_update makes them (the
// same normal, to rounding, when nothing moved), oriented as before. The contacts are found at the
// start of the substep; a face that turned fast within it (a letter's cell, 15 degrees in a substep
// as its letter landed) left them pushing along the face as it was, and the point went 1.1 cm in
// under the face as it is (docs/ALGORITHM.md §5, "Normals that follow their face"). A box whose
// volume halved or doubled in the substep is being crushed or restored: its faces swing by tens of
// degrees and are no guide, and its contacts keep their normals (followed there, spheres created
// deep in each other were thrown apart faster with every frame).
void followFaces(CollisionWorld& w) {
    CollisionState& s = w.collision;
    std::span<Contact> contacts(s.all.data(), s.objectCount);
    w.workers.forRange(contacts.size(), [&](size_t first, size_t last, int) {
        for (size_t n = first; n < last; ++n) {
            Contact& c = contacts[n];
            if (c.face == Contact::kNoFace) continue;
            const CollisionBody& B = w.bodies[c.bodyB];
            Vec3 nodes[8];
            updateBoxNodes(*B.lattice, std::span(w.x).subspan(B.firstParticle, B.particleCount),
                           c.b.box - B.firstBox, 1, nodes);
            const float volume = determinant(boxFrame(nodes) * s.planes[c.b.box].inverseFrame);
            if (!(volume > 0.5f && volume < 2.0f)) continue;
            const int* f = kFaceNodes[c.face];
            const Vec3 normal =
                normalize(cross(nodes[f[2]] - nodes[f[0]], nodes[f[3]] - nodes[f[1]]));
            if (isFinite(normal)) c.normal = dot(normal, c.normal) < 0 ? -normal : normal;
        }
    });
}

} // namespace

void respondBeforeMove(CollisionWorld& w, float dt) {
    CollisionState& s = w.collision;
    if (s.all.empty()) return;
    scheduleContacts(w);
#if FFD_CHECKS
    const std::string contacts = contactProblem(s.all, s.boxParticles, w.bodies.size(),
                                                s.bodyFirstParticle, s.bodyParticleCount);
    FFD_CHECK(contacts.empty(), "contacts: " + contacts);
    const std::string schedule = scheduleProblem(s.all, s.solver.schedule, w.bodies.size());
    FFD_CHECK(schedule.empty(), "solver schedule: " + schedule);
#endif
    const int iterations = w.settings.solverIterations;
    solveContactPositions(s.all, s.boxParticles, w.x, {}, w.invMass, dt, iterations,
                          w.bodies.size(), s.solver, w.workers);
    const float impact = 2.0f * length(w.settings.gravity) * dt;
    solveRigidPhase(s.all, s.boxParticles, s.rigid, s.rigidPoints, w.x, w.v, w.invMass,
                    s.bodyFirstParticle, s.bodyParticleCount, dt, impact,
                    w.settings.maxSeparationSpeed, iterations, s.solver, w.workers);
}

float respondAfterMove(CollisionWorld& w, float dt) {
    CollisionState& s = w.collision;
    if (s.all.empty()) return 0;
    const int iterations = w.settings.solverIterations;
    const float impact = 2.0f * length(w.settings.gravity) * dt;
    followFaces(w);
    if (w.settings.rigidProjection > 0)
        projectRigidModes(s.all, s.boxParticles, s.rigid, s.rigidPoints, w.x, w.v, w.invMass,
                          s.bodyFirstParticle, s.bodyParticleCount, dt, w.settings.rigidProjection,
                          iterations, s.solver, w.workers);
    solveContactPositions(s.all, s.boxParticles, w.x, w.v, w.invMass, dt, iterations,
                          w.bodies.size(), s.solver, w.workers);
    return solveContactVelocities(s.all, s.boxParticles, w.x, w.v, w.invMass, dt, impact,
                                  iterations, w.bodies.size(), s.solver, w.workers);
}

} // namespace ffd::detail
