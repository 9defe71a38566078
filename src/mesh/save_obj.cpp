// saveObj: a mesh as an OBJ file, written to a temporary name and renamed into place.
#include "ffdaabb/mesh_io.h"
#include "util/atomic_file.h"

#include <cstdio>

namespace ffd {

void saveObj(const TriangleMesh& mesh, const std::filesystem::path& path) {
    AtomicFile file(path);
    std::FILE* f = file.handle();
    std::fprintf(f, "# ffdaabb: %zu vertices, %zu triangles\n", mesh.positions.size(),
                 mesh.triangles.size());
    if (!mesh.name.empty()) std::fprintf(f, "o %s\n", mesh.name.c_str());
    for (const Vec3& p : mesh.positions)
        std::fprintf(f, "v %.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z));
    for (const auto& t : mesh.triangles)
        std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    file.commit();
}

} // namespace ffd
