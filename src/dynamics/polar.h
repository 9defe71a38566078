// Rotational part of a 3x3 matrix for shape matching.
//
// Reference: M. Mueller, J. Bender, N. Chentanez, M. Macklin, "A Robust Method to Extract the
// Rotational Part of Deformations", MIG 2016. The rotation q is improved by turning it about
// omega = sum_k r_k x a_k / |sum_k r_k . a_k| (r_k, a_k the columns of R(q) and A), which
// climbs tr(R^T A). Unlike the polar decomposition through A^T A it never divides by a
// singular value, so flat (rank 2), degenerate (rank 1 or 0) and reflected (det < 0) matrices
// still give a proper rotation, and warm-starting from the last step's q makes one or two
// iterations enough.
#pragma once

#include "ffdaabb/math.h"

namespace ffd::detail {

/// Improves the unit quaternion ioRotation towards the rotation R maximising tr(R^T A).
/// Stops after maxIterations or when the correction angle falls below `tolerance` radians.
/// Returns the number of iterations used.
int extractRotation(const Mat3& A, Quat& ioRotation, int maxIterations, float tolerance = 1e-6f);

} // namespace ffd::detail
