// Helpers of the render tests: scenes, projected rectangles, pixel classes, running programs.
#pragma once

#include "ffdaabb/generators.h"
#include "ffdaabb/render.h"
#include "ffdaabb/world.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <unistd.h>
#include <vector>

namespace ffd::test {

/// A unit sphere body (38-cell lattice, the paper's) at `position`.
inline BodyId addBall(World& world, Vec3 position) {
    BodySettings s;
    s.lattice.targetCells = 38;
    s.position = position;
    return world.addBody(icosphere(2), s);
}

/// Three unit spheres at known, separate positions, above the floor.
inline World threeBalls() {
    World world;
    addBall(world, {-2.4f, 1.2f, 0});
    addBall(world, {0, 1.0f, -1.0f});
    addBall(world, {2.4f, 1.6f, 0.6f});
    return world;
}

/// A camera looking at threeBalls from the front, slightly down.
inline render::Camera frontCamera() {
    render::Camera c;
    c.eye = {0, 2.5f, 9};
    c.target = {0, 1.2f, 0};
    c.fovYDegrees = 40;
    return c;
}

/// A screen rectangle in pixel coordinates (projectToPixel's convention).
struct Rect {
    float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;

    void add(Vec3 p) {
        x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
        x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
    }
    /// Whether pixel (x, y), covering [x, x+1) x [y, y+1), touches the rectangle grown by margin.
    bool touches(int x, int y, float margin) const {
        return float(x + 1) > x0 - margin && float(x)<x1 + margin&& float(y + 1)> y0 - margin &&
               float(y) < y1 + margin;
    }
    float area() const { return std::max(0.0f, x1 - x0) * std::max(0.0f, y1 - y0); }
};

/// The screen rectangle holding the projection of a box.
inline Rect projectBox(const render::Camera& camera, int width, int height, const Aabb& box) {
    Rect r;
    for (int n = 0; n < 8; ++n)
        r.add(render::projectToPixel(camera, width, height,
                                     {(n & 1) ? box.hi.x : box.lo.x, (n & 2) ? box.hi.y : box.lo.y,
                                      (n & 4) ? box.hi.z : box.lo.z}));
    return r;
}

struct Hsv {
    float h = 0, s = 0, v = 0; ///< hue in degrees, saturation and value in [0, 1]
};

inline Hsv toHsv(float r, float g, float b) {
    const float mx = std::max({r, g, b}), mn = std::min({r, g, b});
    Hsv out;
    out.v = mx;
    out.s = mx > 0 ? (mx - mn) / mx : 0;
    if (mx - mn <= 0) return out;
    float h;
    if (mx == r)
        h = (g - b) / (mx - mn);
    else if (mx == g)
        h = 2 + (b - r) / (mx - mn);
    else
        h = 4 + (r - g) / (mx - mn);
    out.h = std::fmod(h * 60 + 360, 360.0f);
    return out;
}

inline Hsv pixelHsv(const uint8_t* p) {
    return toHsv(float(p[0]) / 255, float(p[1]) / 255, float(p[2]) / 255);
}

inline Hsv colourHsv(Vec3 c) {
    return toHsv(c.x, c.y, c.z);
}

inline float hueDistance(float a, float b) {
    const float d = std::fabs(a - b);
    return std::min(d, 360 - d);
}

/// A pixel showing a body: saturated and not too dark. Background, floor, grid and shadows
/// are all near-grey.
inline bool isBodyPixel(const uint8_t* p) {
    const Hsv c = pixelHsv(p);
    return c.s > 0.4f && c.v > 0.12f;
}

inline bool samePixel(const uint8_t* a, const uint8_t* b, int tolerance) {
    for (int c = 0; c < 4; ++c)
        if (std::abs(int(a[c]) - int(b[c])) > tolerance) return false;
    return true;
}

/// Whether `name` is an executable in PATH.
inline bool inPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    if (!path) return false;
    std::string all(path);
    size_t start = 0;
    while (start <= all.size()) {
        const size_t end = std::min(all.find(':', start), all.size());
        const std::string dir = all.substr(start, end - start);
        if (!dir.empty() && ::access((dir + "/" + name).c_str(), X_OK) == 0) return true;
        start = end + 1;
    }
    return false;
}

} // namespace ffd::test
