// Queries on a World: ray casts and box overlaps against the deformed meshes, the bodies each
// body touched in the last step with the normal impulse between them, and the contact begin and
// end events of the last step.
//
//   if (auto hit = ffd::raycast(world, eye, direction))          // closest hit, any distance
//       std::printf("body %u, triangle %u at %.3f m\n", hit->body.index, hit->triangle,
//                   hit->distance);
//   std::vector<ffd::BodyId> inside;
//   ffd::bodiesOverlapping(world, ffd::Aabb{{-1, 0, -1}, {1, 1, 1}}, inside);
//   for (const ffd::ContactEvent& e : ffd::contactEvents(world).begin) { ... }
//
// Geometric queries read the meshes as World::vertices gives them (the end of the last step,
// or the pose a body was last placed in). They cull by bounding boxes: each body's box over its
// vertices, then a bounding-volume hierarchy over its triangles, built once per shared model
// (rest pose) and refitted to a body's vertices the first time a query reaches that body after
// they changed. The first query after a step thus pays one pass over all vertices (the bodies'
// boxes) and a refit of each body it reaches; the next ones only their own traversal.
//
// Like every World call, queries are not safe to run concurrently with each other or with
// step() on the same World: they update those caches.
#pragma once

#include "ffdaabb/math.h"
#include "ffdaabb/world.h"

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace ffd {

/// Where a ray meets a body's deformed mesh.
struct RayHit {
    BodyId body;
    uint32_t triangle = 0; ///< index into World::triangles(body)
    /// Weights of the triangle's corners t[0], t[1], t[2] (each in [0, 1], summing to 1):
    /// point = sum of weight * vertex.
    Vec3 barycentric;
    float distance = 0; ///< from the ray's origin to `point`, metres
    Vec3 point;         ///< origin + distance * unit direction
    /// Unit normal of the triangle by its winding (outward for an outward-wound closed mesh,
    /// as the generators and loaders make them); dot(normal, direction) > 0 for a ray that
    /// leaves the body there, e.g. one cast from inside it.
    Vec3 normal;
};

/// The closest point where the ray from `origin` along `direction` (any length but zero; it is
/// normalised) meets any body's deformed mesh within `maxDistance` metres (0 <= distance <=
/// maxDistance), or nothing. Both faces of every triangle are hit, so a ray cast from inside a
/// body hits the body's surface from within. The triangle test is watertight (Woop, Benthin,
/// Wald, "Watertight Ray/Triangle Intersection", JCGT 2013): a ray through an edge or a vertex
/// shared by triangles hits at least one of them. Ties in distance go to the body earlier in
/// World::bodies(), then to the lower triangle index. InputError for a non-finite origin or
/// direction, a zero direction or a negative or NaN maxDistance.
std::optional<RayHit> raycast(const World& world, Vec3 origin, Vec3 direction,
                              float maxDistance = std::numeric_limits<float>::infinity());

/// The same, skipping the bodies in `ignore` (e.g. the body the ray starts from). Stale handles
/// in `ignore` are allowed (they name no body).
std::optional<RayHit> raycast(const World& world, Vec3 origin, Vec3 direction, float maxDistance,
                              std::span<const BodyId> ignore);

/// Every point where the ray meets a deformed mesh within `maxDistance`, nearest first (ties:
/// body order, then triangle). A ray through an edge may list both triangles sharing it.
/// Clears `out`.
void raycastAll(const World& world, Vec3 origin, Vec3 direction, float maxDistance,
                std::vector<RayHit>& out);

/// Whether the body's deformed mesh meets the box (closed box: touching counts): a triangle
/// meets it (separating-axis test, Akenine-Moeller 2001), or the box lies inside the mesh (its
/// centre inside by the mesh's winding number along a fixed ray). InputError for a stale handle
/// or an empty box (lo > hi on an axis) or one with non-finite corners.
bool bodyOverlaps(const World& world, BodyId body, const Aabb& box);

/// The bodies whose deformed meshes meet the box (bodyOverlaps), in World::bodies() order.
/// Clears `out`.
void bodiesOverlapping(const World& world, const Aabb& box, std::vector<BodyId>& out);

/// Two bodies (or a body and the floor) that had contacts in the last step.
struct ContactPair {
    BodyId bodyA; ///< the one earlier in World::bodies() (at the time of the step)
    BodyId bodyB; ///< the other; null for the floor
    /// Normal impulse between them, summed over the step's contacts and substeps, N s (>= 0):
    /// the rigid phase's, the projection's and the velocity pass's (ContactInfo::impulse), so
    /// that a body at rest on the floor gets about its weight times the frame step.
    float normalImpulse = 0;
    /// The same as a vector: the impulse B exerted on A along the contacts' normals, N s.
    Vec3 impulse;
    /// Contacts between them summed over the substeps (a contact of two substeps counts twice).
    uint32_t contactCount = 0;
};

/// Every pair that had contacts in the last step (any substep), in a canonical order: by bodyA's
/// place in World::bodies(), then bodyB's, the floor last; the same for any thread count. Empty
/// before the first step. Contacts include those found within the contact skin and the
/// speculative margin (what the bodies may travel in a substep), which may carry no impulse:
/// a pair can touch one step before its surfaces meet. The handles stay as they were: a body
/// removed since is named by its stale handle. Valid until the next step().
std::span<const ContactPair> contactPairs(const World& world);

/// One of a body's partners in the last step.
struct BodyContact {
    BodyId other;            ///< null for the floor
    float normalImpulse = 0; ///< N s over the step (ContactPair::normalImpulse)
    Vec3 impulse;            ///< the impulse `other` exerted on the body, N s
    uint32_t contactCount = 0;
};

/// The bodies (and the floor) `body` had contacts with in the last step, in contactPairs()'
/// order, with the normal impulse between them. Clears `out`; empty for a body added since.
/// InputError for a stale handle.
void touchingBodies(const World& world, BodyId body, std::vector<BodyContact>& out);

/// A pair that started or stopped having contacts (ContactPair's bodies: A before B, B null for
/// the floor).
struct ContactEvent {
    BodyId bodyA;
    BodyId bodyB;
    friend bool operator==(const ContactEvent&, const ContactEvent&) = default;
};

/// The last step's events, like Box2D's contact begin and end touch events.
struct ContactEvents {
    /// Pairs with contacts in the last step and none in the step before, in contactPairs()'
    /// order.
    std::span<const ContactEvent> begin;
    /// Pairs with contacts in the step before and none in the last step, in the previous
    /// step's order. A pair with a body removed in between ends too, at the next step, naming
    /// the removed body by its stale handle (World::isValid is false for it).
    std::span<const ContactEvent> end;
};

/// The events of the last step() (empty before the first). Valid until the next step().
ContactEvents contactEvents(const World& world);

} // namespace ffd
