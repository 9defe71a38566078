// Mass-spring dynamics on the FFD lattice's particles, the second model beside shape matching.
//
// Reference: M. Macklin, M. Mueller, N. Chentanez, "XPBD: Position-Based Simulation of
// Compliant Constrained Dynamics", MIG 2016. Each spring is a distance constraint with
// compliance 1/k. The springs project the current positions to goal positions (XPBD
// Gauss-Seidel), and the particles move towards them exactly as in shape matching:
//   v += (g - x) / dt + dt a;  x += dt v.
// For soft springs the goal displacement is dt^2 k C / m (Hooke's law, explicit); for stiff ones
// it saturates at the rest length, so the step is stable for any stiffness. Using the same
// update as shape matching gives resting contact the same equilibrium (goals balance gravity)
// and lets the collision response treat both models alike.
//
// Springs: structural (cell edges, length h), shear (face diagonals, sqrt(2) h), body diagonals
// (sqrt(3) h) and bending (two cells along an axis, 2h, through an existing middle particle).
// A spring of rest length L gets k = E L (a bar of cross-section L^2), E the Young's modulus.
#pragma once

#include "ffdaabb/lattice.h"

#include <span>
#include <vector>

namespace ffd::detail {

enum class SpringKind : uint8_t { Structural, Shear, Diagonal, Bending };

struct Spring {
    uint32_t a = 0, b = 0;
    float rest = 0;     ///< metres
    float stiffnessScale = 1; ///< k = E * rest * stiffnessScale
    SpringKind kind = SpringKind::Structural;
};

struct MassSpringModel {
    std::vector<Spring> springs; ///< in a fixed order (Gauss-Seidel is order dependent)
};

MassSpringModel buildMassSpring(const Lattice& lattice, float bendingScale = 0.2f);

struct MassSpringStep {
    float dt = 1.0f / 120.0f;
    float youngsModulus = 2e5f; ///< Pa
    float damping = 0.0f;       ///< fraction of the non-rigid velocity removed per substep
    Vec3 acceleration;
    int iterations = 4;
};

struct MassSpringScratch {
    std::vector<Vec3> goal;
    std::vector<float> lambda, mass;
};

/// One substep: goals by projecting the springs, damp non-rigid motion, integrate.
/// invMass: #P inverse particle masses (1/kg); x, v: #P.
void stepMassSpring(const MassSpringModel& model, const MassSpringStep& step,
                    std::span<const float> invMass, std::span<Vec3> x, std::span<Vec3> v,
                    MassSpringScratch& scratch);

/// Removes `fraction` of every particle's velocity relative to the body's best rigid motion
/// (linear and angular momentum kept exactly). mass: #P particle masses.
void dampNonRigidVelocity(std::span<const float> mass, std::span<const Vec3> x,
                          std::span<Vec3> v, float fraction);

} // namespace ffd::detail
