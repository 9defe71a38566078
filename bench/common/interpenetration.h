// An engine-independent measure of how much closed triangle meshes interpenetrate, so that our
// engine and a peer (Bullet) are judged by one yardstick on their final (and sampled) states.
//
// For every unordered pair of bodies whose bounds overlap, each vertex of one body that lies
// inside the other's closed mesh counts, with depth = its distance to that mesh's surface.
// Inside means a generalized winding number above 1/2 (Jacobson, Kavan, Sorkine-Hornung 2013,
// "Robust inside-outside segmentation using generalized winding numbers"): unlike ray parity it
// stays meaningful when a squashed peer mesh folds over itself or a vertex sits on an edge.
#pragma once

#include "ffdaabb/math.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace ffd::bench {

/// One body's current surface: positions #V (metres) and triangles #T (counter-clockwise seen
/// from outside, closed). Views only; the caller owns the data.
struct MeshView {
    std::span<const Vec3> vertices;
    std::span<const std::array<uint32_t, 3>> triangles;
};

struct InterpenetrationSettings {
    float referenceSize = 1.0f; ///< metres; depths are also reported divided by it (diameter)
    float floorHeight = 0.0f;   ///< the floor plane y = floorHeight, for the below-floor figures
    float deepFraction = 0.01f; ///< a vertex deeper than deepFraction * referenceSize is "deep"
    /// Bodies closer than gapFraction * referenceSize count as neighbours for the gap figures.
    float gapFraction = 0.1f;
};

/// What measureInterpenetration found. Depths in metres.
struct Interpenetration {
    int bodies = 0;
    int bodyPairs = 0;      ///< unordered pairs with a vertex of either inside the other
    int insideVertices = 0; ///< vertices inside another body (a vertex inside two counts twice)
    int deepVertices = 0;   ///< of those, deeper than deepFraction * referenceSize
    double maxDepth = 0;    ///< deepest vertex, distance to the other body's surface
    double meanDepth = 0;   ///< mean depth of the inside vertices (0 when none)
    double maxDepthRelative = 0; ///< maxDepth / referenceSize
    /// The deepest vertex (-1 when none is inside): vertex `deepestVertex` of body
    /// `deepestBody` lies inside body `deepestInside`, maxDepth from its surface. Indices are
    /// into the measured bodies; of equally deep vertices, the first found.
    int deepestBody = -1, deepestVertex = -1, deepestInside = -1;
    double lowestY = 0;         ///< lowest vertex y over all bodies
    double belowFloor = 0;      ///< max(0, floorHeight - lowestY)
    int belowFloorVertices = 0; ///< vertices below the floor plane
    /// The other side of the trade: how far apart neighbours rest. Each body's gap is the
    /// smallest vertex-to-surface distance to any other body (0 when they interpenetrate), for
    /// bodies with a neighbour within gapFraction * referenceSize ("near bodies"). In a resting
    /// pile that is the contact gap an engine keeps (a collision margin shows up here).
    int nearBodies = 0;
    double medianGap = 0; ///< over near bodies, metres
    double meanGap = 0;
    double minGap = 0;  ///< the closest pair of near bodies (0 when any interpenetrate)
    bool finite = true; ///< every vertex finite (non-finite bodies are skipped)
};

/// Generalized winding number of `point` with respect to `mesh`: 1 inside a closed outward
/// mesh, 0 outside (sum of signed solid angles / 4 pi, Van Oosterom and Strackee's formula).
/// O(#T): every triangle's solid angle (MeshTree: the same number from far fewer).
double windingNumber(Vec3 point, const MeshView& mesh);

/// True when windingNumber(point, mesh) > 1/2.
bool insideMesh(Vec3 point, const MeshView& mesh);

/// Unsigned distance from `point` to the nearest triangle of `mesh`; O(#T).
double distanceToSurface(Vec3 point, const MeshView& mesh);

/// The point of `mesh`'s surface nearest to `point`.
Vec3 closestPointOnSurface(Vec3 point, const MeshView& mesh);

/// A bounding volume hierarchy over one mesh's triangles (as they are when it is made), for
/// the two queries the measure asks of every vertex near another body, without visiting every
/// triangle:
/// - the winding number, evaluated hierarchically and still exactly (Jacobson et al. 2013,
///   section 3.3): a subtree whose bounding box does not contain the point adds the solid
///   angles of a fan from its box's centre over its triangles' boundary edges instead of its
///   triangles' own (the two surfaces together are closed and lie in the box, so they add 0
///   at a point outside it). Any triangle soup, closed or not; equal to windingNumber up to
///   the rounding of the sums;
/// - the squared distance to the nearest triangle, subtrees farther than the best so far left
///   out: the same number distanceToSurface squares.
/// Views the mesh, which must outlive it unchanged.
class MeshTree {
public:
    explicit MeshTree(const MeshView& mesh);
    double windingNumber(Vec3 point) const;
    bool inside(Vec3 point) const { return windingNumber(point) > 0.5; }
    /// The least squared distance from `point` to a triangle, or `limit` when none is nearer.
    double distanceSquared(Vec3 point, double limit) const;
    double distanceToSurface(Vec3 point) const;
    size_t nodeCount() const { return nodes_.size(); }
    /// Subtrees that a point outside their box reads through their boundary's fan.
    size_t fanCount() const {
        return size_t(
            std::count_if(nodes_.begin(), nodes_.end(), [](const Node& n) { return n.fan; }));
    }

private:
    using P3 = std::array<double, 3>;
    struct Node {
        P3 lo, hi, apex;        ///< bounds of its triangles' vertices; the fan's apex
        uint32_t first, count;  ///< its triangles, order_[first, first + count)
        uint32_t right = 0;     ///< second child (the first is the next node); 0: a leaf
        uint32_t edgeFirst = 0; ///< its boundary's directed edges, edges_[edgeFirst, ...)
        uint32_t edgeCount = 0; ///< (kept only when fewer than its triangles: `fan`)
        bool fan = false;
    };
    using Edge = std::array<uint32_t, 2>;
    std::vector<Edge> build(uint32_t first, uint32_t count, const std::vector<P3>& centroid);

    MeshView mesh_;
    std::vector<P3> v_;
    std::vector<uint32_t> order_;
    std::vector<Node> nodes_;
    std::vector<Edge> edges_;
};

/// Measures the interpenetration of `bodies` (each a closed mesh), the gaps between neighbours
/// and their position relative to the floor. Cost: for each pair with overlapping bounds, one
/// winding number per vertex of either body inside the other's bounds; one distance per inside
/// vertex, and per vertex within the gap range of a separate neighbour's bounds; each through
/// the other body's MeshTree (made once per call, for the bodies that are near another).
/// Called for each vertex found inside another body: body `a`'s vertex `vertex` lies inside
/// body `b`'s mesh, `depth` metres from its surface (indices into the measured bodies).
using InsideVertexFn = std::function<void(size_t a, size_t vertex, size_t b, double depth)>;

Interpenetration measureInterpenetration(std::span<const MeshView> bodies,
                                         const InterpenetrationSettings& settings = {},
                                         const InsideVertexFn& onInside = {});

/// Folds `sample` into `ioWorst` field by field: maxima of the counts, the depths (meanDepth
/// included; the deepest vertex goes with maxDepth), medianGap and meanGap; minima of lowestY and
/// (over samples with near bodies) of minGap, the closest approach; and of finiteness. A default
/// (empty, 0 bodies) `ioWorst` takes the sample as it is.
void keepWorst(Interpenetration& ioWorst, const Interpenetration& sample);

} // namespace ffd::bench
