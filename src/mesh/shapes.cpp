// Collider shapes: a box and a bowl (ffdaabb/generators.h).
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"

#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace ffd {

TriangleMesh box(Vec3 h, int n) {
    if (!(h.x > 0 && h.y > 0 && h.z > 0) || !std::isfinite(h.x + h.y + h.z))
        throw InputError("box", "half extents must be positive and finite");
    if (n < 1 || n > 256) throw InputError("box", "quads per edge must be in 1..256");
    TriangleMesh mesh;
    mesh.name = "box";
    const int axes[3][2] = {{1, 2}, {2, 0}, {0, 1}}; // the two axes spanning each face
    for (int axis = 0; axis < 3; ++axis)
        for (int sign : {-1, 1}) {
            const uint32_t first = uint32_t(mesh.positions.size());
            const int u = axes[axis][sign > 0 ? 0 : 1], v = axes[axis][sign > 0 ? 1 : 0];
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i) {
                    float p[3];
                    p[axis] = float(sign);
                    p[u] = -1.0f + 2.0f * float(i) / float(n);
                    p[v] = -1.0f + 2.0f * float(j) / float(n);
                    mesh.positions.push_back({p[0] * h.x, p[1] * h.y, p[2] * h.z});
                }
            auto at = [&](int i, int j) { return first + uint32_t(j * (n + 1) + i); };
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                    mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
                }
        }
    cleanup(mesh); // the faces share their edges' vertices: closed
    return mesh;
}

TriangleMesh bowl(float radius, float thickness, int segments) {
    if (!(radius > 0) || !std::isfinite(radius))
        throw InputError("bowl", "radius must be positive and finite");
    if (!(thickness > 0 && thickness < radius))
        throw InputError("bowl", "thickness must be in (0, radius)");
    if (segments < 8 || segments > 1024) throw InputError("bowl", "segments must be in 8..1024");
    // The profile in (r, y), from the outer pole up to the rim and down the inside to the inner
    // pole, revolved about y: a closed hemispherical shell with a flat rim at y = 0.
    const int arc = segments / 4; // steps of each quarter arc
    std::vector<std::pair<float, float>> profile;
    const float inner = radius - thickness;
    for (int k = 0; k <= arc; ++k) {
        const float a = 0.5f * std::numbers::pi_v<float> * float(k) / float(arc);
        profile.push_back({radius * std::sin(a), -radius * std::cos(a)});
    }
    for (int k = arc; k >= 0; --k) {
        const float a = 0.5f * std::numbers::pi_v<float> * float(k) / float(arc);
        profile.push_back({inner * std::sin(a), -inner * std::cos(a)});
    }
    TriangleMesh mesh;
    mesh.name = "bowl";
    const int rings = int(profile.size()) - 2; // the first and last points are the poles
    mesh.positions.push_back({0, profile.front().second, 0});
    for (int k = 1; k <= rings; ++k)
        for (int s = 0; s < segments; ++s) {
            const float t = 2.0f * std::numbers::pi_v<float> * float(s) / float(segments);
            mesh.positions.push_back({profile[size_t(k)].first * std::cos(t),
                                      profile[size_t(k)].second,
                                      profile[size_t(k)].first * std::sin(t)});
        }
    const uint32_t last = uint32_t(mesh.positions.size());
    mesh.positions.push_back({0, profile.back().second, 0});
    auto at = [&](int ring, int s) { return uint32_t(1 + (ring - 1) * segments + s % segments); };
    for (int s = 0; s < segments; ++s) {
        mesh.triangles.push_back({0, at(1, s), at(1, s + 1)});
        for (int k = 1; k < rings; ++k) {
            mesh.triangles.push_back({at(k, s), at(k + 1, s), at(k + 1, s + 1)});
            mesh.triangles.push_back({at(k, s), at(k + 1, s + 1), at(k, s + 1)});
        }
        mesh.triangles.push_back({last, at(rings, s + 1), at(rings, s)});
    }
    if (signedVolume(mesh) < 0)
        for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    return mesh;
}

} // namespace ffd
