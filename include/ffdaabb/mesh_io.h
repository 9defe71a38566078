// Mesh files: reading OBJ, PLY, STL and OFF, writing OBJ. Part of the content component
// (ffdaabb::content), not of the physics core.
#pragma once

#include "ffdaabb/mesh.h"

#include <filesystem>

namespace ffd {

/// Loads a mesh file: .obj, .ply, .stl or .off, each optionally gzipped (.ply.gz, .obj.gz, ...;
/// inflated with zlib first), extensions in any case. The file is read from memory by the
/// library's own reader for its format, with no access to other files (material libraries are
/// ignored). All meshes in the file are
/// merged in file order (node transforms are not applied: these formats have none), polygons
/// are triangulated, points and lines are dropped, and exactly equal positions are joined (so
/// an OBJ or STL cube has 8 vertices), the vertices numbered in the order the triangles first
/// use them (a file's own vertex order is not kept, and vertices no triangle uses are dropped); nothing else is cleaned up: call cleanup() for that.
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

} // namespace ffd
