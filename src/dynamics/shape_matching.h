// Lattice shape matching on the FFD lattice's particles.
//
// Reference: A. R. Rivers, D. L. James, "FastLSM: Fast Lattice Shape Matching for Robust
// Real-Time Deformation", SIGGRAPH 2007; M. Mueller, B. Heidelberger, M. Teschner, M. Gross,
// "Meshless Deformations Based on Shape Matching", SIGGRAPH 2005 (the goal-position update);
// M. Mueller, B. Heidelberger, M. Hennix, J. Ratcliff, "Position Based Dynamics", 2006 (damping
// that leaves rigid motion alone, applied here per region).
//
// Region r (one per particle) holds the particles within the (2w+1)^3 cube of lattice points
// around particle r (FastLSM's regions; the same as w steps over 26-neighbour connectivity
// wherever the lattice has no gaps). Membership is symmetric, so the regions containing
// particle i are exactly the members of region i. With m~_i = m_i / |R_i|:
//   c_r = sum m~ x / M_r,  A_r = sum m~ x x0^T - M_r c_r c0_r^T,  R_r = rot(A_r),
//   g_i = mean over r in R_i of R_r (x0_i - c0_r) + c_r.
// Every sum is a box filter over the lattice's point grid, so FastLSM's separable summation
// (bars along x, plates along y, cubes along z) makes the cost independent of w.
#pragma once

#include "dynamics/simd4.h"
#include "ffdaabb/lattice.h"

#include <span>
#include <vector>

namespace ffd::detail {

/// Immutable shape-matching data of one lattice, shared by all bodies made from it.
struct ShapeMatchingModel {
    int halfWidth = 1;                   ///< w
    GridCoord pointDims{0, 0, 0};        ///< the lattice's point grid (cells + 1 per axis)
    std::vector<uint32_t> particlePoint; ///< #P index into the point grid (x fastest)
    std::vector<float> massFraction;     ///< #P m_i / M (sums to 1)
    std::vector<float> tildeMass;        ///< #P m~_i / M
    std::vector<float> regionSize;       ///< #P |R_i|
    std::vector<float> regionMass;       ///< #P M_r / M
    std::vector<Vec3> restCentred;       ///< #P x0_i - (rest centre of mass)
    std::vector<Vec3> regionRestCentre;  ///< #P c0_r, same frame
    std::vector<uint32_t> memberStart;   ///< #P + 1, CSR of region members (naive path, tests)
    std::vector<uint32_t> members;

    size_t pointCount() const { return size_t(pointDims[0]) * pointDims[1] * pointDims[2]; }
};

ShapeMatchingModel buildShapeMatching(const Lattice& lattice, int halfWidth);

/// Per-substep parameters.
struct ShapeMatchingStep {
    float dt = 1.0f / 120.0f;
    float stiffness = 1.0f;     ///< alpha in (0,1]
    float damping = 0.0f;       ///< fraction of the non-rigid velocity removed, [0,1]
    bool regionDamping = false; ///< damp relative to each region's rigid motion (else the body's)
    Vec3 acceleration;          ///< gravity + external force / mass, m/s^2
    int rotationIterations = 2; ///< warm-started polar iterations per region
    bool integratePositions = true; ///< x += dt v here; the World does it after the contacts
};

/// Reusable buffers (one per thread).
struct ShapeMatchingScratch {
    std::vector<float> a, b;   ///< channel-major padded grids
    std::vector<float> region; ///< per-region values between the passes
    std::vector<float> soa;    ///< per-region matrices, one array per element
    std::vector<Vec3> goal, rigidVelocity;
    // stepShapeMatching4: four bodies, one per lane.
    std::vector<F4> a4, b4; ///< point grids, 12 channels of four lanes per point
    std::vector<V4> x4, v4,
        dv4; ///< #P positions (relative to the mass centre), velocities, changes
};

/// One substep for one body: goals from the current positions, then
/// v += damping * (v_rigid - v) + alpha (g - x) / dt + dt a;  x += dt v.
/// x, v: #P; rotations: #P warm-start quaternions (one per region), updated.
/// `naive` sums over the explicit member lists instead (same result up to rounding).
void stepShapeMatching(const ShapeMatchingModel& model, const ShapeMatchingStep& step,
                       std::span<Vec3> x, std::span<Vec3> v, std::span<Quat> rotations,
                       ShapeMatchingScratch& scratch, bool naive = false);

/// One body's share of a stepShapeMatching4 call.
struct ShapeMatchingLane {
    std::span<const Vec3> x; ///< #P positions (not changed: the caller integrates)
    std::span<Vec3> v;       ///< #P velocities, updated
    std::span<Quat> rotations;
    /// Optional, #P: each region's rotation over the last substep. The next warm start
    /// continues it (a region turning steadily then needs a single Newton step); updated.
    std::span<Quat> rotationSteps;
    float stiffness = 1.0f;
    float damping = 0.0f; ///< fraction of the non-rigid velocity removed (the body's rigid motion)
    Vec3 acceleration;
};

/// stepShapeMatching (without region damping or integration) for `count` (1..4) bodies of the
/// same model at once, one per vector lane: every per-particle and per-region operation works on
/// four bodies. Lanes never mix: a body's result does not depend on the others in the call or
/// on its lane.
void stepShapeMatching4(const ShapeMatchingModel& model, float dt, int rotationIterations,
                        const ShapeMatchingLane* lanes, int count, ShapeMatchingScratch& scratch);

/// Goal positions only (no integration), for tests: outGoals #P.
void shapeMatchingGoals(const ShapeMatchingModel& model, std::span<const Vec3> x,
                        std::span<Quat> rotations, int rotationIterations,
                        ShapeMatchingScratch& scratch, std::span<Vec3> outGoals,
                        bool naive = false);

/// Internal forces change no momentum; this removes the float rounding that would make them:
/// subtracts the mass-weighted mean from ioVelocityChange (#P), the sums taken in double.
void removeMomentumDrift(std::span<const float> mass, std::span<Vec3> ioVelocityChange);

} // namespace ffd::detail
