// Loads a mesh file (OBJ, PLY, PLY.GZ, STL, OFF), drops 10 copies of it (they share one
// lattice), and writes the final deformed meshes to an OBJ file.
//   custom_mesh input.obj output.obj
#include <ffdaabb/error.h>
#include <ffdaabb/mesh_io.h>
#include <ffdaabb/world.h>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s input-mesh output.obj\n", argv[0]);
        return 2;
    }
    try {
        ffd::TriangleMesh mesh = ffd::loadMesh(argv[1]);
        ffd::cleanup(mesh);
        ffd::normalizeSize(mesh, 0.5f);
        ffd::World world;
        for (int i = 0; i < 10; ++i) {
            ffd::BodySettings s;
            s.position = {0.05f * float(i % 3), 0.5f + 0.6f * float(i), 0.03f * float(i % 2)};
            world.addBody(mesh, s);
        }
        for (int frame = 0; frame < 240; ++frame) world.step();
        // All bodies in one OBJ, one group each.
        ffd::TriangleMesh all;
        for (ffd::BodyId id : world.bodies()) {
            const uint32_t base = uint32_t(all.positions.size());
            for (const ffd::Vec3& v : world.vertices(id)) all.positions.push_back(v);
            for (auto t : world.triangles(id))
                all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
        }
        ffd::saveObj(all, argv[2]);
        std::printf("%zu bodies, %zu vertices written to %s\n", world.bodyCount(),
                    all.positions.size(), argv[2]);
    } catch (const ffd::InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    return 0;
}
