// response_before_move and response_after_move: the solver schedule, pre-stabilisation, the
// rigid impact phase, the projection and the velocity pass over all contacts (collision/contact.h,
// collision/pipeline.h).
#include "collision/pipeline.h"
#include "util/check.h"

#include <algorithm>
#include <cmath>

namespace ffd::detail {

void zoneCells(const CollisionWorld& w, std::vector<ZoneCell>& cells) {
    float width = 0;
    for (const CollisionBody& r : w.bodies) {
        const Vec3 e = r.bounds.extent();
        width = maxNum(width, maxNum(e.x, e.z));
    }
    if (!(width > 0) || !std::isfinite(width)) width = 1;
    const float inverse = 1.0f / width;
    cells.resize(w.bodies.size());
    for (size_t b = 0; b < w.bodies.size(); ++b) {
        const Vec3 c = w.bodies[b].bounds.centre() * inverse;
        constexpr float kRange = 1 << 29;
        if (std::abs(c.x) < kRange && std::abs(c.z) < kRange)
            cells[b] = {int32_t(std::floor(c.x)), int32_t(std::floor(c.z))};
        else
            cells[b] = {ZoneCell::kNowhere, ZoneCell::kNowhere};
    }
}

namespace {

// The bodies' zone cells are those findObjectContacts computed this substep: their bounds have
// not changed since node_update.
void scheduleContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    FFD_CHECK(s.solver.cells.size() == w.bodies.size(),
              "solver schedule: " + std::to_string(s.solver.cells.size()) + " zone cells for " +
                  std::to_string(w.bodies.size()) + " bodies (object contacts not found first)");
    buildSolverSchedule(s.all, s.solver.cells, s.solver.schedule, w.workers, s.solver.bandContacts);
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
