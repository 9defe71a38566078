// Rotational part of a 3x3 matrix for shape matching: the rotation R maximising tr(R^T A)
// (the polar factor of A when A is non-singular with det > 0).
//
// References: M. Mueller, J. Bender, N. Chentanez, M. Macklin, "A Robust Method to Extract the
// Rotational Part of Deformations", MIG 2016 (iterate on a unit quaternion, so that flat,
// degenerate and reflected matrices still give a proper rotation, and warm-start from the last
// step); B. K. P. Horn, "Closed-form solution of absolute orientation using unit quaternions",
// JOSA A 4(4), 1987 (the exact answer as the top eigenvector of a symmetric 4x4 matrix).
//
// refineRotation improves a warm-started q by Newton steps on f(q) = tr(R(q)^T A): in q's frame
// M = R^T A, gradient g = (M32 - M23, M13 - M31, M21 - M12), Hessian H = tr(M) I - sym(M). Near
// the optimum H is positive definite and convergence is quadratic; elsewhere it takes Mueller
// et al.'s step g / |tr M| (which alone converges only linearly: about a third of the error is
// left per iteration even for an isotropic region, enough to make a spinning body lag its
// rotation and lose energy). closestRotation is exact and used when the warm start is poor.
#pragma once

#include "dynamics/simd4.h"
#include "ffdaabb/math.h"

namespace ffd::detail {

/// Improves ioRotation towards the rotation maximising tr(R^T A) by at most maxIterations
/// steps, stopping when a step is below `tolerance` radians. Returns the last step's angle.
float refineRotation(const Mat3& A, Quat& ioRotation, int maxIterations, float tolerance = 1e-6f);

/// The rotation maximising tr(R^T A), exactly (Horn's quaternion method, Jacobi eigen-solve).
/// For A = 0 returns the identity.
Quat closestRotation(const Mat3& A);

/// refineRotation, falling back on closestRotation when the warm start was too far to converge
/// within maxIterations.
void extractRotation(const Mat3& A, Quat& ioRotation, int maxIterations);

} // namespace ffd::detail

namespace ffd::detail {

/// extractRotation for many matrices at once, four at a time with vector arithmetic:
/// a[e][r] is element e (row-major) of matrix r; rotations[r] is improved in place (count
/// entries). Lanes that need more than the warm-started Newton steps fall back on the scalar
/// path, so the result matches extractRotation's to rounding.
void extractRotations(const float* const a[9], Quat* rotations, size_t count, int maxIterations);

} // namespace ffd::detail

namespace ffd::detail {

/// extractRotation for four matrices at once (A[e] holds element e, row-major, of each lane's
/// matrix); q holds the warm starts and receives the results.
void extractRotations4(const F4 A[9], Q4& q, int maxIterations);

} // namespace ffd::detail
