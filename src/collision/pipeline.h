// The collision stages of World::step (ffdaabb/profile.h names them), each one function over
// the view of the world it is handed (collision/body.h: CollisionWorld):
//   node_update           FFD-AABB nodes from particles, per-box and per-object min/max
//   sphere_test           phase 1: bounding spheres and candidate object pairs (enhanced only)
//   object_contacts       phase 2 (spatial hash) + phase 3 (box pairs)
//   floor_contacts        node-vs-floor contacts
//   response_before_move  the solver schedule, pre-stabilisation, rigid impact phase
//   response_after_move   projection, velocity pass
// (the overlap recovery's stages are in collision/overlap_recovery.h)
// Reference: Jeon, Choi, Hong, "Enhanced FFD-AABB Collision Algorithm for Deformable Objects",
// 2012 (Fig. 2: the three phases); Jung, Hong, Choi, IET Image Processing 5(4), 2011.
#pragma once

#include "collision/contact.h"
#include "ffdaabb/world.h"

#include <vector>

namespace ffd::detail {

/// Rebuilds the node/box -> body lookups after bodies were added or removed.
void rebuildCollisionTopology(CollisionWorld& world);

/// After the boxes [first, first + count) were removed (and the later ones renumbered down by
/// count): drops the box pairs' claims that involve them and renumbers the others.
void forgetBoxes(CollisionWorld& world, uint32_t first, uint32_t count);

/// node_update for bodies [first, last): nodes, box bounds, body bounds.
void updateNodes(CollisionWorld& world, size_t firstBody, size_t lastBody);

/// Each awake body's bounding sphere (as sphereTest computes them), without the pairs; a
/// sleeping body keeps the one it fell asleep with.
void computeSpheres(CollisionWorld& world);
/// One body's bounding sphere.
void computeSphere(CollisionWorld& world, size_t body);

/// sphere_test: each body's bounding sphere (centre of its node bounds; radius reaching the
/// farthest corner of any of its box bounds, so that the test is conservative for the narrow
/// phase's inflated box bounds) and the candidate pairs (all pairs below
/// settings.sweepThreshold bodies, sort-and-sweep on x above), less the whole pairs of the
/// overlap recovery. Fills world.collision.pairs.
void sphereTest(CollisionWorld& world);

/// The pairs of bodies whose bounding spheres overlap (on the spheres as they are), into `out`:
/// by brute force up to settings.sweepThreshold bodies, by sort and sweep above (sphereTest's
/// pairs before the whole pairs are taken out).
void sphereTestPairs(CollisionWorld& world, std::vector<CandidatePair>& out);
/// Candidate pairs by brute force over all pairs (for tests of the sweep).
void sphereTestAllPairs(CollisionWorld& world, std::vector<CandidatePair>& out);
void sphereTestSweep(CollisionWorld& world, std::vector<CandidatePair>& out);

/// floor: contacts of box nodes with the floor, found on the current positions (speculative:
/// within the skin plus the distance the node can travel this substep), appended to
/// world.collision.all after the object contacts (findAllObjectContacts runs first).
void findFloorContacts(CollisionWorld& world);

/// What phases 2-3 tested: node/box pairs (phase 2), the box pairs they named (phase 3, each
/// tested once) and, of those, the pairs that gave a contact.
struct ObjectContactCounts {
    int nodeBoxPairs = 0;
    int boxPairs = 0;
    int contactBoxPairs = 0;
};

/// Phases 2-3 for `mode` (Enhanced uses world.collision.pairs from sphereTest): fills `out`
/// with the contacts in canonical order, and `counts`. Also sets the bodies' zone cells
/// (world.collision.solver.cells), whatever the mode, for the response of the same substep.
void findObjectContacts(CollisionWorld& world, CollisionMode mode, ContactList& out,
                        ObjectContactCounts& counts);

/// object_collision: findObjectContacts into world.collision.all, which findFloorContacts then
/// completes with the floor's: both are solved together so that piles and the floor push each
/// other consistently.
void findAllObjectContacts(CollisionWorld& world);

/// Sorts box-pair keys (low box << 32 | high box, each below `boxes`) ascending, as std::sort
/// would: by radix on the two halves packed together when there are many (`scratch` is reused).
void sortBoxPairKeys(std::vector<uint64_t>& keys, std::vector<uint64_t>& scratch, uint32_t boxes);

/// The solver's zone cells (contact.h, buildSolverSchedule): each body's cell on a grid over x
/// and z as wide as the widest body, so that bodies in contact lie in the same or neighbouring
/// cells. It depends on the positions alone, never on the thread count.
void zoneCells(const CollisionWorld& world, std::vector<ZoneCell>& cells);

/// The response before the position update: pre-stabilisation and the rigid phase (see
/// collision/contact.h). Reads the zone cells findObjectContacts set this substep.
void respondBeforeMove(CollisionWorld& world, float dt);

/// The response after the position update: projection with velocities following, then the
/// velocity pass. Returns the deepest remaining violation (metres).
float respondAfterMove(CollisionWorld& world, float dt);

} // namespace ffd::detail
