// Phase 2 of the Enhanced FFD-AABB pipeline: spatial hashing of boundary nodes.
//
// Reference: M. Teschner, B. Heidelberger, M. Mueller, D. Pomeranets, M. Gross, "Optimized
// Spatial Hashing for Collision Detection of Deformable Objects", VMV 2003. A point p falls in
// grid cell floor(p / l); cell (i,j,k) maps to bucket (i*73856093 xor j*19349663 xor
// k*83492791) mod T with T prime. Buckets carry a timestamp instead of being cleared, so a
// query costs nothing for the buckets a step does not touch. Each entry keeps its exact cell,
// so two cells sharing a bucket never mix and a box visiting both sees each node once.
#pragma once

#include "ffdaabb/math.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace ffd::detail {

/// Smallest prime >= n (n >= 2).
uint32_t nextPrime(uint32_t n);

class SpatialHash {
public:
    /// Starts a new step: a table of at least 2 * expectedEntries buckets (prime), cell size l.
    void begin(size_t expectedEntries, float cellSize);

    /// Inserts `item` at point p.
    void insert(uint32_t item, Vec3 p) {
        const int32_t i = cell(p.x), j = cell(p.y), k = cell(p.z);
        const uint32_t h = bucket(i, j, k);
        Bucket& b = buckets_[h];
        if (b.stamp != stamp_) b.stamp = stamp_, b.head = kNone;
        entries_.push_back({i, j, k, item, b.head});
        b.head = uint32_t(entries_.size() - 1);
    }

    /// Calls f(item) for every item inserted in grid cell (i,j,k) this step.
    template <class F>
    void forEachInCell(int32_t i, int32_t j, int32_t k, F&& f) const {
        const Bucket& b = buckets_[bucket(i, j, k)];
        if (b.stamp != stamp_) return;
        for (uint32_t e = b.head; e != kNone; e = entries_[e].next) {
            const Entry& en = entries_[e];
            if (en.i == i && en.j == j && en.k == k) f(en.item);
        }
    }

    int32_t cell(float v) const { return int32_t(std::floor(v * inverseCellSize_)); }
    float cellSize() const { return cellSize_; }
    size_t tableSize() const { return buckets_.size(); }
    size_t entryCount() const { return entries_.size(); }

private:
    static constexpr uint32_t kNone = UINT32_MAX;
    struct Bucket {
        uint32_t stamp = 0;
        uint32_t head = kNone;
    };
    struct Entry {
        int32_t i, j, k;
        uint32_t item;
        uint32_t next;
    };

    uint32_t bucket(int32_t i, int32_t j, int32_t k) const {
        const uint32_t h =
            (uint32_t(i) * 73856093u) ^ (uint32_t(j) * 19349663u) ^ (uint32_t(k) * 83492791u);
        return h % uint32_t(buckets_.size());
    }

    std::vector<Bucket> buckets_;
    std::vector<Entry> entries_;
    uint32_t stamp_ = 0;
    float cellSize_ = 1, inverseCellSize_ = 1;
};

} // namespace ffd::detail
