// Phase 2 of the Enhanced FFD-AABB pipeline: spatial hashing of boundary nodes.
//
// Reference: M. Teschner, B. Heidelberger, M. Mueller, D. Pomeranets, M. Gross, "Optimized
// Spatial Hashing for Collision Detection of Deformable Objects", VMV 2003. A point p falls in
// grid cell floor(p / l); cell (i,j,k) maps to bucket (i*73856093 xor j*19349663 xor
// k*83492791) mod T with T prime. Buckets carry a timestamp instead of being cleared, so a
// step costs nothing for the buckets it does not touch.
//
// The table is filled in two passes (count, then place: a counting sort into the touched
// buckets), so each bucket's entries lie contiguous in memory and a query scans an array
// instead of chasing a linked list. Each entry keeps its exact cell and its owner, so two
// cells sharing a bucket never mix and a query can skip entries cheaply.
#pragma once

#include "ffdaabb/math.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace ffd::detail {

/// Smallest prime >= n (n >= 2).
uint32_t nextPrime(uint32_t n);

__extension__ using Uint128 = unsigned __int128;

/// The magic number of fastMod for divisor t (t >= 1).
constexpr uint64_t fastModMagic(uint32_t t) {
    return ~uint64_t(0) / t + 1;
}

/// h mod t without a division, given magic = fastModMagic(t) (Lemire, Kaser, Kurz, "Faster
/// Remainder by Direct Computation", 2019): exact for every 32-bit h and t.
constexpr uint32_t fastMod(uint32_t h, uint64_t magic, uint32_t t) {
    return uint32_t((Uint128(magic * h) * t) >> 64);
}

class SpatialHash {
public:
    struct Entry {
        int32_t i, j, k;
        uint32_t item;  ///< caller's id (a node index)
        uint32_t owner; ///< caller's group (a body index)
        Vec3 position;  ///< where it was added (read with the entry, not from elsewhere)
    };

    /// Starts a new step: a table of at least 2 * expectedEntries buckets (prime), cell size l.
    void begin(size_t expectedEntries, float cellSize);

    /// Stages an item at point p; the table is built by build().
    void add(uint32_t item, uint32_t owner, Vec3 p) {
        staged_.push_back({cell(p.x), cell(p.y), cell(p.z), item, owner, p});
    }

    /// Sorts the staged items into their buckets (two passes, timestamps, no clearing).
    void build();

    /// Calls f(entry) for every item in grid cell (i,j,k) whose owner is not `skipOwner`. A
    /// bucket holding only that owner's items is passed over without reading them (most cells
    /// a box visits hold only its own object's nodes).
    template <class F>
    void forEachInCell(int32_t i, int32_t j, int32_t k, uint32_t skipOwner, F&& f) const {
        const Bucket& b = buckets_[bucket(i, j, k)];
        if (b.stamp != stamp_ || b.soleOwner == skipOwner) return;
        const Entry* e = entries_.data() + b.start;
        for (uint32_t n = 0; n < b.count; ++n)
            if (e[n].owner != skipOwner && e[n].i == i && e[n].j == j && e[n].k == k) f(e[n]);
    }

    static constexpr uint32_t kNoOwner = UINT32_MAX;

    /// forEachInCell over every cell of a range, for the items whose position lies in `within`
    /// (closed bounds). The buckets are looked up (and prefetched) before any is read, then
    /// the entries of those that matter, so their cache misses overlap instead of queueing;
    /// each entry's stored position is checked before anything else of it is read.
    template <class F>
    void forEachInRange(int32_t i0, int32_t i1, int32_t j0, int32_t j1, int32_t k0, int32_t k1,
                        uint32_t skipOwner, const Aabb& within, F&& f) const {
        constexpr int kBatch = 32;
        uint32_t hs[kBatch];
        int32_t cs[kBatch][3];
        int n = 0;
        const Bucket* live[kBatch];
        int liveCell[kBatch];
        auto flush = [&] {
            // Second level: the buckets that hold anything of interest, their entries
            // prefetched before the first is scanned.
            int lives = 0;
            for (int m = 0; m < n; ++m) {
                const Bucket& b = buckets_[hs[m]];
                if (b.stamp != stamp_ || b.soleOwner == skipOwner) continue;
                __builtin_prefetch(entries_.data() + b.start);
                live[lives] = &b;
                liveCell[lives++] = m;
            }
            for (int l = 0; l < lives; ++l) {
                const Bucket& b = *live[l];
                const int32_t* c = cs[liveCell[l]];
                const Entry* e = entries_.data() + b.start;
                for (uint32_t q = 0; q < b.count; ++q) {
                    const Vec3 p = e[q].position;
                    if (!(p.x >= within.lo.x && p.x <= within.hi.x && p.y >= within.lo.y &&
                          p.y <= within.hi.y && p.z >= within.lo.z && p.z <= within.hi.z))
                        continue;
                    if (e[q].owner != skipOwner && e[q].i == c[0] && e[q].j == c[1] &&
                        e[q].k == c[2])
                        f(e[q]);
                }
            }
            n = 0;
        };
        for (int32_t k = k0; k <= k1; ++k)
            for (int32_t j = j0; j <= j1; ++j)
                for (int32_t i = i0; i <= i1; ++i) {
                    hs[n] = bucket(i, j, k);
                    __builtin_prefetch(&buckets_[hs[n]]);
                    cs[n][0] = i, cs[n][1] = j, cs[n][2] = k;
                    if (++n == kBatch) flush();
                }
        flush();
    }

    int32_t cell(float v) const { return int32_t(std::floor(v * inverseCellSize_)); }
    float cellSize() const { return cellSize_; }
    size_t tableSize() const { return buckets_.size(); }
    size_t entryCount() const { return entries_.size(); }

private:
    struct Bucket {
        uint32_t stamp = 0;
        uint32_t start = 0;
        uint32_t count = 0;
        uint32_t soleOwner = kMixed; ///< the one owner of all its items, or kMixed
    };
    static constexpr uint32_t kMixed = UINT32_MAX - 1;

    uint32_t bucket(int32_t i, int32_t j, int32_t k) const {
        const uint32_t h =
            (uint32_t(i) * 73856093u) ^ (uint32_t(j) * 19349663u) ^ (uint32_t(k) * 83492791u);
        return fastMod(h, modMagic_, tableSize_);
    }

    std::vector<Bucket> buckets_;
    std::vector<Entry> staged_, entries_;
    std::vector<uint32_t> touched_, slotOf_, bucketOf_;
    uint32_t stamp_ = 0;
    uint64_t modMagic_ = 0;  ///< ceil(2^64 / T)
    uint32_t tableSize_ = 1; ///< T
    float cellSize_ = 1, inverseCellSize_ = 1;
};

} // namespace ffd::detail
