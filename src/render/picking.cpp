#include "ffdaabb/render.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ffd::render {

namespace {

/// Möller-Trumbore ray/triangle intersection: the distance along the (unit) ray to the
/// triangle, or a negative value for a miss.
float rayTriangle(Vec3 origin, Vec3 dir, Vec3 a, Vec3 b, Vec3 c) {
    const Vec3 e1 = b - a, e2 = c - a;
    const Vec3 p = cross(dir, e2);
    const float det = dot(e1, p);
    if (std::fabs(det) < 1e-12f) return -1;
    const float inv = 1.0f / det;
    const Vec3 s = origin - a;
    const float u = dot(s, p) * inv;
    if (u < 0 || u > 1) return -1;
    const Vec3 q = cross(s, e1);
    const float v = dot(dir, q) * inv;
    if (v < 0 || u + v > 1) return -1;
    return dot(e2, q) * inv;
}

/// Whether the ray meets the box before `maxDistance` (slab test).
bool rayHitsBox(Vec3 origin, Vec3 dir, const Aabb& box, float maxDistance) {
    float t0 = 0, t1 = maxDistance;
    for (int a = 0; a < 3; ++a) {
        const float d = std::fabs(dir[a]) > 1e-12f ? dir[a] : 1e-12f;
        float ta = (box.lo[a] - origin[a]) / d, tb = (box.hi[a] - origin[a]) / d;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta), t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    return true;
}

} // namespace

Pick pickBody(const World& world, const Camera& camera, int width, int height, float x, float y) {
    Vec3 origin, dir;
    pixelRay(camera, width, height, x, y, origin, dir);
    Pick pick;
    float best = std::numeric_limits<float>::max();
    for (BodyId b : world.bodies()) {
        // The bounds hold the whole deformed mesh: most bodies are skipped here.
        if (!rayHitsBox(origin, dir, world.bounds(b), best)) continue;
        const auto v = world.vertices(b);
        for (const auto& t : world.triangles(b)) {
            const float d = rayTriangle(origin, dir, v[t[0]], v[t[1]], v[t[2]]);
            if (d > 0 && d < best) best = d, pick.body = b;
        }
    }
    if (pick.body.isNull()) return pick;
    pick.point = origin + dir * best;
    pick.distance = best;
    const auto particles = world.particles(pick.body);
    float nearest = std::numeric_limits<float>::max();
    for (uint32_t i = 0; i < particles.size(); ++i) {
        const float d = lengthSquared(particles[i] - pick.point);
        if (d < nearest) nearest = d, pick.particle = i;
    }
    return pick;
}

} // namespace ffd::render
