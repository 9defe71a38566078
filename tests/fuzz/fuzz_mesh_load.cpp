// libFuzzer target: loadMesh on arbitrary bytes, then (for what loads) cleanup and a lattice.
// The first input byte picks the file name's extension, plain or gzipped (.obj .ply .stl .off
// and .gz of each); the rest is the file. loadMesh reads files only, so the bytes go to a temp
// file first (tmpfs under /dev/shm when there is one).
//
// Contract checked: loadMesh either returns a valid mesh (indices in range, finite positions,
// at least one triangle) or throws InputError; nothing else escapes, nothing crashes, leaks or
// trips a sanitizer. Loaded meshes of moderate size go on through cleanup() and buildLattice().
#include "ffdaabb/error.h"
#include "ffdaabb/lattice.h"
#include "ffdaabb/mesh_io.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace {

const std::filesystem::path& scratchDir() {
    static const std::filesystem::path dir = [] {
        const std::filesystem::path base =
            std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
        auto d = base / ("ffdaabb-fuzz-mesh-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(scratchDir(), ec);
        });
        return d;
    }();
    return dir;
}

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz_mesh_load: contract broken: %s\n", what);
        std::abort();
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* kExtensions[] = {".obj",    ".ply",    ".stl",    ".off",
                                        ".obj.gz", ".ply.gz", ".stl.gz", ".off.gz"};
    const std::filesystem::path file =
        scratchDir() / (std::string("input") + kExtensions[data[0] % 8]);
    {
        std::FILE* f = std::fopen(file.c_str(), "wb");
        if (!f) std::abort();
        if (size > 1 && std::fwrite(data + 1, 1, size - 1, f) != size - 1) std::abort();
        std::fclose(f);
    }
    ffd::TriangleMesh mesh;
    try {
        mesh = ffd::loadMesh(file);
    } catch (const ffd::InputError&) {
        std::filesystem::remove(file);
        return 0;
    }
    std::filesystem::remove(file);

    check(!mesh.triangles.empty(), "a loaded mesh has no triangles");
    for (const auto& t : mesh.triangles)
        for (uint32_t i : t) check(i < mesh.positions.size(), "a vertex index is out of range");
    for (const ffd::Vec3& p : mesh.positions) check(ffd::isFinite(p), "a position is not finite");

    // What a scene does with a loaded mesh: clean it up and embed it in a coarse lattice.
    if (mesh.triangleCount() > 20000) return 0;
    ffd::cleanup(mesh);
    try {
        ffd::LatticeSettings coarse;
        coarse.resolution = 4; // a few dozen cells at most: quick for any mesh
        const ffd::Lattice lattice = ffd::buildLattice(mesh, coarse);
        check(lattice.vertices.size() == mesh.positions.size(), "not every vertex is embedded");
        for (const ffd::Embedding& e : lattice.vertices)
            check(e.cell < lattice.cellCount(), "an embedding names a cell out of range");
    } catch (const ffd::InputError&) {
        // A mesh left empty by cleanup, or of zero extent, is refused: fine.
    }
    return 0;
}
