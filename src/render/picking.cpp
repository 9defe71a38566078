#include "ffdaabb/queries.h"
#include "ffdaabb/render.h"

#include <limits>

namespace ffd::render {

Pick pickBody(const World& world, const Camera& camera, int width, int height, float x, float y) {
    Vec3 origin, dir;
    pixelRay(camera, width, height, x, y, origin, dir);
    Pick pick;
    const std::optional<RayHit> hit = raycast(world, origin, dir);
    if (!hit) return pick;
    pick.body = hit->body;
    pick.point = hit->point;
    pick.distance = hit->distance;
    pick.triangle = hit->triangle;
    pick.barycentric = hit->barycentric;
    pick.normal = hit->normal;
    const auto particles = world.particles(pick.body);
    float nearest = std::numeric_limits<float>::max();
    for (uint32_t i = 0; i < particles.size(); ++i) {
        const float d = lengthSquared(particles[i] - pick.point);
        if (d < nearest) nearest = d, pick.particle = i;
    }
    return pick;
}

} // namespace ffd::render
