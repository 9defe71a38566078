#include "render/camera_math.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace ffd::render {

namespace detail {

void clipPlanes(const Camera& camera, float& outNear, float& outFar) {
    const float d = std::max(length(camera.target - camera.eye), 1e-3f);
    outNear = camera.nearPlane > 0 ? camera.nearPlane : d / 100;
    outFar = camera.farPlane > outNear ? camera.farPlane : d * 40;
}

Mat4 viewMatrix(const Camera& camera) {
    return lookAt(camera.eye, camera.target, camera.up);
}

Mat4 projectionMatrix(const Camera& camera, float aspect) {
    float zNear = 0, zFar = 0;
    clipPlanes(camera, zNear, zFar);
    const float fov =
        std::clamp(camera.fovYDegrees, 1.0f, 170.0f) * std::numbers::pi_v<float> / 180;
    return perspective(fov, aspect, zNear, zFar);
}

} // namespace detail

Camera frameBox(const Aabb& box, float aspect, const Framing& framing) {
    const float deg = std::numbers::pi_v<float> / 180;
    Aabb b = box;
    if (b.empty()) b = Aabb{{-0.5f, 0, -0.5f}, {0.5f, 1, 0.5f}};
    const float halfY = 0.5f * std::clamp(framing.fovYDegrees, 1.0f, 170.0f) * deg;
    const float tanY = std::tan(halfY), tanX = tanY * std::max(aspect, 1e-3f);
    const float az = framing.azimuthDegrees * deg, el = framing.elevationDegrees * deg;
    const Vec3 back{std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
    Camera c;
    c.target = b.centre();
    c.fovYDegrees = framing.fovYDegrees;
    c.eye = c.target + back; // only for the camera's axes
    const detail::Mat4 view = detail::viewMatrix(c);
    const Vec3 right{view.at(0, 0), view.at(0, 1), view.at(0, 2)};
    const Vec3 up{view.at(1, 0), view.at(1, 1), view.at(1, 2)};
    // A corner p (relative to the target) lies at depth d - dot(p, back) in front of an eye at
    // distance d: it is inside the view when |dot(p, right)| and |dot(p, up)| are within that
    // depth times the half-angle tangents. The nearest distance that holds every corner in view:
    const float margin = std::max(framing.margin, 1.0f);
    float distance = 1e-3f;
    for (int n = 0; n < 8; ++n) {
        const Vec3 corner{(n & 1) ? b.hi.x : b.lo.x, (n & 2) ? b.hi.y : b.lo.y,
                          (n & 4) ? b.hi.z : b.lo.z};
        const Vec3 p = corner - c.target;
        const float depth = std::max(std::fabs(dot(p, right)) * margin / tanX,
                                     std::fabs(dot(p, up)) * margin / tanY);
        distance = std::max(distance, dot(p, back) + depth);
    }
    // Not inside the box's sphere, where the near plane would cut the scene.
    distance = std::max(distance, 0.5f * length(b.extent()) * 1.05f);
    c.eye = c.target + back * distance;
    return c;
}

Camera frameWorld(const World& world, float aspect, const Framing& framing) {
    Aabb box;
    for (BodyId b : world.bodies()) box.add(world.bounds(b));
    if (!box.empty() && world.settings().floor)
        box.lo.y = std::min(box.lo.y, world.settings().floorHeight);
    return frameBox(box, aspect, framing);
}

Vec3 projectToPixel(const Camera& camera, int width, int height, Vec3 point) {
    const float aspect = float(width) / float(std::max(height, 1));
    const detail::Mat4 m = detail::projectionMatrix(camera, aspect) * detail::viewMatrix(camera);
    const detail::Vec4 clip = m * detail::Vec4{point.x, point.y, point.z, 1};
    if (clip.w <= 0) return {0, 0, std::numeric_limits<float>::infinity()};
    const float x = clip.x / clip.w, y = clip.y / clip.w, z = clip.z / clip.w;
    return {(x * 0.5f + 0.5f) * float(width), (0.5f - y * 0.5f) * float(height), z};
}

void pixelRay(const Camera& camera, int width, int height, float x, float y, Vec3& outOrigin,
              Vec3& outDirection) {
    const float aspect = float(width) / float(std::max(height, 1));
    const float tanY = std::tan(0.5f * std::clamp(camera.fovYDegrees, 1.0f, 170.0f) *
                                std::numbers::pi_v<float> / 180);
    const float nx = 2 * x / float(width) - 1, ny = 1 - 2 * y / float(height);
    const detail::Mat4 v = detail::viewMatrix(camera);
    // The rows of the view matrix's rotation are the camera's right, up and backward axes.
    const Vec3 right{v.at(0, 0), v.at(0, 1), v.at(0, 2)};
    const Vec3 up{v.at(1, 0), v.at(1, 1), v.at(1, 2)};
    const Vec3 back{v.at(2, 0), v.at(2, 1), v.at(2, 2)};
    outOrigin = camera.eye;
    outDirection = normalize(right * (nx * tanY * aspect) + up * (ny * tanY) - back);
}

Vec3 paletteColour(size_t index) {
    // Saturated and apart in hue, none of them the yellow of the sphere overlay or the greys of
    // the floor and background, so that a pixel's colour tells which body it shows.
    static constexpr std::array<Vec3, 8> kPalette{{
        {0.90f, 0.25f, 0.20f}, // red
        {0.20f, 0.45f, 0.90f}, // blue
        {0.25f, 0.75f, 0.30f}, // green
        {0.95f, 0.55f, 0.10f}, // orange
        {0.60f, 0.30f, 0.85f}, // purple
        {0.10f, 0.70f, 0.75f}, // teal
        {0.90f, 0.30f, 0.65f}, // pink
        {0.55f, 0.75f, 0.10f}, // lime
    }};
    return kPalette[index % kPalette.size()];
}

Vec3 bodyColour(BodyId body) {
    return paletteColour(body.index);
}

float autoGridSpacing(const World& world) {
    Aabb box;
    for (BodyId b : world.bodies()) box.add(world.bounds(b));
    if (box.empty()) return 1.0f;
    const float size = std::max(maxComponent(box.extent()), 1e-3f);
    // About 3 to 30 lines across the bodies.
    return std::pow(10.0f, std::floor(std::log10(size / 3)));
}

} // namespace ffd::render
