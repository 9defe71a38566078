// Headless images (EGL): where bodies and overlays land in the picture.
#include "ffdaabb/error.h"
#include "render_test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

using namespace ffd;
using namespace ffd::test;

namespace {

constexpr int kW = 320, kH = 200;

std::vector<Rect> bodyRects(const World& world, const render::Camera& c) {
    std::vector<Rect> rects;
    for (BodyId b : world.bodies()) rects.push_back(projectBox(c, kW, kH, world.bounds(b)));
    return rects;
}

bool inAny(const std::vector<Rect>& rects, int x, int y, float margin) {
    for (const Rect& r : rects)
        if (r.touches(x, y, margin)) return true;
    return false;
}

/// Pixels that differ (any channel by more than 2) between two images of the same size.
std::vector<std::pair<int, int>> changedPixels(const render::Image& a, const render::Image& b) {
    std::vector<std::pair<int, int>> out;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (!samePixel(a.pixel(x, y), b.pixel(x, y), 2)) out.emplace_back(x, y);
    return out;
}

} // namespace

/// One renderer for the suite: making an EGL context costs more than a small image.
class RenderImage : public ::testing::Test {
public:
    // An exception here would make gtest skip the suite: it is kept and fails every test.
    static void SetUpTestSuite() {
        try {
            renderer_ = std::make_unique<render::OffscreenRenderer>();
        } catch (const std::exception& e) {
            error_ = e.what();
        }
    }
    static void TearDownTestSuite() { renderer_.reset(); }
    void SetUp() override { ASSERT_TRUE(renderer_) << error_; }

protected:
    static render::OffscreenRenderer& renderer() { return *renderer_; }
    void checkBodyPixels(render::Antialiasing aa);

private:
    static std::unique_ptr<render::OffscreenRenderer> renderer_;
    static std::string error_;
};

std::unique_ptr<render::OffscreenRenderer> RenderImage::renderer_;
std::string RenderImage::error_;

TEST_F(RenderImage, ContextIsHeadless) {
    const std::string d = renderer().description();
    std::printf("context: %s\n", d.c_str());
    EXPECT_NE(d.find("EGL"), std::string::npos);
    EXPECT_NE(d.find("GL "), std::string::npos);
}

TEST_F(RenderImage, BodiesFallInsideTheirProjectedBounds) {
    for (render::Antialiasing aa :
         {render::Antialiasing::Msaa, render::Antialiasing::Fxaa, render::Antialiasing::None}) {
        SCOPED_TRACE("antialiasing " + std::to_string(int(aa)));
        checkBodyPixels(aa);
    }
}

void RenderImage::checkBodyPixels(render::Antialiasing aa) {
    const World world = threeBalls();
    const render::Camera c = frontCamera();
    render::DrawOptions options;
    options.antialiasing = aa;
    const render::Image img = renderer().render(world, c, options, kW, kH);
    ASSERT_EQ(img.width, kW);
    ASSERT_EQ(img.height, kH);
    ASSERT_EQ(img.pixels.size(), size_t(kW) * kH * 4);

    const std::vector<BodyId> bodies = world.bodies();
    const std::vector<Rect> rects = bodyRects(world, c);
    std::vector<float> hues;
    for (BodyId b : bodies) hues.push_back(colourHsv(render::bodyColour(b)).h);
    std::vector<int> count(bodies.size(), 0);
    int misplaced = 0, unknown = 0, strayOutside = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const uint8_t* p = img.pixel(x, y);
            EXPECT_EQ(p[3], 255);
            if (!isBodyPixel(p)) continue;
            // Which body: the nearest palette hue.
            const float h = pixelHsv(p).h;
            size_t best = 0;
            for (size_t i = 1; i < hues.size(); ++i)
                if (hueDistance(h, hues[i]) < hueDistance(h, hues[best])) best = i;
            if (hueDistance(h, hues[best]) > 40) {
                ++unknown;
                continue;
            }
            ++count[best];
            if (!rects[best].touches(x, y, 1.0f)) ++misplaced;
        }
    // Outside every body's projected bounds there are only background, floor, grid, shadows.
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (!inAny(rects, x, y, 2.0f) && pixelHsv(img.pixel(x, y)).s > 0.25f) ++strayOutside;
    EXPECT_EQ(misplaced, 0);
    EXPECT_EQ(unknown, 0);
    EXPECT_EQ(strayOutside, 0);
    for (size_t i = 0; i < bodies.size(); ++i)
        // A sphere fills pi/4 of its square; allow for the specular highlight and the edges.
        EXPECT_GT(float(count[i]), 0.5f * rects[i].area()) << "body " << i;
    // Above the horizon: the background colour itself.
    const uint8_t* sky = img.pixel(kW / 2, 0);
    const render::DrawOptions d;
    EXPECT_NEAR(sky[0], d.background.x * 255, 1.0);
    EXPECT_NEAR(sky[1], d.background.y * 255, 1.0);
    EXPECT_NEAR(sky[2], d.background.z * 255, 1.0);
}

TEST_F(RenderImage, WithoutFloorEverythingElseIsBackground) {
    const World world = threeBalls();
    const render::Camera c = frontCamera();
    render::DrawOptions d;
    d.floor = false;
    const render::Image img = renderer().render(world, c, d, kW, kH);
    const std::vector<Rect> rects = bodyRects(world, c);
    const uint8_t bg[4] = {uint8_t(std::lround(d.background.x * 255)),
                           uint8_t(std::lround(d.background.y * 255)),
                           uint8_t(std::lround(d.background.z * 255)), 255};
    int other = 0, covered = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const bool background = samePixel(img.pixel(x, y), bg, 1);
            if (!inAny(rects, x, y, 1.0f))
                other += background ? 0 : 1;
            else
                covered += background ? 0 : 1;
        }
    EXPECT_EQ(other, 0);
    EXPECT_GT(covered, 1000);
}

TEST_F(RenderImage, OddSizesAndExplicitCameraFraming) {
    const World world = threeBalls();
    const render::Image img = renderer().render(world, {}, 333, 217);
    EXPECT_EQ(img.width, 333);
    EXPECT_EQ(img.height, 217);
    // Auto framing: every body in view, none cut by the image border.
    const render::Camera c = render::frameWorld(world, 333.0f / 217.0f);
    int border = 0;
    for (int x = 0; x < 333; ++x)
        border += isBodyPixel(img.pixel(x, 0)) + isBodyPixel(img.pixel(x, 216));
    for (int y = 0; y < 217; ++y)
        border += isBodyPixel(img.pixel(0, y)) + isBodyPixel(img.pixel(332, y));
    EXPECT_EQ(border, 0);
    for (BodyId b : world.bodies()) {
        const Vec3 centre = render::projectToPixel(c, 333, 217, world.centreOfMass(b));
        EXPECT_TRUE(isBodyPixel(img.pixel(int(centre.x), int(centre.y))));
    }
    EXPECT_THROW(renderer().render(world, {}, 0, 10), InputError);
}

TEST_F(RenderImage, SphereOverlayDrawsAroundTheSpheresOnly) {
    World world = threeBalls();
    world.step(); // the enhanced pipeline's own bounding spheres
    render::Camera c = frontCamera();
    c.eye = {0, 3, 13}; // room for the spheres around the bodies
    render::DrawOptions d;
    const render::Image base = renderer().render(world, c, d, kW, kH);
    d.overlays.spheres = true;
    const render::Image with = renderer().render(world, c, d, kW, kH);
    const auto changed = changedPixels(base, with);
    ASSERT_GT(changed.size(), 300u);

    struct Projected {
        Rect box;
        Vec3 centre;
        float radius;
    };
    std::vector<Projected> spheres;
    for (BodyId b : world.bodies()) {
        Vec3 centre;
        float r = 0;
        world.boundingSphere(b, centre, r);
        ASSERT_GT(r, 0);
        Projected p;
        p.box = projectBox(c, kW, kH, {centre - Vec3{r, r, r}, centre + Vec3{r, r, r}});
        p.centre = render::projectToPixel(c, kW, kH, centre);
        // The outline's radius on screen, from the sphere's angular radius.
        const float d2 = lengthSquared(centre - c.eye);
        const float focal = float(kH) / 2 / std::tan(c.fovYDegrees * 3.14159265f / 360);
        p.radius = focal * r / std::sqrt(d2 - r * r);
        spheres.push_back(p);
    }
    int outside = 0;
    for (auto [x, y] : changed) {
        bool inside = false;
        for (const Projected& s : spheres) inside = inside || s.box.touches(x, y, 2.0f);
        outside += inside ? 0 : 1;
    }
    EXPECT_EQ(outside, 0);
    // Far corners untouched.
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x) {
            EXPECT_TRUE(samePixel(base.pixel(x, y), with.pixel(x, y), 0));
            EXPECT_TRUE(samePixel(base.pixel(kW - 1 - x, kH - 1 - y),
                                  with.pixel(kW - 1 - x, kH - 1 - y), 0));
        }
    // Lines near each sphere's outline on all four sides.
    for (const Projected& s : spheres) {
        int side[4] = {0, 0, 0, 0}; // right, top, left, bottom
        for (auto [x, y] : changed) {
            const float dx = float(x) + 0.5f - s.centre.x, dy = float(y) + 0.5f - s.centre.y;
            const float dist = std::sqrt(dx * dx + dy * dy);
            if (dist < 0.8f * s.radius || dist > 1.12f * s.radius) continue;
            const int quadrant = std::abs(dx) > std::abs(dy) ? (dx > 0 ? 0 : 2) : (dy < 0 ? 1 : 3);
            ++side[quadrant];
        }
        for (int q = 0; q < 4; ++q) EXPECT_GT(side[q], 3) << "side " << q;
    }
}

TEST_F(RenderImage, BoxLatticeAndContactOverlaysStayOnTheirBodies) {
    World world = threeBalls();
    for (int i = 0; i < 60; ++i) world.step(); // resting on the floor: floor contacts
    ASSERT_GT(world.profile().floorContacts, 0);
    const render::Camera c = frontCamera();
    const render::Image base = renderer().render(world, c, {}, kW, kH);
    auto check = [&](render::Overlays overlays, float grow, const char* name) {
        render::DrawOptions d;
        d.overlays = overlays;
        const auto changed = changedPixels(base, renderer().render(world, c, d, kW, kH));
        std::vector<Rect> rects;
        for (BodyId b : world.bodies()) {
            Aabb box = world.bounds(b);
            for (const Vec3& p : world.particles(b)) box.add(p);
            box.lo -= Vec3{grow, grow, grow}, box.hi += Vec3{grow, grow, grow};
            rects.push_back(projectBox(c, kW, kH, box));
        }
        int outside = 0;
        for (auto [x, y] : changed) outside += inAny(rects, x, y, 2.0f) ? 0 : 1;
        EXPECT_GT(changed.size(), 20u) << name;
        EXPECT_EQ(outside, 0) << name;
    };
    check({false, true, false, false}, 0, "boxes");
    check({false, false, true, false}, 0, "lattice");
    // Contact marks reach 0.6 cell sizes along the normal.
    check({false, false, false, true}, 0.7f * world.info(world.bodies()[0]).cellSize, "contacts");
}

TEST_F(RenderImage, HighlightAndShadowsChangeOnlyWhereExpected) {
    World world = threeBalls();
    for (int i = 0; i < 60; ++i) world.step();
    const render::Camera c = frontCamera();
    const std::vector<Rect> rects = bodyRects(world, c);
    render::DrawOptions d;
    d.antialiasing = render::Antialiasing::Msaa; // FXAA blends shadow edges with their surround
    const render::Image base = renderer().render(world, c, d, kW, kH);

    d.highlight = world.bodies()[1];
    auto changed = changedPixels(base, renderer().render(world, c, d, kW, kH));
    EXPECT_GT(changed.size(), 500u);
    for (auto [x, y] : changed) EXPECT_TRUE(rects[1].touches(x, y, 1.0f));

    // Shadows only darken, and only the floor.
    d.highlight = {};
    d.shadows = false;
    const render::Image unshadowed = renderer().render(world, c, d, kW, kH);
    changed = changedPixels(unshadowed, base);
    EXPECT_GT(changed.size(), 200u);
    int lighter = 0, bodyInterior = 0;
    for (auto [x, y] : changed) {
        const uint8_t *a = unshadowed.pixel(x, y), *b = base.pixel(x, y);
        lighter += (b[0] + b[1] + b[2] > a[0] + a[1] + a[2]) ? 1 : 0;
        // A body pixel may change only on the body's silhouette, where multisampling mixes
        // in the (shadowed) floor behind it: one of its neighbours is not the body.
        if (!isBodyPixel(a)) continue;
        bool edge = false;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int nx = std::clamp(x + dx, 0, kW - 1), ny = std::clamp(y + dy, 0, kH - 1);
                edge = edge || !isBodyPixel(unshadowed.pixel(nx, ny));
            }
        bodyInterior += edge ? 0 : 1;
    }
    EXPECT_EQ(lighter, 0);
    EXPECT_EQ(bodyInterior, 0);
}

TEST_F(RenderImage, FxaaSmoothsEdgesAndKeepsFlatAreas) {
    World world = threeBalls();
    const render::Camera c = frontCamera();
    render::DrawOptions d;
    d.antialiasing = render::Antialiasing::None;
    d.overlays.spheres = true;
    const render::Image sharp = renderer().render(world, c, d, kW, kH);
    d.antialiasing = render::Antialiasing::Fxaa;
    const render::Image smooth = renderer().render(world, c, d, kW, kH);
    // Only pixels on an edge change: some neighbour differs from them in the sharp image.
    const auto changed = changedPixels(sharp, smooth);
    EXPECT_GT(changed.size(), 200u);
    int flat = 0;
    for (auto [x, y] : changed) {
        bool edge = false;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int nx = std::clamp(x + dx, 0, kW - 1), ny = std::clamp(y + dy, 0, kH - 1);
                edge = edge || !samePixel(sharp.pixel(x, y), sharp.pixel(nx, ny), 2);
            }
        flat += edge ? 0 : 1;
    }
    EXPECT_EQ(flat, 0);
}

TEST_F(RenderImage, HundredSpheresTiming) {
    World world;
    for (int i = 0; i < 100; ++i)
        addBall(world, {float(i % 10) * 2.2f - 10, 1.0f + float(i / 10) * 0.0f + float(i % 3),
                        float(i / 10) * 2.2f - 10});
    world.step();
    render::DrawOptions d;
    renderer().render(world, d, 1280, 720); // warm up
    const int frames = 5;
    auto start = std::chrono::steady_clock::now();
    for (int f = 0; f < frames; ++f) renderer().render(world, d, 1280, 720);
    const double plain =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count() /
        frames;
    d.overlays = {true, true, true, true};
    start = std::chrono::steady_clock::now();
    for (int f = 0; f < frames; ++f) renderer().render(world, d, 1280, 720);
    const double overlays =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count() /
        frames;
    d.overlays = {};
    d.antialiasing = render::Antialiasing::Msaa;
    start = std::chrono::steady_clock::now();
    for (int f = 0; f < frames; ++f) renderer().render(world, d, 1280, 720);
    const double msaa =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count() /
        frames;
    std::printf("100 spheres at 1280x720 (%s): %.1f ms per frame (default antialiasing), %.1f ms "
                "with all overlays, %.1f ms with 4x MSAA\n",
                renderer().description().c_str(), plain, overlays, msaa);
    EXPECT_LT(plain, 2000);
}
