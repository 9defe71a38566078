// What the queries (ffdaabb/queries.h) keep in a world: the caches of the geometric queries
// (queries.cpp) and the contact tally of the step (contact_tally.cpp).
#pragma once

#include "ffdaabb/math.h"
#include "ffdaabb/queries.h"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace ffd::detail {

struct WorldData;

/// A bounding-volume hierarchy over a mesh's triangles, built on the rest pose and shared by
/// every body of a model; its boxes are refitted per body (BodyQueryCache).
struct TriangleBvh {
    struct Node {
        uint32_t first = 0; ///< leaf: its triangles are order[first, first + count)
        uint32_t count = 0; ///< 0 for an inner node
        uint32_t right = 0; ///< inner node: its second child (the first is the next node)
    };
    std::vector<Node> nodes;     ///< depth first: a node's children come after it
    std::vector<uint32_t> order; ///< triangle indices, grouped by leaf
    bool closed = false;         ///< the mesh is closed (isClosed): a ray's crossings count
};

/// A body's refitted hierarchy, current while `epoch` is the cache's.
struct BodyQueryCache {
    uint64_t epoch = 0;      ///< 0: never refitted
    std::vector<Aabb> boxes; ///< per node of its model's TriangleBvh
};

/// The geometric queries' caches. `epoch` moves on whenever vertices may have changed (a step,
/// updateMesh, bodies added or removed); everything refitted under an older epoch is stale.
struct QueryCache {
    uint64_t epoch = 1;
    uint64_t boundsEpoch = 0;           ///< when `bounds` were computed
    std::vector<Aabb> bounds;           ///< per dense body: its vertices' box
    std::vector<BodyQueryCache> bodies; ///< per dense body
    std::map<const void*, std::unique_ptr<TriangleBvh>> models; ///< by BodyModel
    std::vector<std::pair<float, uint32_t>> rayOrder;           ///< scratch: entry, body
};

/// One run of consecutive contacts of one pair in a substep, before they are merged.
struct ContactRun {
    uint64_t key = 0; ///< dense A << 32 | dense B (UINT32_MAX: the floor), A < B
    double impulse = 0;
    double vx = 0, vy = 0, vz = 0; ///< the impulse on A, as a vector
    uint32_t count = 0;
};

/// The contact pairs and events of the last step and what makes them.
struct ContactTally {
    std::vector<ContactRun> runs;                        ///< this step's, substep after substep
    std::vector<std::pair<uint64_t, uint32_t>> sortKeys; ///< scratch: key, run
    std::vector<ContactPair> pairs, previous;
    std::vector<uint64_t> pairKeys; ///< per pair, its dense key (at the step)
    std::vector<ContactEvent> begin, end;
    std::vector<uint64_t> scratch;
};

/// After each substep's response: adds the substep's contacts (collision state's `all`) to the
/// step's runs.
void tallyContacts(WorldData& world);

/// At the end of a step: the step's pairs from its runs, and the events against the previous
/// step's pairs.
void finishContactTally(WorldData& world);

/// The queries without their culling (for tests): every triangle of every body against the
/// same ray and box tests as raycast and bodyOverlaps.
std::optional<RayHit> raycastEveryTriangle(const World& world, Vec3 origin, Vec3 direction,
                                           float maxDistance);
bool bodyOverlapsEveryTriangle(const World& world, BodyId body, const Aabb& box);

/// Vertices may have changed (a step, updateMesh, bodies added or removed): the geometric
/// queries' caches are stale.
inline void meshesChanged(QueryCache& cache) {
    ++cache.epoch;
}

} // namespace ffd::detail
