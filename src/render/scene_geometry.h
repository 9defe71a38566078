// What the renderer draws, built on the CPU without GL: smooth normals of deformed meshes and
// the overlay line lists. Kept apart from the GL code so that it can be tested and reused.
#pragma once

#include "ffdaabb/render.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace ffd::render::detail {

struct LineVertex {
    Vec3 position;
    Vec3 colour; ///< sRGB
};

/// Area-weighted vertex normals of the deformed mesh, unit length (zero for isolated
/// vertices). positions: #V, triangles: #T, outNormals: resized to #V.
void smoothNormals(std::span<const Vec3> positions,
                   std::span<const std::array<uint32_t, 3>> triangles,
                   std::vector<Vec3>& outNormals);

/// The sphere the overlay shows for a body: the world's own bounding sphere where the last
/// step computed one (enhanced mode), else the same construction from the current boundary
/// nodes (centre of their bounds, radius to the farthest corner of any cell box's bounds).
void overlaySphere(const World& world, BodyId body, Vec3& outCentre, float& outRadius);

/// Wire sphere: `meridians` great circles through the poles (+y) and `parallels` circles of
/// latitude, `segments` segments each.
void appendSphereWire(Vec3 centre, float radius, Vec3 colour, std::vector<LineVertex>& out,
                      int meridians = 6, int parallels = 5, int segments = 32);
/// The 12 edges of a hexahedron given by its corners, corner n = i + 2j + 4k.
void appendHexahedronWire(const Vec3* corners, Vec3 colour, std::vector<LineVertex>& out);
/// Unique cell edges of a lattice as particle index pairs (each edge once, sorted).
void latticeEdges(const Lattice& lattice, std::vector<std::array<uint32_t, 2>>& outEdges);

/// Every overlay line of `world` selected in `options` (spheres, boxes, lattice, contacts, and
/// the extra lines), in that order.
void appendOverlayLines(const World& world, const DrawOptions& options,
                        std::vector<LineVertex>& out);

/// Overlay colours.
inline constexpr Vec3 kSphereColour{1.0f, 0.9f, 0.1f};
inline constexpr Vec3 kBoxColour{0.1f, 0.85f, 0.9f};
inline constexpr Vec3 kLatticeColour{0.3f, 0.3f, 0.45f};
inline constexpr Vec3 kObjectContactColour{1.0f, 0.1f, 0.1f};
inline constexpr Vec3 kFloorContactColour{1.0f, 0.2f, 0.9f};

} // namespace ffd::render::detail
