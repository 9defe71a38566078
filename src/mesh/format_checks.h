// Structural checks of mesh files before Assimp sees them. Assimp 5.2.5 is lenient where we
// need errors (it reads "nan", clamps or keeps out-of-range indices, accepts short files) and
// fragile where we need safety (truncated binary PLY segfaults, a PLY header without
// end_header loops forever, polygons flagged wrongly abort in Triangulate). These checks walk
// the bytes of each format once, without allocating per element, and accept only the subset
// of each format that Assimp parses the same way we do, so that the first error a user sees
// names the file, the element and what was expected.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace ffd::detail {

/// Most vertices, faces or triangles a file may declare (2^28): beyond it the header is
/// treated as absurd and rejected before anything is allocated.
inline constexpr uint64_t kMaxMeshElements = uint64_t(1) << 28;
/// Largest file we read, compressed or after inflating (2 GiB; Assimp's loaders use 32-bit
/// sizes in places).
inline constexpr uint64_t kMaxFileBytes = uint64_t(1) << 31;
/// Most corners of one polygon: Assimp's ear clipping is quadratic or worse in it.
inline constexpr uint64_t kMaxPolygonCorners = 1024;

enum class MeshFormat { Obj, Ply, Stl, Off };

/// Lower-case extension without the dot ("obj", "ply", "stl", "off").
const char* formatExtension(MeshFormat format);

/// What the checks found out about the file.
struct PrecheckResult {
    bool text = false; ///< a text encoding: Assimp gets the buffer with a final newline added
};

/// Throws InputError(source, ...) when `data` is not a well-formed file of `format` within the
/// subset described above: truncated, malformed, absurd counts, non-finite coordinates (named
/// by vertex index) and vertex indices out of range.
PrecheckResult precheck(MeshFormat format, std::string_view data, const std::string& source);

} // namespace ffd::detail
