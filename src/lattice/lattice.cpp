// The sparse FFD lattice: voxelisation, particles, embedding and FFD-AABB cell boxes.
//
// References: Sederberg & Parry 1986 (FFD); Jung, Hong & Choi, IET Image Processing 5(4), 2011
// (FFD-AABB, Fig. 1 of Jeon, Choi & Hong 2012: build the grid, the per-cell AABB of the mesh,
// then the boundary nodes' local coordinates and the outside surface set).
#include "ffdaabb/lattice.h"

#include "dynamics/simd4.h"
#include "ffdaabb/error.h"
#include "lattice/geometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <string>

namespace ffd {

namespace {

// Upper bound on grid cells (occupied or not) so that absurd cell sizes fail cleanly instead of
// exhausting memory: 2^27 bytes of occupancy state at most.
constexpr int64_t kMaxGridCells = int64_t(1) << 27;

// Cell states during voxelisation.
constexpr uint8_t kEmpty = 0, kSurface = 1, kInterior = 2;

struct Grid {
    float h = 0;
    Vec3 origin;
    GridCoord dims{1, 1, 1};

    int64_t size() const { return int64_t(dims[0]) * dims[1] * dims[2]; }
    int64_t index(int i, int j, int k) const {
        return int64_t(i) + int64_t(dims[0]) * (int64_t(j) + int64_t(dims[1]) * k);
    }
    Vec3 cellMin(int i, int j, int k) const {
        return origin + Vec3{float(i), float(j), float(k)} * h;
    }
    int clampAxis(float v, int axis) const {
        const float f = std::floor((v - origin[axis]) / h);
        if (!(f >= 0)) return 0; // also catches NaN
        return f >= float(dims[axis] - 1) ? dims[axis] - 1 : int(f);
    }
};

std::string describe(float v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", double(v));
    return buf;
}

// A grid of cell size h holding the mesh bounds.
Grid makeGrid(const Aabb& box, float h) {
    Grid g;
    g.h = h;
    const Vec3 extent = box.extent();
    int64_t total = 1;
    for (int a = 0; a < 3; ++a) {
        const double n = std::ceil(double(extent[a]) / double(h));
        if (!(n <= double(kMaxGridCells))) // NaN too
            throw InputError("lattice.cellSize",
                             "cell size " + describe(h) + " is too small for an object of extent " +
                                 describe(extent[a]) + " (the grid would be too large)");
        g.dims[a] = std::max(1, int(n));
        total *= g.dims[a];
    }
    if (total > kMaxGridCells)
        throw InputError("lattice.cellSize",
                         "cell size " + describe(h) + " gives a grid of " + std::to_string(total) +
                             " cells (at most " + std::to_string(kMaxGridCells) +
                             " supported); use a larger cell size or fewer target cells");
    // Anchored at the minimum corner (centring makes counts jump: a sphere goes 27 -> 56).
    g.origin = box.lo;
    return g;
}

// Marks surface cells (a triangle touches them) and, optionally, the interior cells a flood fill
// of the outside does not reach. Returns the state of every grid cell.
std::vector<uint8_t> voxelize(const TriangleMesh& mesh, const Grid& g, bool fillInterior) {
    std::vector<uint8_t> state(size_t(g.size()), kEmpty);
    // A touch within a millionth of h counts: conservative, so grazing triangles get a cell.
    const float tolerance = g.h * 1e-6f;
    for (const auto& t : mesh.triangles) {
        const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
        const Vec3 lo = min(a, min(b, c)), hi = max(a, max(b, c));
        const int i0 = g.clampAxis(lo.x - tolerance, 0), i1 = g.clampAxis(hi.x + tolerance, 0);
        const int j0 = g.clampAxis(lo.y - tolerance, 1), j1 = g.clampAxis(hi.y + tolerance, 1);
        const int k0 = g.clampAxis(lo.z - tolerance, 2), k1 = g.clampAxis(hi.z + tolerance, 2);
        const bool single = i0 == i1 && j0 == j1 && k0 == k1;
        for (int k = k0; k <= k1; ++k)
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) {
                    uint8_t& s = state[size_t(g.index(i, j, k))];
                    if (s == kSurface) continue;
                    const Vec3 cmin = g.cellMin(i, j, k);
                    if (single || detail::triangleOverlapsBox(
                                      a, b, c, cmin, cmin + Vec3{g.h, g.h, g.h}, tolerance))
                        s = kSurface;
                }
    }
    if (!fillInterior) return state;

    // Flood the outside through a one-cell pad around the grid (6-connected: a closed surface
    // voxelised conservatively never leaks), then whatever is neither reached nor surface is
    // interior.
    const int px = g.dims[0] + 2, py = g.dims[1] + 2, pz = g.dims[2] + 2;
    std::vector<uint8_t> outside(size_t(px) * py * pz, 0);
    auto padIndex = [&](int i, int j, int k) {
        return size_t(i) + size_t(px) * (j + size_t(py) * k);
    };
    auto blocked = [&](int i, int j, int k) {
        // Padded coordinates; the pad is never blocked.
        if (i == 0 || j == 0 || k == 0 || i == px - 1 || j == py - 1 || k == pz - 1) return false;
        return state[size_t(g.index(i - 1, j - 1, k - 1))] == kSurface;
    };
    std::vector<std::array<int, 3>> stack{{0, 0, 0}};
    outside[0] = 1;
    while (!stack.empty()) {
        const auto [i, j, k] = stack.back();
        stack.pop_back();
        const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                              {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
        for (const auto& n : nb) {
            if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= px || n[1] >= py || n[2] >= pz)
                continue;
            const size_t idx = padIndex(n[0], n[1], n[2]);
            if (outside[idx] || blocked(n[0], n[1], n[2])) continue;
            outside[idx] = 1;
            stack.push_back({n[0], n[1], n[2]});
        }
    }
    for (int k = 0; k < g.dims[2]; ++k)
        for (int j = 0; j < g.dims[1]; ++j)
            for (int i = 0; i < g.dims[0]; ++i) {
                uint8_t& s = state[size_t(g.index(i, j, k))];
                if (s == kEmpty && !outside[padIndex(i + 1, j + 1, k + 1)]) s = kInterior;
            }
    return state;
}

// Sub-cells per cell edge for the mass distribution, and the budget of sub-cells it may sample.
constexpr int kMassSamples = 8;
constexpr int64_t kMassSampleBudget = int64_t(1) << 22;
// The least mass a particle keeps, as a share of its even share (massFractions).
constexpr float kLeastMassShare = 0.1f;

// Each particle's share of the body's mass (Lattice::massFraction): the mesh voxelised again on a
// grid n times finer than the cells (n = kMassSamples, less for lattices past the budget), each
// sub-cell weighing 1 when inside the surface, 1/2 when the surface touches it and 0 outside,
// spread to the 8 corners of its cell by the trilinear weights of its centre. The body's centre
// of mass and its inertia are then those of the mesh's volume (to about a sub-cell), where an
// even share per cell put them at the lattice's centre: a letter a cell deep whose back face
// grazes a second layer of cells had its centre of mass on that face, and a sphere its centre
// 19 % of its radius off (docs/ALGORITHM.md §1, "Mass"). Every particle keeps at least
// kLeastMassShare of its even share (its incident cells' M/(8C)), so that none is massless; an
// empty volume (a sheet voxelised without interior) gives the even shares.
std::vector<float> massFractions(const TriangleMesh& mesh, const Lattice& L, const Grid& g,
                                 bool fillInterior) {
    const size_t P = L.particleCount();
    std::vector<float> even(P, 0.0f);
    const float share = 1.0f / (8.0f * float(L.cellCount()));
    for (const auto& corners : L.cellParticles)
        for (const uint32_t p : corners) even[p] += share;
    int n = kMassSamples;
    while (n > 1 && g.size() * n * n * n > kMassSampleBudget) --n;
    Grid fine;
    fine.h = g.h / float(n);
    fine.origin = g.origin;
    for (int a = 0; a < 3; ++a) fine.dims[a] = g.dims[a] * n;
    const std::vector<uint8_t> state = voxelize(mesh, fine, fillInterior);
    std::vector<double> mass(P, 0.0);
    double total = 0;
    for (size_t c = 0; c < L.cellCount(); ++c) {
        const GridCoord& cell = L.cells[c];
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const uint8_t st = state[size_t(
                        fine.index(cell[0] * n + i, cell[1] * n + j, cell[2] * n + k))];
                    const double weight = st == kInterior ? 1.0 : st == kSurface ? 0.5 : 0.0;
                    if (weight == 0) continue;
                    const Vec3 local{(float(i) + 0.5f) / float(n), (float(j) + 0.5f) / float(n),
                                     (float(k) + 0.5f) / float(n)};
                    float w[8];
                    trilinearWeights(local, w);
                    for (int corner = 0; corner < 8; ++corner)
                        mass[L.cellParticles[c][corner]] += weight * double(w[corner]);
                    total += weight;
                }
    }
    if (!(total > 0)) return even;
    std::vector<float> out(P);
    double sum = 0;
    for (size_t p = 0; p < P; ++p) {
        out[p] = std::max(float(mass[p] / total), kLeastMassShare * even[p]);
        sum += double(out[p]);
    }
    for (float& m : out) m = float(double(m) / sum);
    return out;
}

void checkSettings(const LatticeSettings& s) {
    if (!std::isfinite(s.cellSize) || s.cellSize < 0)
        throw InputError("lattice.cellSize", "cell size " + describe(s.cellSize) +
                                                 " is invalid (expected a positive number, or 0 "
                                                 "to choose it from targetCells/resolution)");
    if (!std::isfinite(s.resolution) || s.resolution < 0 || s.resolution > 4096)
        throw InputError("lattice.resolution",
                         "resolution " + describe(s.resolution) +
                             " is out of range (expected cells along the longest extent, 0..4096)");
    if (s.cellSize == 0 && s.resolution == 0 && (s.targetCells < 1 || s.targetCells > 1000000))
        throw InputError("lattice.targetCells", "target cell count " +
                                                    std::to_string(s.targetCells) +
                                                    " is out of range (expected 1..1000000)");
    if (!std::isfinite(s.boxSkin) || s.boxSkin < 0 || s.boxSkin > 0.25f)
        throw InputError("lattice.boxSkin", "box skin " + describe(s.boxSkin) +
                                                " is out of range (expected 0..0.25 of a cell)");
}

float longestExtent(const TriangleMesh& mesh) {
    const float e = maxComponent(bounds(mesh).extent());
    if (!(e > 0))
        throw InputError(
            mesh.name.empty() ? "mesh" : mesh.name,
            "the mesh has zero extent (all vertices coincide); cannot build a lattice");
    return e;
}

} // namespace

uint32_t Lattice::findCell(GridCoord c) const {
    if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= dims[0] || c[1] >= dims[1] || c[2] >= dims[2])
        return UINT32_MAX;
    return cellIndex[size_t(c[0]) + size_t(dims[0]) * (size_t(c[1]) + size_t(dims[1]) * c[2])];
}

Vec3 Lattice::cellMin(uint32_t cell) const {
    const GridCoord& c = cells[cell];
    return origin + Vec3{float(c[0]), float(c[1]), float(c[2])} * cellSize;
}

int countCells(const TriangleMesh& mesh, float h, bool fillInterior) {
    const Grid g = makeGrid(bounds(mesh), h);
    const std::vector<uint8_t> state = voxelize(mesh, g, fillInterior);
    int n = 0;
    for (uint8_t s : state) n += s != kEmpty;
    return n;
}

float chooseCellSize(const TriangleMesh& mesh, const LatticeSettings& settings,
                     int* outSearchSteps) {
    checkSettings(settings);
    if (outSearchSteps) *outSearchSteps = 0;
    if (settings.cellSize > 0) return settings.cellSize;
    const float extent = longestExtent(mesh);
    if (settings.resolution > 0) return extent / settings.resolution;

    // Bisection on log h: the count falls (not strictly monotonically) as h grows; keep the h
    // whose count is nearest the target, preferring the larger h on ties.
    const int target = settings.targetCells;
    double lo = std::log(double(extent) / 512.0), hi = std::log(double(extent) * 1.01);
    float best = float(std::exp(hi));
    int bestError = std::numeric_limits<int>::max();
    int steps = 0;
    for (; steps < 48 && bestError > 0; ++steps) {
        const double mid = 0.5 * (lo + hi);
        const float h = float(std::exp(mid));
        const int n = countCells(mesh, h, settings.fillInterior);
        const int error = std::abs(n - target);
        if (error < bestError || (error == bestError && h > best)) best = h, bestError = error;
        if (n > target)
            lo = mid;
        else
            hi = mid;
        if (hi - lo < 1e-7) break;
    }
    if (outSearchSteps) *outSearchSteps = steps;
    return best;
}

Embedding embedPoint(const Lattice& lattice, Vec3 p) {
    const float h = lattice.cellSize;
    GridCoord c;
    for (int a = 0; a < 3; ++a) {
        const float f = std::floor((p[a] - lattice.origin[a]) / h);
        c[a] = !(f >= 0) ? 0 : (f >= float(lattice.dims[a] - 1) ? lattice.dims[a] - 1 : int(f));
    }
    uint32_t cell = lattice.findCell(c);
    if (cell == UINT32_MAX) {
        // Outside every occupied cell (only for points off the mesh): the nearest cell by
        // distance to its box, lowest index on ties.
        float bestDistance = std::numeric_limits<float>::max();
        cell = 0; // when every distance overflows (coordinates near 1e38)
        for (uint32_t i = 0; i < lattice.cells.size(); ++i) {
            const Vec3 lo = lattice.cellMin(i);
            const Vec3 q = max(lo, min(p, lo + Vec3{h, h, h}));
            const float d = lengthSquared(p - q);
            if (d < bestDistance) bestDistance = d, cell = i;
        }
    }
    return {cell, (p - lattice.cellMin(cell)) / h};
}

Lattice buildLattice(const TriangleMesh& mesh, const LatticeSettings& settings,
                     LatticeStats* outStats) {
    const auto start = std::chrono::steady_clock::now();
    validate(mesh, mesh.name.empty() ? "mesh" : mesh.name);
    LatticeStats stats;
    const float h = chooseCellSize(mesh, settings, &stats.searchSteps);
    const Grid g = makeGrid(bounds(mesh), h);
    const std::vector<uint8_t> state = voxelize(mesh, g, settings.fillInterior);

    Lattice L;
    L.cellSize = h;
    L.origin = g.origin;
    L.dims = g.dims;
    L.cellIndex.assign(size_t(g.size()), UINT32_MAX);

    // Cells in grid order (x fastest), so everything downstream is deterministic.
    for (int k = 0; k < g.dims[2]; ++k)
        for (int j = 0; j < g.dims[1]; ++j)
            for (int i = 0; i < g.dims[0]; ++i) {
                const uint8_t s = state[size_t(g.index(i, j, k))];
                if (s == kEmpty) continue;
                L.cellIndex[size_t(g.index(i, j, k))] = uint32_t(L.cells.size());
                L.cells.push_back({i, j, k});
                L.cellIsSurface.push_back(s == kSurface);
                (s == kSurface ? stats.surfaceCells : stats.interiorCells)++;
            }

    // Coordinates so large that single-precision products overflow (1e38) can leave every
    // triangle-box test undecided: a lattice without cells embeds nothing.
    if (L.cells.empty())
        throw InputError(mesh.name.empty() ? "mesh" : mesh.name,
                         "the mesh occupies no lattice cell: its extent of " +
                             describe(maxComponent(bounds(mesh).extent())) +
                             " is beyond what single precision can voxelise");

    // Particles: the corners of occupied cells, numbered in grid-point order.
    const int qx = g.dims[0] + 1, qy = g.dims[1] + 1, qz = g.dims[2] + 1;
    auto pointIndex = [&](int i, int j, int k) {
        return size_t(i) + size_t(qx) * (j + size_t(qy) * k);
    };
    std::vector<uint32_t> pointParticle(size_t(qx) * qy * qz, 0);
    for (const GridCoord& c : L.cells)
        for (int corner = 0; corner < 8; ++corner)
            pointParticle[pointIndex(c[0] + (corner & 1), c[1] + ((corner >> 1) & 1),
                                     c[2] + ((corner >> 2) & 1))] = 1;
    for (int k = 0; k < qz; ++k)
        for (int j = 0; j < qy; ++j)
            for (int i = 0; i < qx; ++i) {
                uint32_t& slot = pointParticle[pointIndex(i, j, k)];
                if (!slot) {
                    slot = UINT32_MAX;
                    continue;
                }
                slot = uint32_t(L.restParticles.size());
                L.restParticles.push_back(g.cellMin(i, j, k));
                L.particleCoords.push_back({i, j, k});
            }
    L.cellParticles.resize(L.cells.size());
    for (size_t c = 0; c < L.cells.size(); ++c)
        for (int corner = 0; corner < 8; ++corner)
            L.cellParticles[c][corner] = pointParticle[pointIndex(
                L.cells[c][0] + (corner & 1), L.cells[c][1] + ((corner >> 1) & 1),
                L.cells[c][2] + ((corner >> 2) & 1))];

    // Embedding of every vertex.
    L.vertices.resize(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v)
        L.vertices[v] = embedPoint(L, mesh.positions[v]);

    // Cell boxes: the AABB of the mesh part inside each surface cell, from the triangles
    // clipped to the cell (so triangles spanning cells are covered), clamped to the cell.
    std::vector<Aabb> parts(L.cells.size());
    for (const auto& t : mesh.triangles) {
        const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
        const Vec3 lo = min(a, min(b, c)), hi = max(a, max(b, c));
        for (int k = g.clampAxis(lo.z, 2); k <= g.clampAxis(hi.z, 2); ++k)
            for (int j = g.clampAxis(lo.y, 1); j <= g.clampAxis(hi.y, 1); ++j)
                for (int i = g.clampAxis(lo.x, 0); i <= g.clampAxis(hi.x, 0); ++i) {
                    const uint32_t cell = L.cellIndex[size_t(g.index(i, j, k))];
                    if (cell == UINT32_MAX || !L.cellIsSurface[cell]) continue;
                    const Vec3 cmin = g.cellMin(i, j, k);
                    detail::addClippedTriangle(a, b, c, cmin, cmin + Vec3{h, h, h}, parts[cell]);
                }
    }
    // In local coordinates, clamped to the cell; every vertex embedded in the cell is added
    // explicitly so that it is inside its box even where clipping rounded.
    std::vector<Aabb> local(L.cells.size());
    for (size_t c = 0; c < L.cells.size(); ++c) {
        if (parts[c].empty()) continue;
        const Vec3 cmin = L.cellMin(uint32_t(c));
        local[c].add(max(Vec3{0, 0, 0}, min((parts[c].lo - cmin) / h, Vec3{1, 1, 1})));
        local[c].add(max(Vec3{0, 0, 0}, min((parts[c].hi - cmin) / h, Vec3{1, 1, 1})));
    }
    for (const Embedding& e : L.vertices) local[e.cell].add(e.local);

    // Whether the space beyond face f of cell c's box, towards occupied cell `next`, is outside
    // the mesh. Between the box's face and the part of the mesh in `next` (across the whole
    // cross-section of the two cells) no triangle lies, so that space is all inside or all
    // outside, and one point of it says which: the middle of the gap between the two parts (`next`
    // counts whole when it holds none). A surface that runs on into `next` leaves no gap, and the
    // face leads into the body, as does one towards a cell filled as interior. Where two parts
    // of a mesh face each other across a notch narrower than a cell (the legs of an H), or a
    // surface leaves the cell across an edge or corner (a sphere's cells on the diagonal), the
    // gap is outside and the face leads out of the body: another body can lie there, and no
    // box of `next` meets it first (docs/ALGORITHM.md, section 2).
    const std::vector<uint8_t> surfaceCell = L.cellIsSurface;
    auto facesOutside = [&](size_t c, uint32_t next, int f) {
        if (!surfaceCell[next]) return false; // filled as interior: inside the mesh
        const int axis = f >> 1;
        const bool up = f & 1;
        // The surface-free stretch along the axis, in cells: this part's gap to its cell's
        // face and the next part's gap to the same face (a whole cell when it holds none).
        const float mine = up ? 1.0f - local[c].hi[axis] : local[c].lo[axis];
        const bool empty = local[next].empty();
        const float theirs = empty ? 1.0f : up ? local[next].lo[axis] : 1.0f - local[next].hi[axis];
        if (!(mine + theirs > settings.boxSkin)) return false;
        Vec3 q{0.5f, 0.5f, 0.5f}; // in this cell's local coordinates
        q[axis] = up ? 1.0f + 0.5f * (theirs - mine) : 0.5f * (mine - theirs);
        return detail::windingNumber(mesh, L.cellMin(uint32_t(c)) + q * h) < 0.5;
    };
    L.cellBox.assign(L.cells.size(), UINT32_MAX);
    const float skin = settings.boxSkin;
    const GridCoord steps[6] = {{-1, 0, 0}, {1, 0, 0},  {0, -1, 0},
                                {0, 1, 0},  {0, 0, -1}, {0, 0, 1}};
    for (size_t c = 0; c < L.cells.size(); ++c) {
        if (!L.cellIsSurface[c]) continue;
        if (local[c].empty()) {
            // Touched only within the overlap tolerance: no surface of its own to bound.
            L.cellIsSurface[c] = 0;
            --stats.surfaceCells, ++stats.interiorCells;
            continue;
        }
        CellBox box;
        box.cell = uint32_t(c);
        box.lo = local[c].lo - Vec3{skin, skin, skin};
        box.hi = local[c].hi + Vec3{skin, skin, skin};
        for (int f = 0; f < 6; ++f) {
            const GridCoord n{L.cells[c][0] + steps[f][0], L.cells[c][1] + steps[f][1],
                              L.cells[c][2] + steps[f][2]};
            const uint32_t next = L.findCell(n);
            if (next == UINT32_MAX || facesOutside(c, next, f))
                box.outsideFaces |= uint8_t(1u << f);
        }
        L.cellBox[c] = uint32_t(L.boxes.size());
        L.boxes.push_back(box);
    }

    // Each box's vertices (counting sort by box, in vertex order).
    L.boxVertexStart.assign(L.boxes.size() + 1, 0);
    for (const Embedding& e : L.vertices)
        if (L.cellBox[e.cell] != UINT32_MAX) ++L.boxVertexStart[L.cellBox[e.cell] + 1];
    for (size_t k = 0; k < L.boxes.size(); ++k) L.boxVertexStart[k + 1] += L.boxVertexStart[k];
    L.boxVertices.resize(L.boxVertexStart.back());
    {
        std::vector<uint32_t> at(L.boxVertexStart.begin(), L.boxVertexStart.end() - 1);
        for (size_t v = 0; v < L.vertices.size(); ++v) {
            const Embedding& e = L.vertices[v];
            if (L.cellBox[e.cell] != UINT32_MAX)
                L.boxVertices[at[L.cellBox[e.cell]]++] = {uint32_t(v), e.local};
        }
    }

    L.massFraction = massFractions(mesh, L, g, settings.fillInterior);

    stats.buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (outStats) *outStats = stats;
    return L;
}

void deformVertices(const Lattice& lattice, std::span<const Vec3> particles,
                    std::span<Vec3> outVertices) {
    using detail::F4;
    using detail::splat;
    const size_t n = std::min(outVertices.size(), lattice.vertices.size());
    const Embedding* embed = lattice.vertices.data();
    // Each cell's trilinear map as a polynomial in (s, t, u), its 8 coefficients (x, y, z in a
    // vector's lanes) made once: p = a + b s + c t + d u + e st + f su + g tu + h stu.
    thread_local std::vector<F4> poly;
    poly.resize(lattice.cellParticles.size() * 8);
    for (size_t c = 0; c < lattice.cellParticles.size(); ++c) {
        const std::array<uint32_t, 8>& q = lattice.cellParticles[c];
        F4 p[8];
        for (int k = 0; k < 8; ++k) {
            const Vec3 v = particles[q[k]];
            p[k] = F4{v.x, v.y, v.z, 0.0f};
        }
        // The cell's four edges along s (corners 2j + 4k to 2j + 4k + 1).
        const F4 e00 = p[1] - p[0], e10 = p[3] - p[2], e01 = p[5] - p[4], e11 = p[7] - p[6];
        F4* out = &poly[c * 8];
        out[0] = p[0];
        out[1] = e00;
        out[2] = p[2] - p[0];
        out[3] = p[4] - p[0];
        out[4] = e10 - e00;
        out[5] = e01 - e00;
        out[6] = (p[6] - p[4]) - (p[2] - p[0]);
        out[7] = (e11 - e01) - (e10 - e00);
    }
    float* out = &outVertices.data()->x;
    auto vertex = [&](size_t v) {
        const Embedding e = embed[v];
        const F4* k = &poly[size_t(e.cell) * 8];
        const float s = e.local.x, t = e.local.y, u = e.local.z;
        return k[0] + k[1] * splat(s) + k[2] * splat(t) + k[3] * splat(u) + k[4] * splat(s * t) +
               k[5] * splat(s * u) + k[6] * splat(t * u) + k[7] * splat(s * t * u);
    };
    // Four floats a vertex, the fourth overwritten by the next vertex's x; the last one three.
    for (size_t v = 0; v + 1 < n; ++v) detail::store4(out + 3 * v, vertex(v));
    if (n > 0) {
        const F4 r = vertex(n - 1);
        out[3 * (n - 1)] = r[0], out[3 * (n - 1) + 1] = r[1], out[3 * (n - 1) + 2] = r[2];
    }
}

void updateBoxNodes(const Lattice& lattice, std::span<const Vec3> particles, size_t first,
                    size_t count, std::span<Vec3> outNodes) {
    const Vec3* x = particles.data();
    for (size_t b = 0; b < count; ++b) {
        const CellBox& box = lattice.boxes[first + b];
        const std::array<uint32_t, 8>& q = lattice.cellParticles[box.cell];
        // The box is a sub-box of its cell, so its corners follow from lerps of the cell's
        // corners: 8 along x (lo and hi for 4 edges), 8 along y, 8 along z.
        Vec3 ex[2][4];
        for (int e = 0; e < 4; ++e) {
            const Vec3 a = x[q[2 * e]], d = x[q[2 * e + 1]] - a;
            ex[0][e] = a + d * box.lo.x;
            ex[1][e] = a + d * box.hi.x;
        }
        Vec3 ey[2][2][2]; // [x side][y side][z layer]
        for (int sx = 0; sx < 2; ++sx)
            for (int layer = 0; layer < 2; ++layer) {
                const Vec3 a = ex[sx][2 * layer], d = ex[sx][2 * layer + 1] - a;
                ey[sx][0][layer] = a + d * box.lo.y;
                ey[sx][1][layer] = a + d * box.hi.y;
            }
        Vec3* out = outNodes.data() + b * 8;
        for (int n = 0; n < 8; ++n) {
            const int sx = n & 1, sy = (n >> 1) & 1, sz = (n >> 2) & 1;
            const Vec3 a = ey[sx][sy][0], d = ey[sx][sy][1] - a;
            out[n] = a + d * (sz ? box.hi.z : box.lo.z);
        }
    }
}

void updateBoxNodes(const Lattice& lattice, std::span<const Vec3> particles,
                    std::span<Vec3> outNodes) {
    updateBoxNodes(lattice, particles, 0, lattice.boxes.size(), outNodes);
}

BoxStandoff measureBoxStandoff(const Lattice& lattice, const TriangleMesh& mesh, int directions) {
    if (directions < 1 || directions > 1000000)
        throw InputError("directions", "must be 1..1000000, got " + std::to_string(directions));
    if (mesh.positions.size() != lattice.vertices.size())
        throw InputError(mesh.name.empty() ? "mesh" : mesh.name,
                         "has " + std::to_string(mesh.positions.size()) +
                             " vertices, the lattice embeds " +
                             std::to_string(lattice.vertices.size()) + ": not the lattice's mesh");
    BoxStandoff r;
    if (lattice.boxes.empty() || mesh.positions.empty()) return r;
    std::vector<Vec3> nodes(lattice.nodeCount());
    updateBoxNodes(lattice, lattice.restParticles, nodes);
    std::vector<float>& standoff = r.standoff;
    standoff.resize(static_cast<size_t>(directions));
    constexpr double kGoldenAngle = 2.399963229728653; // pi (3 - sqrt 5)
    for (int i = 0; i < directions; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / directions, ring = std::sqrt(1.0 - z * z);
        const Vec3 d{float(ring * std::cos(i * kGoldenAngle)),
                     float(ring * std::sin(i * kGoldenAngle)), float(z)};
        float boxes = -INFINITY, surface = -INFINITY;
        for (const Vec3& n : nodes) boxes = std::max(boxes, dot(d, n));
        for (const Vec3& v : mesh.positions) surface = std::max(surface, dot(d, v));
        standoff[size_t(i)] = boxes - surface;
        if (i == 0 || standoff[size_t(i)] > r.max)
            r.max = standoff[size_t(i)], r.worstDirection = d;
    }
    return r;
}

} // namespace ffd
