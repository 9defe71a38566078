// The renderer's GL-free parts: camera projection and framing, picking, palette, normals and
// overlay geometry.
#include "render/scene_geometry.h"
#include "render_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

using namespace ffd;
using namespace ffd::test;

TEST(RenderCamera, PixelRayPassesThroughProjectedPoint) {
    render::Camera c;
    c.eye = {3, 4, 7};
    c.target = {-0.5f, 0.8f, 0.2f};
    c.fovYDegrees = 50;
    const int w = 640, h = 360;
    for (Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 2, -1}, Vec3{-2, 0.5f, 1.5f}, Vec3{0.3f, 3, 0}}) {
        const Vec3 px = render::projectToPixel(c, w, h, p);
        ASSERT_TRUE(std::isfinite(px.z));
        Vec3 origin, dir;
        render::pixelRay(c, w, h, px.x, px.y, origin, dir);
        EXPECT_NEAR(length(dir), 1.0f, 1e-5f);
        // The point lies on the ray: its offset from the origin is parallel to the direction.
        const Vec3 d = p - origin;
        EXPECT_LT(length(cross(d, dir)) / length(d), 1e-4f);
        EXPECT_GT(dot(d, dir), 0);
    }
    // The target is at the image centre; a point behind the eye has no pixel.
    const Vec3 centre = render::projectToPixel(c, w, h, c.target);
    EXPECT_NEAR(centre.x, w / 2.0f, 1e-3f);
    EXPECT_NEAR(centre.y, h / 2.0f, 1e-3f);
    EXPECT_TRUE(std::isinf(render::projectToPixel(c, w, h, c.eye + (c.eye - c.target)).z));
    // +y up in the world is up in the image (smaller y).
    EXPECT_LT(render::projectToPixel(c, w, h, c.target + Vec3{0, 1, 0}).y, centre.y);
}

TEST(RenderCamera, FramingKeepsEveryBodyInView) {
    World world;
    addBall(world, {-3, 1, 0});
    addBall(world, {4, 2.5f, -2});
    addBall(world, {0.5f, 6, 3});
    for (float aspect : {0.5f, 1.0f, 16.0f / 9.0f, 3.0f})
        for (float azimuth : {0.0f, 30.0f, 135.0f, -100.0f}) {
            render::Framing f;
            f.azimuthDegrees = azimuth;
            const int h = 400, w = int(float(h) * aspect);
            const render::Camera c = render::frameWorld(world, float(w) / float(h), f);
            // Looks down at the scene, +y up.
            EXPECT_GT(c.eye.y, c.target.y);
            Aabb scene;
            for (BodyId b : world.bodies()) {
                const Rect r = projectBox(c, w, h, world.bounds(b));
                EXPECT_GE(r.x0, -0.5f) << aspect << " " << azimuth;
                EXPECT_LE(r.x1, float(w) + 0.5f);
                EXPECT_GE(r.y0, -0.5f);
                EXPECT_LE(r.y1, float(h) + 0.5f);
                scene.add(world.bounds(b));
            }
            // And it frames them tightly: the scene's box (down to the floor) fills one image
            // direction up to the margin.
            scene.lo.y = 0;
            const Rect all = projectBox(c, w, h, scene);
            const float fill = std::max((all.x1 - all.x0) / float(w), (all.y1 - all.y0) / float(h));
            EXPECT_GT(fill, 0.8f / f.margin) << aspect << " " << azimuth;
            EXPECT_LT(fill, 1.0f) << aspect << " " << azimuth;
        }
}

TEST(RenderCamera, PickFindsTheBodyUnderThePixel) {
    World world = threeBalls();
    const render::Camera c = frontCamera();
    const int w = 320, h = 200;
    const Vec3 centres[] = {{-2.4f, 1.2f, 0}, {0, 1.0f, -1.0f}, {2.4f, 1.6f, 0.6f}};
    for (size_t i = 0; i < 3; ++i) {
        const BodyId b = world.bodies()[i];
        const Vec3 centre = centres[i];
        const Vec3 px = render::projectToPixel(c, w, h, centre);
        const render::Pick p = render::pickBody(world, c, w, h, px.x, px.y);
        ASSERT_EQ(p.body, b);
        // The hit is on the sphere's near side, and the grabbed particle close to it.
        EXPECT_NEAR(length(p.point - centre), 1.0f, 0.05f);
        EXPECT_LT(p.distance, length(centre - c.eye));
        EXPECT_LT(length(world.particles(b)[p.particle] - p.point), world.info(b).cellSize * 1.0f);
        // The triangle and the weights place the point on the deformed mesh, facing the eye.
        const auto v = world.vertices(b);
        const auto t = world.triangles(b)[p.triangle];
        const Vec3 q =
            v[t[0]] * p.barycentric.x + v[t[1]] * p.barycentric.y + v[t[2]] * p.barycentric.z;
        EXPECT_LT(length(q - p.point), 1e-4f);
        EXPECT_LT(dot(p.normal, p.point - c.eye), 0.0f);
    }
    EXPECT_TRUE(render::pickBody(world, c, w, h, 2, 2).body.isNull());
}

TEST(RenderPalette, DeterministicDistinctAndSaturated) {
    std::set<std::tuple<float, float, float>> seen;
    for (size_t i = 0; i < 8; ++i) {
        const Vec3 a = render::paletteColour(i);
        EXPECT_EQ(a, render::paletteColour(i + 8)); // cycles
        seen.insert({a.x, a.y, a.z});
        const Hsv c = colourHsv(a);
        EXPECT_GT(c.s, 0.6f);
        // Not the sphere overlay's yellow.
        EXPECT_GT(hueDistance(c.h, colourHsv(render::detail::kSphereColour).h), 20.0f);
        for (size_t j = 0; j < i; ++j)
            EXPECT_GT(hueDistance(c.h, colourHsv(render::paletteColour(j)).h), 15.0f);
    }
    EXPECT_EQ(seen.size(), 8u);
    EXPECT_EQ(render::bodyColour(BodyId{3, 7}), render::paletteColour(3));
}

TEST(RenderGeometry, SmoothNormalsOfASphereAreRadial) {
    const TriangleMesh m = icosphere(3);
    std::vector<Vec3> normals;
    render::detail::smoothNormals(m.positions, m.triangles, normals);
    ASSERT_EQ(normals.size(), m.positions.size());
    for (size_t i = 0; i < normals.size(); ++i) {
        EXPECT_NEAR(length(normals[i]), 1.0f, 1e-5f);
        EXPECT_GT(dot(normals[i], normalize(m.positions[i])), 0.995f);
    }
}

TEST(RenderGeometry, LatticeEdgesAreUnique) {
    Lattice two;
    // Two cells sharing the face x = 1: 12 + 12 - 4 shared edges.
    two.cellParticles = {{0, 1, 2, 3, 4, 5, 6, 7}, {1, 8, 3, 9, 5, 10, 7, 11}};
    std::vector<std::array<uint32_t, 2>> edges;
    render::detail::latticeEdges(two, edges);
    EXPECT_EQ(edges.size(), 20u);
    std::set<std::array<uint32_t, 2>> unique(edges.begin(), edges.end());
    EXPECT_EQ(unique.size(), edges.size());
    for (const auto& e : edges) EXPECT_LT(e[0], e[1]);
}

TEST(RenderGeometry, OverlayLinesStayOnTheirObjects) {
    World world = threeBalls();
    world.step();
    render::DrawOptions d;
    d.overlays.boxes = true;
    std::vector<render::detail::LineVertex> lines;
    render::detail::appendOverlayLines(world, d, lines);
    size_t boxes = 0;
    for (BodyId b : world.bodies()) boxes += world.lattice(b).boxes.size();
    EXPECT_EQ(lines.size(), boxes * 12 * 2);
    Aabb all;
    for (BodyId b : world.bodies()) all.add(world.bounds(b));
    for (const auto& v : lines) EXPECT_TRUE(all.contains(v.position, 1e-5f));

    // The sphere overlay is the world's own bounding sphere (enhanced mode, after a step).
    lines.clear();
    d.overlays = {};
    d.overlays.spheres = true;
    render::detail::appendOverlayLines(world, d, lines);
    ASSERT_FALSE(lines.empty());
    const BodyId first = world.bodies()[0];
    Vec3 c;
    float r = 0;
    world.boundingSphere(first, c, r);
    ASSERT_GT(r, 0.9f);
    EXPECT_NEAR(length(lines[0].position - c), r, 1e-4f);
    // In previous mode, where no sphere test runs, it is rebuilt from the nodes the same way.
    Vec3 rebuilt;
    float rebuiltRadius = 0;
    world.setMode(CollisionMode::Previous);
    render::detail::overlaySphere(world, first, rebuilt, rebuiltRadius);
    EXPECT_NEAR(rebuiltRadius, r, 0.05f * r);
    EXPECT_LT(length(rebuilt - c), 0.05f * r);
}
