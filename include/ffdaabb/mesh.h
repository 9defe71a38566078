// Triangle meshes: the dense surfaces that ffdaabb embeds in FFD lattices. Loading (OBJ, PLY,
// gzipped PLY, STL, OFF), cleanup, and the generators of the paper's objects
// (Jeon, Choi, Hong 2012, Table 2).
#pragma once

#include "ffdaabb/math.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ffd {

/// An indexed triangle mesh. Triangles are counter-clockwise seen from outside.
struct TriangleMesh {
    std::vector<Vec3> positions;                    ///< #V, metres
    std::vector<std::array<uint32_t, 3>> triangles; ///< #T vertex indices
    std::string name;                               ///< free text, e.g. the file or generator

    size_t vertexCount() const { return positions.size(); }
    size_t triangleCount() const { return triangles.size(); }
};

/// Axis-aligned bounds of all positions (empty box for an empty mesh).
Aabb bounds(const TriangleMesh& mesh);

/// Area-weighted vertex normals, unit length (zero for isolated vertices). #V entries.
std::vector<Vec3> vertexNormals(const TriangleMesh& mesh);

/// True when every edge is shared by exactly two triangles with opposite orientation
/// (a closed, consistently oriented 2-manifold).
bool isClosed(const TriangleMesh& mesh);

/// Signed volume (positive for a closed outward-oriented mesh).
double signedVolume(const TriangleMesh& mesh);

/// Total surface area.
double surfaceArea(const TriangleMesh& mesh);

/// What cleanup() changed.
struct CleanupReport {
    size_t weldedVertices = 0;       ///< vertices merged into an earlier one
    size_t degenerateTriangles = 0;  ///< triangles with repeated indices or zero area, dropped
    size_t duplicateTriangles = 0;   ///< triangles repeating another one's vertex set, dropped
    size_t unreferencedVertices = 0; ///< vertices no triangle uses, dropped

    bool changed() const {
        return weldedVertices + degenerateTriangles + duplicateTriangles + unreferencedVertices > 0;
    }
};

/// Cleanup options. weldTolerance is absolute (metres); 0 welds exactly equal positions only.
struct CleanupSettings {
    float weldTolerance = 0.0f;
    bool weld = true;
    bool dropDegenerate = true;
    bool dropDuplicates = true;
    bool dropUnreferenced = true;
};

/// Welds duplicate vertices, drops degenerate and duplicate triangles and unreferenced
/// vertices, in that order, keeping the first occurrence of everything (deterministic).
CleanupReport cleanup(TriangleMesh& ioMesh, const CleanupSettings& settings = {});

/// Throws InputError when the mesh is empty, has an index out of range or a non-finite
/// position. `source` names the mesh in the message (a file path or generator name).
void validate(const TriangleMesh& mesh, const std::string& source);

/// Loads a mesh file: .obj, .ply, .stl or .off, each optionally gzipped (.ply.gz, .obj.gz, ...;
/// inflated with zlib first), extensions in any case. The file is read from memory by the
/// library's own reader for its format, with no access to other files (material libraries are
/// ignored). All meshes in the file are
/// merged in file order (node transforms are not applied: these formats have none), polygons
/// are triangulated, points and lines are dropped, and exactly equal positions are joined (so
/// an OBJ or STL cube has 8 vertices); nothing else is cleaned up: call cleanup() for that.
///
/// Throws InputError whose source() is the path, for a file that is missing, a directory or
/// not a regular file, unreadable, empty, of an unsupported extension, truncated, malformed
/// (including vertex indices out of range and bad gzip streams), with non-finite coordinates
/// (naming the vertex), declaring more than 2^28 elements, larger than 2 GiB (also after
/// inflating), or without any triangle. Subsets refused as unsupported: PLY triangle strips,
/// 4OFF/nOFF, polygons of more than 1024 corners, OBJ statements that do not start at the
/// beginning of their line.
TriangleMesh loadMesh(const std::filesystem::path& path);

/// Writes an OBJ file (positions and triangles); throws InputError on failure. The file is
/// written to a temporary name and renamed into place, so a failed write leaves nothing.
void saveObj(const TriangleMesh& mesh, const std::filesystem::path& path);

/// Applies the affine map x -> scale * x + offset to all positions.
void transform(TriangleMesh& ioMesh, float scale, Vec3 offset);

/// Scales and translates the mesh so that its bounding box is centred at the origin and its
/// largest extent is `size`.
void normalizeSize(TriangleMesh& ioMesh, float size);

} // namespace ffd
