// Links the physics core alone (ffdaabb::core): two soft boxes, meshes made in code as an
// engine would hand them over, dropped onto each other; prints their heights as they settle
// and fall asleep. (Three stacked this way do not stand: docs/LIMITS.md, known problem 5.)
#include <ffdaabb/world.h>

#include <cstdio>

namespace {

// A closed box of half extents h, its faces split into n x n quads (two triangles each),
// outward oriented.
ffd::TriangleMesh box(ffd::Vec3 h, int n) {
    ffd::TriangleMesh mesh;
    mesh.name = "box";
    // Each face: a normal axis, its sign, and the two axes spanning it (right-handed).
    const int axes[3][2] = {{1, 2}, {2, 0}, {0, 1}};
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
    return mesh; // corners and edges repeat per face: the lattice only needs the surface
}

} // namespace

int main() {
    ffd::World world;
    ffd::BodyId ids[2];
    for (int k = 0; k < 2; ++k) {
        ffd::BodySettings s;
        s.position = {0.05f * float(k), 0.4f + 0.6f * float(k), 0};
        ids[k] = world.addBody(box({0.4f, 0.2f, 0.3f}, 6), s);
    }
    std::printf(" t (s)   box 1    box 2   (lowest point, m)   awake\n");
    bool stood = true; // box 2 on box 1 all along, once landed
    for (int frame = 0; frame <= 1200; ++frame) {
        const float gap = world.bounds(ids[1]).lo.y - world.bounds(ids[0]).lo.y;
        if (frame >= 60) stood = stood && world.bounds(ids[0]).lo.y > -0.01f && gap > 0.35f;
        if (frame % 120 == 0)
            std::printf("%5.1f  %7.3f  %7.3f   %zu\n", frame / 60.0, world.bounds(ids[0]).lo.y,
                        world.bounds(ids[1]).lo.y, world.awakeCount());
        world.step();
    }
    // Resting on the floor and on each other for 20 s: stacked, 0.4 m apart.
    std::printf("%s\n", stood ? "stacked" : "NOT stacked");
    return stood ? 0 : 1;
}
