// Mass-spring dynamics on the FFD lattice's particles, the second model beside shape matching.
//
// Reference: D. Baraff, A. Witkin, "Large Steps in Cloth Simulation", SIGGRAPH 1998 (implicit
// Euler: (M - dt^2 K) dv = dt (f + dt K v), solved by conjugate gradients). Implicit Euler is
// stable at the frame step for any stiffness and, unlike position projection, has the true
// force equilibrium, so a body rests on the floor with its springs balancing gravity. The
// spring Jacobian's transverse term is dropped under compression so that the system stays
// symmetric positive definite (the usual definiteness fix).
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
    float rest = 0;           ///< metres
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
    int iterations = 20;            ///< conjugate-gradient iterations at most
    float tolerance = 1e-4f;        ///< relative residual at which CG stops
    bool integratePositions = true; ///< x += dt v here; the World does it after the contacts
};

struct MassSpringScratch {
    std::vector<Mat3> jacobian; ///< per spring, dF_a/dx_a
    std::vector<Vec3> force, rhs, dv, r, z, p, q, diag;
    std::vector<float> mass;
};

/// One implicit Euler substep: springs and gravity solved together, rigid-motion-preserving
/// damping, x += dt v. Returns the CG iterations used.
/// invMass: #P inverse particle masses (1/kg); x, v: #P.
int stepMassSpring(const MassSpringModel& model, const MassSpringStep& step,
                   std::span<const float> invMass, std::span<Vec3> x, std::span<Vec3> v,
                   MassSpringScratch& scratch);

/// Adds to ioVelocityChange `fraction` of every particle's velocity relative to the body's best
/// rigid motion, negated (so linear and angular momentum are unchanged). mass, x, v,
/// ioVelocityChange: #P.
void addNonRigidDamping(std::span<const float> mass, std::span<const Vec3> x,
                        std::span<const Vec3> v, float fraction, std::span<Vec3> ioVelocityChange);

} // namespace ffd::detail
