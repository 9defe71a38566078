// Reference: T. Akenine-Moeller, "Fast 3D Triangle-Box Overlap Testing", JGT 6(1), 2001.
#include "lattice/geometry.h"

#include <cmath>

namespace ffd::detail {

namespace {

// Projects the triangle (relative to the box centre) and the box on `axis`; true when the two
// intervals are disjoint. A zero axis (parallel edges) separates nothing.
bool separatedOn(Vec3 axis, Vec3 v0, Vec3 v1, Vec3 v2, Vec3 half) {
    const double p0 = double(dot(axis, v0)), p1 = double(dot(axis, v1)), p2 = double(dot(axis, v2));
    const double r = double(half.x) * std::fabs(double(axis.x)) +
                     double(half.y) * std::fabs(double(axis.y)) +
                     double(half.z) * std::fabs(double(axis.z));
    const double lo = std::min(p0, std::min(p1, p2)), hi = std::max(p0, std::max(p1, p2));
    return lo > r || hi < -r;
}

} // namespace

bool triangleOverlapsBox(Vec3 a, Vec3 b, Vec3 c, Vec3 lo, Vec3 hi, float tolerance) {
    const Vec3 centre = (lo + hi) * 0.5f;
    const Vec3 half = (hi - lo) * 0.5f + Vec3{tolerance, tolerance, tolerance};
    const Vec3 v0 = a - centre, v1 = b - centre, v2 = c - centre;

    // The box's face normals: the triangle's bounds against the box.
    for (int axis = 0; axis < 3; ++axis) {
        const float tmin = std::min(v0[axis], std::min(v1[axis], v2[axis]));
        const float tmax = std::max(v0[axis], std::max(v1[axis], v2[axis]));
        if (tmin > half[axis] || tmax < -half[axis]) return false;
    }
    // The triangle's normal.
    const Vec3 e0 = v1 - v0, e1 = v2 - v1, e2 = v0 - v2;
    const Vec3 normal = cross(e0, e1);
    if (lengthSquared(normal) > 0) {
        const double d = double(dot(normal, v0));
        const double r = double(half.x) * std::fabs(double(normal.x)) +
                         double(half.y) * std::fabs(double(normal.y)) +
                         double(half.z) * std::fabs(double(normal.z));
        if (d > r || d < -r) return false;
    }
    // Edge x box-axis cross products.
    const Vec3 edges[3] = {e0, e1, e2};
    const Vec3 units[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3& e : edges)
        for (const Vec3& u : units)
            if (separatedOn(cross(e, u), v0, v1, v2, half)) return false;
    return true;
}

bool addClippedTriangle(Vec3 a, Vec3 b, Vec3 c, Vec3 lo, Vec3 hi, Aabb& ioBounds) {
    // A triangle clipped by 6 planes has at most 9 vertices.
    Vec3 bufferA[12] = {a, b, c}, bufferB[12];
    Vec3* in = bufferA;
    Vec3* out = bufferB;
    int count = 3;
    for (int plane = 0; plane < 6 && count > 0; ++plane) {
        const int axis = plane >> 1;
        const bool isMax = plane & 1;
        const float bound = isMax ? hi[axis] : lo[axis];
        auto inside = [&](Vec3 p) { return isMax ? p[axis] <= bound : p[axis] >= bound; };
        int written = 0;
        for (int i = 0; i < count; ++i) {
            const Vec3 p = in[i], q = in[(i + 1) % count];
            const bool pin = inside(p), qin = inside(q);
            if (pin) out[written++] = p;
            if (pin != qin) {
                const float t = (bound - p[axis]) / (q[axis] - p[axis]);
                Vec3 x = p + (q - p) * t;
                x[axis] = bound; // exactly on the plane despite rounding
                out[written++] = x;
            }
        }
        std::swap(in, out);
        count = written;
    }
    for (int i = 0; i < count; ++i) ioBounds.add(in[i]);
    return count > 0;
}

double windingNumber(const TriangleMesh& mesh, Vec3 p) {
    double sum = 0;
    for (const auto& t : mesh.triangles) {
        double r[3][3], len[3];
        for (int k = 0; k < 3; ++k) {
            const Vec3 d = mesh.positions[t[k]] - p;
            r[k][0] = d.x, r[k][1] = d.y, r[k][2] = d.z;
            len[k] = std::sqrt(r[k][0] * r[k][0] + r[k][1] * r[k][1] + r[k][2] * r[k][2]);
        }
        auto dotOf = [&](int a, int b) {
            return r[a][0] * r[b][0] + r[a][1] * r[b][1] + r[a][2] * r[b][2];
        };
        const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                           r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                           r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        const double den = len[0] * len[1] * len[2] + dotOf(0, 1) * len[2] + dotOf(1, 2) * len[0] +
                           dotOf(2, 0) * len[1];
        sum += 2 * std::atan2(det, den);
    }
    return sum / (4 * 3.14159265358979323846);
}

} // namespace ffd::detail
