// Exact-enough triangle/box predicates used to voxelise meshes.
//
// Reference: T. Akenine-Moeller, "Fast 3D Triangle-Box Overlap Testing", Journal of Graphics
// Tools 6(1), 2001 (separating axis test with the 13 candidate axes).
#pragma once

#include "ffdaabb/math.h"
#include "ffdaabb/mesh.h"

namespace ffd::detail {

/// True when the closed triangle (a,b,c) and the closed box [lo, hi] share a point. The box is
/// grown by `tolerance` on every side, so a positive tolerance makes the test conservative.
bool triangleOverlapsBox(Vec3 a, Vec3 b, Vec3 c, Vec3 lo, Vec3 hi, float tolerance = 0.0f);

/// Clips triangle (a,b,c) to the closed box [lo, hi] (Sutherland-Hodgman against its 6 planes)
/// and adds the resulting polygon's points to `ioBounds`. Returns false when nothing is left.
bool addClippedTriangle(Vec3 a, Vec3 b, Vec3 c, Vec3 lo, Vec3 hi, Aabb& ioBounds);

/// Generalised winding number of the triangles at p: the sum of their signed solid angles over
/// 4 pi, in double precision (van Oosterom and Strackee 1983; Jacobson et al. 2013). 1 inside a
/// closed, outward-wound mesh, 0 outside, in between for open ones. The library's own: the
/// interpenetration measure (bench/common) keeps its own, so that it shares no code with what
/// it judges.
double windingNumber(const TriangleMesh& mesh, Vec3 p);

} // namespace ffd::detail
