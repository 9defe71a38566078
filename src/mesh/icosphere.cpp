// Icosphere: the regular icosahedron, each triangle split into four at its edge midpoints
// `subdivisions` times, new vertices projected onto the unit sphere. V = 10 * 4^n + 2,
// T = 20 * 4^n (n = 2: 162 and 320, the paper's sphere).
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"

#include <map>

namespace ffd {

TriangleMesh icosphere(int subdivisions) {
    if (subdivisions < 0 || subdivisions > kMaxIcosphereSubdivisions)
        throw InputError("icosphere", "subdivisions = " + std::to_string(subdivisions) +
                                          " is out of range (expected 0.." +
                                          std::to_string(kMaxIcosphereSubdivisions) + ")");
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    TriangleMesh mesh;
    mesh.name = "icosphere(" + std::to_string(subdivisions) + ")";
    mesh.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& p : mesh.positions) p = normalize(p);
    mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                      {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                      {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                      {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int level = 0; level < subdivisions; ++level) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto key = std::minmax(a, b);
            auto [it, inserted] = midpoints.emplace(key, uint32_t(mesh.positions.size()));
            if (inserted)
                mesh.positions.push_back(normalize(mesh.positions[a] + mesh.positions[b]));
            return it->second;
        };
        std::vector<std::array<uint32_t, 3>> next;
        next.reserve(mesh.triangles.size() * 4);
        for (const auto& tri : mesh.triangles) {
            const uint32_t a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]),
                           c = midpoint(tri[2], tri[0]);
            next.push_back({tri[0], a, c});
            next.push_back({tri[1], b, a});
            next.push_back({tri[2], c, b});
            next.push_back({a, b, c});
        }
        mesh.triangles = std::move(next);
    }
    return mesh;
}

} // namespace ffd
