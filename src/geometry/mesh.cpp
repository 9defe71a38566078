// TriangleMesh basics: bounds, normals, closedness, cleanup and validation (the core; files are
// the content component's: mesh/mesh_io.cpp, mesh/save_obj.cpp).
#include "ffdaabb/mesh.h"

#include "ffdaabb/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace ffd {

Aabb bounds(const TriangleMesh& mesh) {
    Aabb box;
    for (const Vec3& p : mesh.positions) box.add(p);
    return box;
}

std::vector<Vec3> vertexNormals(const TriangleMesh& mesh) {
    std::vector<Vec3> normals(mesh.positions.size());
    for (const auto& t : mesh.triangles) {
        const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
        const Vec3 n = cross(b - a, c - a); // length = 2 * area: area weighting for free
        for (uint32_t v : t) normals[v] += n;
    }
    for (Vec3& n : normals) n = normalize(n);
    return normals;
}

namespace {

uint64_t edgeKey(uint32_t a, uint32_t b) {
    return (uint64_t(a) << 32) | b;
}

} // namespace

bool isClosed(const TriangleMesh& mesh) {
    if (mesh.triangles.empty()) return false;
    // Each directed edge must appear exactly once and its reverse exactly once.
    std::unordered_map<uint64_t, int> directed;
    directed.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles)
        for (int e = 0; e < 3; ++e) {
            uint32_t a = t[e], b = t[(e + 1) % 3];
            if (a == b) return false;
            if (++directed[edgeKey(a, b)] > 1) return false;
        }
    for (const auto& [key, count] : directed) {
        uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
        if (directed.find(edgeKey(b, a)) == directed.end()) return false;
    }
    return true;
}

double signedVolume(const TriangleMesh& mesh) {
    double volume = 0;
    for (const auto& t : mesh.triangles) {
        const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
        volume += double(dot(a, cross(b, c)));
    }
    return volume / 6.0;
}

double surfaceArea(const TriangleMesh& mesh) {
    double area = 0;
    for (const auto& t : mesh.triangles) {
        const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
        area += 0.5 * double(length(cross(b - a, c - a)));
    }
    return area;
}

namespace {

// Welds vertices closer than `tolerance` (exactly equal when 0) into the first one found, using
// a uniform grid of cell size max(tolerance, tiny) so that the search is local and deterministic.
size_t weldVertices(TriangleMesh& mesh, float tolerance) {
    const size_t n = mesh.positions.size();
    std::vector<uint32_t> remap(n);
    std::vector<Vec3> kept;
    kept.reserve(n);
    size_t welded = 0;
    if (tolerance <= 0) {
        struct Key {
            float x, y, z;
            bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
        };
        struct KeyHash {
            size_t operator()(const Key& k) const {
                uint32_t b[3];
                std::memcpy(b, &k, sizeof b);
                // +0 and -0 compare equal: hash them alike.
                for (uint32_t& w : b)
                    if ((w & 0x7fffffffu) == 0) w = 0;
                return (size_t(b[0]) * 73856093u) ^ (size_t(b[1]) * 19349663u) ^
                       (size_t(b[2]) * 83492791u);
            }
        };
        std::unordered_map<Key, uint32_t, KeyHash> index;
        index.reserve(n);
        for (size_t i = 0; i < n; ++i) {
            const Vec3 p = mesh.positions[i];
            auto [it, inserted] = index.emplace(Key{p.x, p.y, p.z}, uint32_t(kept.size()));
            if (inserted)
                kept.push_back(p);
            else
                ++welded;
            remap[i] = it->second;
        }
    } else {
        const float cell = tolerance * 2.0f;
        auto key = [&](int64_t i, int64_t j, int64_t k) {
            return uint64_t(i * 73856093) ^ uint64_t(j * 19349663) ^ uint64_t(k * 83492791);
        };
        std::unordered_multimap<uint64_t, uint32_t> grid;
        grid.reserve(n);
        const float tol2 = tolerance * tolerance;
        for (size_t v = 0; v < n; ++v) {
            const Vec3 p = mesh.positions[v];
            const int64_t ci = int64_t(std::floor(p.x / cell)),
                          cj = int64_t(std::floor(p.y / cell)),
                          ck = int64_t(std::floor(p.z / cell));
            uint32_t found = UINT32_MAX;
            for (int64_t di = -1; di <= 1 && found == UINT32_MAX; ++di)
                for (int64_t dj = -1; dj <= 1 && found == UINT32_MAX; ++dj)
                    for (int64_t dk = -1; dk <= 1; ++dk) {
                        auto range = grid.equal_range(key(ci + di, cj + dj, ck + dk));
                        for (auto it = range.first; it != range.second; ++it)
                            if (lengthSquared(kept[it->second] - p) <= tol2 &&
                                (found == UINT32_MAX || it->second < found))
                                found = it->second;
                        if (found != UINT32_MAX) break;
                    }
            if (found == UINT32_MAX) {
                found = uint32_t(kept.size());
                kept.push_back(p);
                grid.emplace(key(ci, cj, ck), found);
            } else {
                ++welded;
            }
            remap[v] = found;
        }
    }
    if (welded > 0) {
        for (auto& t : mesh.triangles)
            for (uint32_t& v : t) v = remap[v];
        mesh.positions = std::move(kept);
    }
    return welded;
}

} // namespace

CleanupReport cleanup(TriangleMesh& ioMesh, const CleanupSettings& settings) {
    CleanupReport report;
    if (settings.weld) report.weldedVertices = weldVertices(ioMesh, settings.weldTolerance);

    if (settings.dropDegenerate) {
        auto isDegenerate = [&](const std::array<uint32_t, 3>& t) {
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
            const Vec3 a = ioMesh.positions[t[0]], b = ioMesh.positions[t[1]],
                       c = ioMesh.positions[t[2]];
            return lengthSquared(cross(b - a, c - a)) == 0.0f;
        };
        const size_t before = ioMesh.triangles.size();
        std::erase_if(ioMesh.triangles, isDegenerate);
        report.degenerateTriangles = before - ioMesh.triangles.size();
    }

    if (settings.dropDuplicates) {
        // Same vertex set = duplicate, whatever the orientation (a double-sided pair is not a
        // surface an FFD lattice can embed meaningfully twice).
        std::unordered_map<uint64_t, std::vector<uint32_t>> seen; // hash -> kept triangle ids
        std::vector<std::array<uint32_t, 3>> kept;
        kept.reserve(ioMesh.triangles.size());
        for (const auto& t : ioMesh.triangles) {
            std::array<uint32_t, 3> s = t;
            std::sort(s.begin(), s.end());
            const uint64_t h = (uint64_t(s[0]) * 0x9E3779B97F4A7C15ull) ^
                               (uint64_t(s[1]) * 0xC2B2AE3D27D4EB4Full) ^
                               (uint64_t(s[2]) * 0x165667B19E3779F9ull);
            auto& bucket = seen[h];
            bool duplicate = false;
            for (uint32_t k : bucket) {
                std::array<uint32_t, 3> o = kept[k];
                std::sort(o.begin(), o.end());
                if (o == s) {
                    duplicate = true;
                    break;
                }
            }
            if (duplicate) {
                ++report.duplicateTriangles;
                continue;
            }
            bucket.push_back(uint32_t(kept.size()));
            kept.push_back(t);
        }
        ioMesh.triangles = std::move(kept);
    }

    if (settings.dropUnreferenced) {
        std::vector<uint32_t> remap(ioMesh.positions.size(), UINT32_MAX);
        for (const auto& t : ioMesh.triangles)
            for (uint32_t v : t) remap[v] = 0;
        std::vector<Vec3> kept;
        kept.reserve(ioMesh.positions.size());
        for (size_t v = 0; v < remap.size(); ++v)
            if (remap[v] == 0) {
                remap[v] = uint32_t(kept.size());
                kept.push_back(ioMesh.positions[v]);
            }
        report.unreferencedVertices = ioMesh.positions.size() - kept.size();
        if (report.unreferencedVertices > 0) {
            for (auto& t : ioMesh.triangles)
                for (uint32_t& v : t) v = remap[v];
            ioMesh.positions = std::move(kept);
        }
    }
    return report;
}

void validate(const TriangleMesh& mesh, const std::string& source) {
    if (mesh.positions.empty())
        throw InputError(source, "the mesh has no vertices (expected at least 3)");
    if (mesh.triangles.empty())
        throw InputError(source, "the mesh has no triangles (expected at least 1)");
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3 p = mesh.positions[v];
        if (!isFinite(p)) {
            char buf[160];
            std::snprintf(buf, sizeof buf,
                          "vertex %zu has a non-finite coordinate (%g, %g, %g); expected finite "
                          "numbers",
                          v, double(p.x), double(p.y), double(p.z));
            throw InputError(source, buf);
        }
    }
    // Finite coordinates can still span more than a float holds (-3e38 to 3e38): every size
    // and cell count derived from the extent would overflow.
    const Aabb box = bounds(mesh);
    if (!isFinite(box.extent())) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "the mesh spans from (%g, %g, %g) to (%g, %g, %g), an extent too large to "
                      "represent; expected coordinates well within +-1e38",
                      double(box.lo.x), double(box.lo.y), double(box.lo.z), double(box.hi.x),
                      double(box.hi.y), double(box.hi.z));
        throw InputError(source, buf);
    }
    const size_t n = mesh.positions.size();
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (uint32_t v : mesh.triangles[t])
            if (v >= n)
                throw InputError(source, "triangle " + std::to_string(t) + " uses vertex " +
                                             std::to_string(v) + " but the mesh has only " +
                                             std::to_string(n) + " vertices");
}

void transform(TriangleMesh& ioMesh, float scale, Vec3 offset) {
    for (Vec3& p : ioMesh.positions) p = p * scale + offset;
}

void normalizeSize(TriangleMesh& ioMesh, float size) {
    const Aabb box = bounds(ioMesh);
    if (box.empty()) return;
    const float extent = maxComponent(box.extent());
    const float scale = extent > 0 ? size / extent : 1.0f;
    transform(ioMesh, scale, box.centre() * -scale);
}

} // namespace ffd
