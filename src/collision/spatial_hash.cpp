// Reference: Teschner et al., "Optimized Spatial Hashing for Collision Detection of Deformable
// Objects", VMV 2003.
#include "collision/spatial_hash.h"

namespace ffd::detail {

uint32_t nextPrime(uint32_t n) {
    if (n <= 2) return 2;
    for (uint32_t c = n | 1u;; c += 2) {
        bool prime = true;
        for (uint32_t d = 3; uint64_t(d) * d <= c; d += 2)
            if (c % d == 0) {
                prime = false;
                break;
            }
        if (prime) return c;
    }
}

void SpatialHash::begin(size_t expectedEntries, float cellSize) {
    cellSize_ = cellSize;
    inverseCellSize_ = 1.0f / cellSize;
    entries_.clear();
    entries_.reserve(expectedEntries);
    const size_t wanted = 2 * expectedEntries + 1;
    if (buckets_.size() < wanted) {
        // Grow (never shrink, so steady state reuses the table); fresh buckets carry stamp 0.
        buckets_.assign(nextPrime(uint32_t(wanted)), Bucket{});
        stamp_ = 0;
    }
    if (++stamp_ == 0) { // wrapped after 2^32 steps: clear once
        for (Bucket& b : buckets_) b.stamp = 0;
        stamp_ = 1;
    }
}

} // namespace ffd::detail
