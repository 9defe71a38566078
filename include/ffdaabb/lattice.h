// The sparse FFD lattice a mesh is embedded in, and the FFD-AABB cell boxes built from it.
//
// References: T. W. Sederberg, S. R. Parry, "Free-Form Deformation of Solid Geometric Models",
// SIGGRAPH 1986 (FFD; here of degree 1 per cell, i.e. trilinear); S. Jung, M. Hong, M.-H. Choi,
// "Collision Handling for Free-Form Deformation Embedded Surface", IET Image Processing 5(4),
// 2011 (FFD-AABB: per-cell boxes with 8 boundary nodes in local coordinates); J. Jeon,
// M.-H. Choi, M. Hong, "Enhanced FFD-AABB Collision Algorithm for Deformable Objects", 2012.
//
// A lattice is a uniform grid of cubic cells of size h that keeps only the cells the mesh
// occupies (a triangle touches them, plus the enclosed interior). Particles sit at the corners
// of occupied cells and are shared between neighbouring cells. Every mesh vertex stores its
// cell and local coordinates (s,t,u); its position is the trilinear blend of the cell's 8
// corner particles, so every embedded point is linear in the particle positions.
#pragma once

#include "ffdaabb/math.h"
#include "ffdaabb/mesh.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace ffd {

/// How the cell size is chosen: the first of cellSize > 0, resolution > 0, targetCells.
/// The paper gives cell counts (Table 2), not sizes, so the default is a target count found by
/// bisection on h; the grid is anchored at the mesh's minimum corner.
struct LatticeSettings {
    float cellSize = 0;       ///< explicit cell size h, metres (> 0 to use it)
    float resolution = 0;     ///< > 0: h = (longest bounding-box extent) / resolution
    int targetCells = 64;     ///< otherwise: h chosen so that the lattice has about this many cells
    bool fillInterior = true; ///< add the cells enclosed by the surface (flood fill from outside)
    float boxSkin = 0.005f;   ///< cell boxes are inflated by boxSkin * h on every side
};

/// Grid coordinates of a cell or lattice point.
using GridCoord = std::array<int32_t, 3>;

/// Where a vertex (or any point) lives in the lattice: its cell and local coordinates in it.
struct Embedding {
    uint32_t cell = 0; ///< index into Lattice::cells
    Vec3 local;        ///< (s,t,u), in [0,1]^3 for points inside the cell
};

/// Face bits of a cell box: -x, +x, -y, +y, -z, +z.
enum BoxFace : uint8_t {
    kFaceMinX = 1 << 0,
    kFaceMaxX = 1 << 1,
    kFaceMinY = 1 << 2,
    kFaceMaxY = 1 << 3,
    kFaceMinZ = 1 << 4,
    kFaceMaxZ = 1 << 5,
};

/// An FFD-AABB cell box: the rest-pose AABB of the part of the mesh inside one surface cell,
/// in the cell's local coordinates. Its 8 corners are the boundary nodes; node n = i + 2j + 4k
/// takes lo or hi per axis by the bits (i,j,k) of n, like the cell's corner particles.
struct CellBox {
    uint32_t cell = 0; ///< index into Lattice::cells
    Vec3 lo, hi;       ///< local coordinates of the box in the cell (may exceed [0,1] by the skin)
    /// BoxFace bits: the faces that lead out of the body. The neighbouring lattice cell that way
    /// is empty, or the space between this box's face and the neighbouring cell's part of the
    /// mesh is outside the mesh (a notch narrower than a cell; judged at rest by the winding
    /// number).
    uint8_t outsideFaces = 0;

    /// Local coordinates of boundary node n (0..7) in the cell.
    Vec3 nodeLocal(int n) const {
        return {(n & 1) ? hi.x : lo.x, (n & 2) ? hi.y : lo.y, (n & 4) ? hi.z : lo.z};
    }
};

/// A mesh vertex as one of its box's: the vertex and its local coordinates in the box's cell.
struct BoxVertex {
    uint32_t vertex = 0;
    Vec3 local;
};

/// An immutable lattice with its embedding and cell boxes, built once per mesh and settings and
/// shared by every body made from them.
struct Lattice {
    float cellSize = 0;      ///< h, metres
    Vec3 origin;             ///< rest position of grid point (0,0,0)
    GridCoord dims{0, 0, 0}; ///< grid size in cells (occupied or not)

    std::vector<GridCoord> cells;                       ///< #C grid coordinates of occupied cells
    std::vector<std::array<uint32_t, 8>> cellParticles; ///< #C corner particles, corner i+2j+4k
    std::vector<uint8_t> cellIsSurface;                 ///< #C 1 when a triangle touches the cell

    std::vector<Vec3> restParticles;       ///< #P rest positions, metres
    std::vector<GridCoord> particleCoords; ///< #P grid coordinates

    /// #P each particle's share of the body's mass (they sum to 1): the mesh's volume, sampled
    /// on a grid finer than the cells, spread to its cells' corners by trilinear weights, so
    /// that the particles' centre of mass and inertia are the volume's; each particle keeps at
    /// least a tenth of an even share (M/(8C) per incident cell).
    std::vector<float> massFraction;
    std::vector<Embedding> vertices; ///< #V embedding of every mesh vertex
    std::vector<CellBox> boxes;      ///< #B one per surface cell, in cell order
    std::vector<uint32_t> cellBox;   ///< #C box index of each cell, UINT32_MAX for interior
    /// The mesh vertices of each box, box by box: box k's are boxVertices[boxVertexStart[k],
    /// boxVertexStart[k + 1]), in vertex order. Every vertex is its own cell's box's (that
    /// box holds it: lattice.cpp adds every embedded vertex to its cell's box).
    std::vector<uint32_t> boxVertexStart; ///< #B + 1
    std::vector<BoxVertex> boxVertices;   ///< #V

    size_t cellCount() const { return cells.size(); }
    size_t particleCount() const { return restParticles.size(); }
    size_t surfaceCellCount() const { return boxes.size(); }
    size_t nodeCount() const { return boxes.size() * 8; }

    /// Index of the occupied cell at grid coordinate c, or UINT32_MAX.
    uint32_t findCell(GridCoord c) const;
    /// Rest-pose minimum corner of cell `cell`.
    Vec3 cellMin(uint32_t cell) const;

    /// Dense lookup grid -> cell index (UINT32_MAX for empty), dims.x * dims.y * dims.z.
    std::vector<uint32_t> cellIndex;
};

/// What the build did, for reports.
struct LatticeStats {
    int surfaceCells = 0;
    int interiorCells = 0;
    int searchSteps = 0; ///< lattice evaluations spent choosing h (targetCells)
    double buildSeconds = 0;
};

/// Builds the lattice of `mesh` (validated first; InputError on bad mesh or settings).
Lattice buildLattice(const TriangleMesh& mesh, const LatticeSettings& settings = {},
                     LatticeStats* outStats = nullptr);

/// The cell size buildLattice would use for these settings.
float chooseCellSize(const TriangleMesh& mesh, const LatticeSettings& settings,
                     int* outSearchSteps = nullptr);

/// Number of occupied cells the lattice of `mesh` would have with cell size h (no boxes, no
/// embedding; what the cell-size search evaluates).
int countCells(const TriangleMesh& mesh, float h, bool fillInterior);

/// Embeds an arbitrary rest-pose point: the occupied cell containing it (the nearest occupied
/// cell when none does) and its local coordinates there (not clamped).
Embedding embedPoint(const Lattice& lattice, Vec3 restPoint);

/// Position of an embedded point given particle positions (#P).
inline Vec3 evaluate(const Lattice& lattice, std::span<const Vec3> particles, const Embedding& e) {
    float w[8];
    trilinearWeights(e.local, w);
    const auto& corner = lattice.cellParticles[e.cell];
    Vec3 p{};
    for (int c = 0; c < 8; ++c) p += particles[corner[c]] * w[c];
    return p;
}

/// Deformed mesh vertices: outVertices[v] = trilinear blend of its cell's particles.
/// particles: #P positions; outVertices: #V.
void deformVertices(const Lattice& lattice, std::span<const Vec3> particles,
                    std::span<Vec3> outVertices);

/// Boundary nodes of every cell box from particle positions (the per-step FFD-AABB update,
/// 8 nodes per box independent of mesh density). particles: #P; outNodes: #B * 8, node n of
/// box b at b * 8 + n.
void updateBoxNodes(const Lattice& lattice, std::span<const Vec3> particles,
                    std::span<Vec3> outNodes);

/// Same for a range of boxes [first, first + count); outNodes holds count * 8 nodes.
void updateBoxNodes(const Lattice& lattice, std::span<const Vec3> particles, size_t first,
                    size_t count, std::span<Vec3> outNodes);

/// How far a lattice's cell boxes stand off its mesh at rest, direction by direction: along a
/// unit direction d, the farthest box node less the farthest mesh vertex (their dot products
/// with d). For a convex mesh that is how far its boxes reach beyond its surface that way, and
/// two such bodies pressed together along d rest about the sum of their two figures further
/// apart than touching, since the contacts hold their boxes apart (docs/LIMITS.md, known
/// problem 9). Never more than a cell's diagonal with its skin. In the mesh's units. The
/// commands summarise the sample with the project's one median and quantile (mesh-info).
struct BoxStandoff {
    std::vector<float> standoff; ///< one per direction, spread evenly over the sphere
    float max = 0;               ///< the largest
    Vec3 worstDirection;         ///< the direction of `max`
};

/// Measures BoxStandoff over `directions` (1..1,000,000) directions of a Fibonacci lattice on the
/// sphere; `mesh` is the one `lattice` was built from (InputError otherwise, or for a count
/// out of range). Cost: directions x (nodes + vertices) dot products.
BoxStandoff measureBoxStandoff(const Lattice& lattice, const TriangleMesh& mesh,
                               int directions = 2000);

} // namespace ffd
