// Contacts and their response on lattice particles.
//
// A contact joins an embedded point of body A (a point of a box pair's manifold, or a boundary
// node for the floor) to an embedded point of body B (or the floor). Every embedded point is a
// trilinear blend sum_a w_a x_a of its cell's 8 particles, so a correction D at the point maps back
// to particles exactly: with inverse masses 1/m_a, moving particle a by (w_a / m_a) * D / W, W =
// sum w_a^2 / m_a, moves the point by D with the least mass-weighted motion. The correction is
// split between the two bodies by these generalised inverse masses (Position Based Dynamics,
// Mueller et al. 2006).
//
// The response of a substep. The dynamics has updated the velocities (not the positions), and
// the contacts were found on the current positions, speculatively (within what the bodies can
// travel in the substep). Then, in order:
//   0. pre-stabilisation: overlap that exists before the step (what the last substep's
//      iterations left) is projected away without touching velocities, so that it is not turned
//      into separating velocity (Macklin et al., "Unified Particle Physics for Real-Time
//      Applications", 2014, section 4.4);
//   1. rigid phase: the share `rigidity` of each impact's approach is removed through the
//      bodies' rigid modes (mass, centre, inertia of their particles). With stiff shape matching
//      an impulse on a few contact particles is spread over the body by the next dynamics step,
//      so a particle-only response removes just the contact particles' share of the momentum
//      per substep and a fast body sinks in deep before it stops; the rigid phase stops it at
//      once while leaving the rest of the impact to deform the body.
//   (the positions move: x += dt v)
//   2a. with WorldSettings::rigidProjection > 0, projection on the bodies' rigid modes of the
//      violation their rigid motions made in the move, with static friction at that level
//      (projectRigidModes): a load then reaches the whole body in the substep it arrives;
//   2. position projection, velocities following the correction (dv = dx / dt, position-based
//      dynamics): what the particles could not do they no longer "want" to do, so no velocity
//      survives hidden in the constraints' null space (a particle reached only through small
//      weights would otherwise keep a velocity that every projection cancels);
//   3. velocity pass: no contact closes more than its gap in the next substep (speculative),
//      restitution for impacts, Coulomb friction limited by all three phases' normal impulses.
// This order was chosen after measuring the alternatives (docs/ALGORITHM.md): Box2D's
// (velocities before the position update, projection without velocity change) left resting
// bodies vibrating at 1e-4 J/kg; projecting after the dynamics moved the positions, with the
// rigid phase after it, counted impacts twice and made resting bodies hop.
#pragma once

#include "collision/body.h"
#include "collision/narrow_phase.h"
#include "collision/spatial_hash.h"
#include "dynamics/simd4.h"
#include "ffdaabb/math.h"
#include "util/workers.h"

#include <array>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace ffd::detail {

/// The 8 corner particles of a box's cell (world-wide indices, corner i + 2j + 4k), per
/// world-wide box (CollisionState::boxParticles).
using BoxParticles = std::array<uint32_t, 8>;

/// An embedded point: a box (world-wide index) and local coordinates in its cell; its particles
/// are the box's cell's corners, with the trilinear weights of `local`. The weights are made
/// again wherever the point is read (PointWeights) rather than stored: a contact is 96 bytes
/// smaller, and the solver's sweeps, which read each contact several times a substep, are
/// bound by memory once a scene's contacts outgrow the cache (docs/BENCHMARKS.md).
struct ContactPoint {
    uint32_t box = 0;
    Vec3 local;
};

/// A point's particles and weights, as the solver uses them.
struct PointWeights {
    const uint32_t* particle = nullptr; ///< 8, in the box table
    float weight[8];
    PointWeights() = default;
    PointWeights(const ContactPoint& p, std::span<const BoxParticles> boxes)
        : particle(boxes[p.box].data()) {
        trilinearWeights(p.local, weight);
    }
};

struct Contact {
    ContactPoint a, b;  ///< b unused when !hasB (floor)
    Vec3 normal;        ///< unit, the direction A must move relative to B
    float offset = 0;   ///< constraint C = dot(pA - pB, normal) - offset >= 0
    float invMassA = 0; ///< sum w^2 / m over A's particles
    float invMassB = 0;
    float friction = 0.5f;
    float restitution = 0;
    float rigidity = 0; ///< share of the approach the rigid phase removes, [0, 1]
    float distance = 0; ///< signed distance to B's exit face (the floor) when detected
    /// Overlap (<= 0) the projections leave in this substep: what lies beyond the push-out depth
    /// of a deep contact (pushedOut), or beyond the depth its box pair can show
    /// (BoxPairManifold::depthBound); 0 otherwise (margins.h, object_contacts.cpp).
    float tolerated = 0;
    /// Its overlap goes over several substeps (push-out, overlap recovery): the rigid phase
    /// leaves it out, since its approach is its bodies restoring the dent the last push-out left.
    bool pushedOut = false;
    bool hasB = false;
    // Identification, for a canonical order and for tests.
    uint32_t bodyA = 0, bodyB = UINT32_MAX; ///< dense body indices
    /// A's point: its box x 8 + its index in the box pair's manifold (object contacts), or its
    /// node (floor contacts), or its mesh vertex (floor contacts at vertices).
    uint32_t nodeA = 0;
    uint32_t boxB = UINT32_MAX; ///< world-wide box index on B
    // Solver state.
    float approachSpeed = 0;   ///< normal velocity before the response
    float rigidImpulse = 0;    ///< normal impulse of the rigid phase and rigid projection
    float rigidFriction = 0;   ///< |tangential impulse| of the rigid projection's friction
    float positionImpulse = 0; ///< normal impulse of the projection (lambda / dt)
    float gap = 0;             ///< separation after the projection, >= 0
    float normalImpulse = 0;   ///< normal impulse of the velocity pass, >= 0
    Vec3 tangentImpulse;       ///< |.| <= friction * (rigid + position + normal impulses)
    /// Penetration when detected, metres (>= 0).
    float depth() const { return maxNum(0.0f, -distance); }
    /// The normal impulse the response applied over the substep, N s: its three phases'.
    float totalNormalImpulse() const { return rigidImpulse + positionImpulse + normalImpulse; }
};

/// Storage that leaves the elements a resize adds unwritten, for arrays each of whose new
/// elements a stage writes (on several threads, each at its place) before anything reads it:
/// a plain vector would first write every added element with its defaults, on one thread (for
/// the contacts of a substep, megabytes). Only for implicit-lifetime types, whose objects the
/// allocation itself creates.
template <class T>
struct UnwrittenAllocator : std::allocator<T> {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
    template <class U>
    struct rebind {
        using other = UnwrittenAllocator<U>;
    };
    UnwrittenAllocator() = default;
    template <class U>
    UnwrittenAllocator(const UnwrittenAllocator<U>&) noexcept {}
    template <class U>
    void construct(U*) noexcept {} // a resize's new element: written by its stage
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

/// A substep's contacts (the world's, a chunk's, the sort's scratch).
using ContactList = std::vector<Contact, UnwrittenAllocator<Contact>>;

/// An embedded point's value: the trilinear blend of its particles' `values` (positions or
/// velocities).
inline Vec3 blend(const PointWeights& p, std::span<const Vec3> values) {
    Vec3 r{};
    for (int k = 0; k < 8; ++k) r += values[p.particle[k]] * p.weight[k];
    return r;
}
inline Vec3 blend(const ContactPoint& p, std::span<const BoxParticles> boxes,
                  std::span<const Vec3> values) {
    return blend(PointWeights(p, boxes), values);
}

/// A contact's two points' particles and weights (b unset for the floor).
struct ContactWeights {
    PointWeights a, b;
    ContactWeights(const Contact& c, std::span<const BoxParticles> boxes) : a(c.a, boxes) {
        if (c.hasB) b = PointWeights(c.b, boxes);
    }
};

/// The contact's constraint C = (pA - pB) . n - offset on positions x: its points' separation
/// along the normal (negative: overlap).
inline float separation(const Contact& c, std::span<const BoxParticles> boxes,
                        std::span<const Vec3> x) {
    const Vec3 pb = c.hasB ? blend(c.b, boxes, x) : Vec3{};
    return dot(blend(c.a, boxes, x) - pb, c.normal) - c.offset;
}

/// Sort key giving every contact set the same order whichever pipeline found it: by A's node,
/// then B's box.
inline uint64_t contactKey(const Contact& c) {
    return (uint64_t(c.nodeA) << 32) | c.boxB;
}

/// Makes the embedded point at `local` in world-wide box `box`, and its generalised inverse
/// mass sum w^2 / m.
void makeContactPoint(uint32_t box, Vec3 local, std::span<const BoxParticles> boxes,
                      std::span<const float> invMass, ContactPoint& out, float& outInvMass);

/// The order in which the sweeps visit the contacts, for every thread count the same. The
/// contacts are grouped in zones, each swept in canonical order; the zones of one colour share
/// no body, so they are swept on any threads with the same result, and the colours one after
/// the other (buildSolverSchedule).
///
/// A pile with more contacts than a cache holds is swept in blocks: bands of zone rows, each
/// taken through a pass's first sweep and its later sweeps before the next band, colour after
/// colour within it (the tail, colour 4, in the last band). A band's contacts are read from
/// memory in its first sweep and from the cache in the later ones, where sweeping the whole
/// pile each time read every contact from memory in every sweep (docs/BENCHMARKS.md, "The large
/// pile's sweeps in blocks"). Fewer contacts than kBandContacts make one block: the sweeps as
/// without blocks.
struct SolverSchedule {
    std::vector<uint32_t> order;       ///< contact indices, zone by zone
    std::vector<uint32_t> zoneStart;   ///< zone z: order[zoneStart[z], zoneStart[z + 1])
    std::vector<uint32_t> colourStart; ///< colour c: zones [colourStart[c], colourStart[c + 1])
    /// Each block's and colour's zones, largest first (for balance): the zones of block b and
    /// colour c (blockZone) in another order.
    std::vector<uint32_t> bySize;
    /// With more than one block, (blocks + 1) rows of one entry per colour: block b's zones of
    /// colour c are [blockStart[b * colours + c], blockStart[(b + 1) * colours + c]). Empty: one
    /// block, the colours' zones.
    std::vector<uint32_t> blockStart;
    std::vector<uint32_t> zoneOf, zones, next;     ///< scratch of buildSolverSchedule
    std::vector<std::vector<uint32_t>> chunkZones; ///< scratch: the zones of each chunk
    size_t zoneCount() const { return zoneStart.empty() ? 0 : zoneStart.size() - 1; }
    size_t colourCount() const { return colourStart.empty() ? 0 : colourStart.size() - 1; }
    size_t blockCount() const {
        return blockStart.empty() ? 1 : blockStart.size() / colourCount() - 1;
    }
    /// The first zone of colour c in block b (b = blockCount(): the colour's end).
    uint32_t blockZone(size_t b, size_t c) const {
        if (blockStart.empty()) return b == 0 ? colourStart[c] : colourStart[c + 1];
        return blockStart[b * colourCount() + c];
    }
};

/// How many contacts a block of the solver's schedule holds before the next starts (at a row
/// of zones): about 4 MB of contacts with their particles, which a processor's last cache holds
/// beside the rest of the step. Measured on alphabets_x10 (docs/BENCHMARKS.md).
inline constexpr uint32_t kBandContacts = 32768;

/// A body's column of the solver's zones: the cell of its centre on a grid over x and z.
struct ZoneCell {
    static constexpr int32_t kNowhere = INT32_MIN; ///< a body without a finite centre
    int32_t i = 0, k = 0;
};

/// The zone grid's lowest cell over `cells` (bodies without a finite centre left out; INT32_MAX
/// for both when there are none).
void lowestZoneCell(std::span<const ZoneCell> cells, int32_t& i0, int32_t& k0);

/// The zone key of a contact between bodies in cells a and b (b = a for the floor), the grid's
/// lowest cell (i0, k0): colour (0-3), then the block's indices from the lowest cell
/// (kZoneIndexBits each); kTailZone for bodies more than a cell apart and blocks beyond the
/// indices' range. Zones sorted by key are the schedule's order.
inline constexpr int kZoneIndexBits = 14;
inline constexpr uint32_t kZoneIndexMask = (1u << kZoneIndexBits) - 1;
inline constexpr uint32_t kTailZone = 4u << 2 * kZoneIndexBits;
uint32_t zoneKey(ZoneCell a, ZoneCell b, int32_t i0, int32_t k0);

/// Groups the contacts in zones by their bodies' cells (`cells`, per dense body index; any
/// grid whose cells are at least as wide as every body gives few contacts outside the zones):
/// a contact's zone is the 2 x 2 block of cells whose lowest corner is the lowest of its bodies'
/// cells (its body's cell for the floor); the blocks with both corner indices of the same
/// parities form a colour and share no body. A contact between bodies more than a cell apart
/// goes to a last zone of its own colour. Each zone keeps the contacts' order.
/// More than `bandContacts` contacts are swept in blocks (SolverSchedule), each band of zone
/// rows holding at least that many but the last.
void buildSolverSchedule(std::span<const Contact> contacts, std::span<const ZoneCell> cells,
                         SolverSchedule& out, Workers& workers,
                         uint32_t bandContacts = kBandContacts);

/// What is wrong with `schedule` for `contacts` between `bodyCount` bodies (empty: nothing):
/// every contact once in its order, zones and colours in range and in order, and no body in
/// two zones of one colour but the last (the tail, one zone). The zones of a colour are swept
/// at once, so a body shared between two would be written by two threads. Checked after every
/// build with FFD_CHECKS (util/check.h); tests call it directly.
std::string scheduleProblem(std::span<const Contact> contacts, const SolverSchedule& schedule,
                            size_t bodyCount);

/// What is wrong with the contacts between `bodyCount` bodies, body b owning the particles
/// [firstParticle[b], firstParticle[b] + particleCount[b]) (empty: nothing): bodies in range
/// and distinct, points in boxes of the table with finite coordinates, on their own bodies'
/// particles.
std::string contactProblem(std::span<const Contact> contacts, std::span<const BoxParticles> boxes,
                           size_t bodyCount, std::span<const uint32_t> firstParticle,
                           std::span<const uint32_t> particleCount);

/// Scratch of the position and velocity sweeps: each contact's slack after the first sweep,
/// each body's reach (how far the first sweep moved it), the contacts the later sweeps visit
/// (zone by zone, as the schedule's) and the schedule. bodyCount: the dense body indices are
/// below it.
struct SolverScratch {
    std::vector<float> slack, bodyReach, zoneDeepest;
    /// The particles' positions and velocities as the sweeps read and write them: one 4-lane
    /// vector each (the fourth lane unused), so that a point's blend and push are vector
    /// operations, each the same arithmetic lane by lane as on Vec3 (contact_solver.cpp).
    std::vector<F4> x4, v4;
    /// The contacts the later sweeps visit, and the rigid phase's impacts: zone z's at
    /// [schedule.zoneStart[z], activeEnd[z]) (impactEnd[z]).
    std::vector<uint32_t> active, activeEnd, impacts, impactEnd;
    std::vector<ZoneCell> cells; ///< per body, its zone cell (findObjectContacts): the order of
                                 ///< the queries, of the contacts and of the schedule
    SolverSchedule schedule;
    /// The contacts of a block of the schedule (buildSolverSchedule); tests set fewer, to sweep
    /// a small pile in blocks.
    uint32_t bandContacts = kBandContacts;
};

/// A body as a rigid whole, for the rigid phase.
struct RigidState {
    Vec3 centre;
    float invMass = 0;
    Mat3 invInertia;
    Vec3 velocity, angularVelocity; ///< of the particles' rigid motion (mean, least squares)
    Vec3 dv, dw;                    ///< accumulated linear / angular velocity change
    uint32_t firstParticle = 0, particleCount = 0;
    bool active = false;
};

/// Per-contact scratch of the rigid phase.
struct RigidPoint {
    Vec3 armA, armB;    ///< r x n on A and B: the normal's angular direction
    Vec3 turnA, turnB;  ///< I^-1 (r x n): angular velocity change per unit normal impulse
    float invMassA = 0; ///< A's linear inverse mass (0 when A is not involved)
    float invMassB = 0; ///< B's, 0 for the floor
    float invK = 0;     ///< 1 / (normal inverse effective mass of the pair)
    float target = 0;   ///< rigid normal velocity the phase aims at
    float normalImpulse = 0;
    float rigidity = 0; ///< the contact's rigidity, ramped by its approach speed
    // The contact's fields the rigid phase's sweeps read, copied here so that a sweep reads
    // the point alone, not the contact it stands for as well: in a pile ten times the paper's,
    // the response took 0.95 of its time (docs/BENCHMARKS.md).
    Vec3 normal;
    float approachSpeed = 0;
    uint32_t bodyA = 0, bodyB = UINT32_MAX; ///< bodyB UINT32_MAX: no body B (the floor)
    // The projection on rigid modes (projectRigidModes): the arms, the tangential slip of the
    // bodies' rigid motion in the move, and its static-friction impulse (times dt).
    Vec3 rA, rB, slip, tangent;
};

/// Fills mass, centre and inertia of every body whose state is flagged active, and its rigid
/// velocity and angular velocity when `v` is given (zero when it is empty); states[j] is body
/// firstBody + j's.
void prepareRigidStates(std::span<const Vec3> x, std::span<const Vec3> v,
                        std::span<const float> invMass, std::span<const uint32_t> firstParticle,
                        std::span<const uint32_t> particleCount, std::span<RigidState> states,
                        size_t firstBody = 0);

/// Step 1: for impacts (approaching faster than impactThreshold; contacts pushedOut are never
/// impacts), removes the share `rigidity`
/// of the approach beyond what the contact may close in this substep (speculative bound),
/// through the bodies' rigid modes (normal impulses only), then applies the change to the
/// bodies' particles. maxSeparationSpeed > 0 bounds how fast the phase may push two bodies'
/// rigid motions apart at a contact (0: no bound). Records approachSpeed and rigidImpulse of
/// every contact.
void solveRigidPhase(std::span<Contact> contacts, std::span<const BoxParticles> boxes,
                     std::vector<RigidState>& states, std::vector<RigidPoint>& points,
                     std::span<const Vec3> x, std::span<Vec3> v, std::span<const float> invMass,
                     std::span<const uint32_t> firstParticle,
                     std::span<const uint32_t> particleCount, float dt, float impactThreshold,
                     float maxSeparationSpeed, int iterations, SolverScratch& scratch,
                     Workers& workers);

/// Step 2a (WorldSettings::rigidProjection > 0): Gauss-Seidel projection through the bodies'
/// rigid modes of the share `share` of the violation (below `tolerated`) that the bodies' rigid
/// motions made in the move, with static friction (Coulomb-limited by the normal correction):
/// each sweep moves the two bodies of a contact as rigid wholes (mass, centre and inertia of
/// their particles), so that a load reaches the whole body in the substep it arrives. The
/// particles then move by the bodies' moves (rotations exact), velocities following; each
/// contact's rigidImpulse gains the normal impulse and rigidFriction holds the tangential one,
/// which the velocity pass's friction limit counts.
void projectRigidModes(std::span<Contact> contacts, std::span<const BoxParticles> boxes,
                       std::vector<RigidState>& states, std::vector<RigidPoint>& points,
                       std::span<Vec3> x, std::span<Vec3> v, std::span<const float> invMass,
                       std::span<const uint32_t> firstParticle,
                       std::span<const uint32_t> particleCount, float dt, float share,
                       int iterations, SolverScratch& scratch, Workers& workers);

/// Steps 0 and 2: Gauss-Seidel position projection of C >= tolerated; velocities follow the
/// corrections unless `v` is empty (pre-stabilisation).
void solveContactPositions(std::span<Contact> contacts, std::span<const BoxParticles> boxes,
                           std::span<Vec3> x, std::span<Vec3> v, std::span<const float> invMass,
                           float dt, int iterations, size_t bodyCount, SolverScratch& scratch,
                           Workers& workers);

/// Step 3: the speculative normal bound, restitution (approaches faster than bounceThreshold)
/// and Coulomb friction. Returns the deepest remaining violation of the contacts' constraints
/// (metres, >= 0; the positions do not change in this step).
float solveContactVelocities(std::span<Contact> contacts, std::span<const BoxParticles> boxes,
                             std::span<const Vec3> x, std::span<Vec3> v,
                             std::span<const float> invMass, float dt, float bounceThreshold,
                             int iterations, size_t bodyCount, SolverScratch& scratch,
                             Workers& workers);

/// An object pair that passed the bounding-sphere test (dense body indices, a < b).
struct CandidatePair {
    uint32_t a = 0, b = 0;
    friend bool operator==(const CandidatePair&, const CandidatePair&) = default;
};

/// A pair of bodies placed overlapping, remembered until apart (overlap_recovery.h).
struct OverlapPair {
    uint32_t a = 0, b = 0; ///< dense indices, a < b; b = kFloorBody for the floor
    uint8_t whole = 0;     ///< pushed apart as whole bodies, no object contacts (this substep)
    uint8_t deep = 0;      ///< recovering: a contact deeper than the skin once, overlapping since
    uint8_t confirmed = 0; ///< ever deeper than the skin or a centre inside the other
    /// The way out for a: its overlapping contacts' normals (pointing from b to a) weighted by
    /// their overlap, summed over the last substep's contacts; zero when it had none.
    Vec3 out{};
    float depth = 0; ///< the deepest of those contacts' overlap
};

/// The depth a box pair claimed in a substep (object_contacts.cpp, emitPairs).
struct BoxPairClaim {
    uint64_t key = 0;  ///< low box << 32 | high box
    float claimed = 0; ///< the overlap its contacts were allowed to remove
    float deepest = 0; ///< its deepest point's overlap
};

/// Collision buffers kept between steps (no steady-state allocation).
struct CollisionState {
    std::vector<CollisionBody> bodies; ///< per dense body index, in the world's order
    std::vector<CandidatePair> pairs;
    std::vector<uint32_t> partnerStart, partners; ///< CSR of each body's candidate partners
    std::vector<uint8_t> isCandidate;             ///< per body
    std::vector<uint32_t> sweepOrder;
    std::vector<float> sweepLo, sweepHi; ///< per body, its extent along x in the sweep
    /// Per body, its extents along y and z (lo y, hi y, lo z, hi z), tested before the spheres.
    std::vector<std::array<float, 4>> sweepAcross;
    std::vector<std::vector<CandidatePair>> sweepChunks; ///< the sweep's pairs, per chunk
    std::vector<float> reach, skin; ///< per body, its terms of the margin (margins.h)
    SpatialHash hash;
    std::vector<BoxPlanes> planes;    ///< per box, for the narrow phase
    std::vector<uint32_t> planeStamp; ///< planes[b] is current when planeStamp[b] == stamp
    uint32_t stamp = 0;
    std::vector<uint64_t> boxPairKeys; ///< this substep's box pairs, (low box << 32 | high box)
    /// What each box pair with contacts claimed in the last substep (sorted by key), which
    /// bounds what it may claim in this one (object_contacts.cpp, emitPairs); this substep's, made
    /// by findObjectContacts and kept by findAllObjectContacts.
    std::vector<BoxPairClaim> claims, nextClaims;
    /// Per worker thread, what its box queries use and find (findObjectContacts).
    struct QueryScratch {
        std::vector<uint8_t> partnerMark; ///< per body, during a box's query
        std::vector<float> partnerMargin; ///< per body, its margin against the querying object
        std::vector<uint64_t> keys;       ///< the box pairs it found (merged, sorted, unique)
        std::vector<uint64_t> keySortScratch;
        int potential = 0; ///< node/box pairs it tested
        /// The partners of the body whose boxes it flags: their bounds one by one, or their
        /// unions when there are many.
        std::vector<Aabb> partnerBounds, partnerQueryBounds;
        /// The same bounds four partners to a group, six lanes a group (lo x, y, z, hi x, y, z;
        /// NaN past the last partner).
        std::vector<F4> partnerLanes, partnerQueryLanes;
        Aabb reachUnion, queryUnion;
        bool individual = true;
        /// The querying body's queried boxes and their query bounds, and the grouped query's
        /// scratch.
        std::vector<uint32_t> queryBoxes;
        std::vector<Aabb> queryWithin;
        std::vector<uint64_t> lastKey; ///< per queried box, the box pair it found last
        SpatialHash::GroupScratch group;
    };
    std::vector<QueryScratch> queryScratch;
    /// Per chunk of box pairs (a fixed number of consecutive keys), the contacts and claims of
    /// its pairs: concatenated in chunk order, as one thread would have made them.
    struct PairChunk {
        ContactList contacts;
        std::vector<BoxPairClaim> claims;
        int touching = 0; ///< pairs that gave a contact
    };
    std::vector<PairChunk> pairChunks;
    std::vector<uint32_t> planeBoxes; ///< the boxes whose planes this substep's pairs use
    /// Per body, its bounds grown by its reach and by its skin and reach; for `previous`, their
    /// prefix and suffix unions.
    std::vector<Aabb> reachBounds, queryBounds;
    std::vector<Aabb> prefixBounds, suffixBounds, prefixQueryBounds, suffixQueryBounds;
    std::vector<uint8_t> boxFlags;               ///< per box: queried, hashed (this substep)
    std::vector<uint32_t> hashedSamples;         ///< per body, its boxes' samples hashed (substep)
    std::vector<SpatialHash::Batch> hashBatches; ///< the samples staged per batch of bodies
    /// This substep's contacts: the objects' (canonical order), then the floor's.
    ContactList all;
    // Scratch of the canonical sort: where the contacts come from, their keys, the result.
    std::vector<std::span<const Contact>> sortSpans;
    std::vector<const Contact*> sortSources;
    std::vector<uint32_t> queryOrder; ///< the bodies in the order their boxes query the table
    std::vector<std::pair<uint64_t, uint32_t>> sortKeys, sortKeyScratch;
    ContactList sortScratch;
    size_t objectCount = 0;
    /// Per body, where its floor or plane contacts start in `all` (findFloorContacts).
    std::vector<size_t> floorStart;
    /// A mesh vertex near a plane (WorldSettings::vertexFloorContacts): its box (world-wide),
    /// its local coordinates in the box's cell, the plane, where it is and where its velocity
    /// takes it over the substep (signed distances to the plane).
    struct PlaneVertex {
        uint32_t box = 0, vertex = 0, plane = 0;
        Vec3 local, position;
        float distance = 0, ahead = 0;
    };
    /// Per body, its vertices chosen for plane contacts this substep (floor.cpp); per thread,
    /// the vertices near a plane of the box at hand.
    std::vector<std::vector<PlaneVertex>> planeVertices, planeVertexScratch;
    std::span<const Contact> objectContacts() const { return {all.data(), objectCount}; }
    std::span<const Contact> floorContacts() const {
        return {all.data() + objectCount, all.size() - objectCount};
    }
    std::vector<uint32_t> nodeBody, boxBody; ///< world-wide node/box -> dense body
    std::vector<BoxParticles> boxParticles;  ///< per world-wide box, for the contact points
    std::vector<RigidState> rigid;           ///< per body, for the rigid phase
    std::vector<uint32_t> bodyFirstParticle, bodyParticleCount;
    std::vector<RigidPoint> rigidPoints;
    SolverScratch solver; ///< scratch of the projection and velocity pass
    // Overlap recovery (overlap_recovery.h).
    std::vector<OverlapPair> overlaps;   ///< remembered pairs, sorted by (a, b)
    std::vector<uint64_t> wholePairs;    ///< this substep's whole pairs, (a << 32 | b), sorted
    std::vector<Vec3> overlapCentre;     ///< per body, centre of mass (pairs' bodies only)
    std::vector<Vec3> overlapPush[2];    ///< per kind of pair (whole, by contacts), per body
    std::vector<float> overlapWeight[2]; ///< the same, scratch
    /// Per body: its heap (the lowest body of it; itself when in none), the heap's bodies,
    /// mass, centre of mass and reach from it across gravity (kept at the heap's entry).
    std::vector<uint32_t> heapOf, heapSize;
    std::vector<float> heapMass, heapReach;
    std::vector<Vec3> heapCentre, heapSpread; ///< per heap; per body, its push (spreadHeaps)
    std::vector<Vec3> overlapVelocity, overlapVelocityBefore; ///< per body, scratch
    /// This substep's bounding-sphere pairs, found by trackOverlaps when bodies were just placed
    /// (`overlapNearFound` set; nothing moves before spreadHeaps reads them) or else by
    /// spreadHeaps itself.
    std::vector<CandidatePair> overlapScratch;
    bool overlapNearFound = false;
    std::vector<OverlapPair> overlapAdded, overlapMerged; ///< scratch
};

} // namespace ffd::detail
