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

void SpatialHash::begin(size_t expectedEntries, float cellSize, std::span<const float> ownerReach,
                        float allowance) {
    cellSize_ = cellSize;
    inverseCellSize_ = 1.0f / cellSize;
    allowance_ = allowance;
    reach_.assign(ownerReach.begin(), ownerReach.end());
    extent_.resize(reach_.size());
    for (size_t o = 0; o < reach_.size(); ++o)
        extent_[o] = reach_[o] > allowance ? reach_[o] - allowance : 0.0f;
    staged_.clear();
    staged_.reserve(expectedEntries);
    wide_.clear();
    reserveTable(expectedEntries);
    if (++stamp_ == 0) { // wrapped after 2^32 steps: clear once
        for (Bucket& b : buckets_) b.stamp = 0;
        stamp_ = 1;
    }
}

void SpatialHash::reserveTable(size_t entries) {
    // Load factor 1/2: measured best against 1/4, 1 and 2 on the paper's scenes.
    const size_t wanted = 2 * entries + 1;
    if (buckets_.size() < wanted) {
        // Grow (never shrink, so the steady state reuses the table); fresh buckets carry stamp 0.
        buckets_.assign(nextPrime(uint32_t(wanted)), Bucket{});
        tableSize_ = uint32_t(buckets_.size());
        modMagic_ = fastModMagic(tableSize_);
        stamp_ = 1; // nothing in the fresh table is current
    }
}

void SpatialHash::build() {
    // The wide items' runs of one owner, each with the bounds of its items' cubes.
    wideRuns_.clear();
    for (uint32_t n = 0; n < wide_.size(); ++n) {
        const Entry& e = wide_[n];
        if (wideRuns_.empty() || wideRuns_.back().owner != e.owner)
            wideRuns_.push_back({e.owner, n, n, Aabb{}});
        WideRun& run = wideRuns_.back();
        const float r = reach_[e.owner];
        run.bounds.add(e.position - Vec3{r, r, r});
        run.bounds.add(e.position + Vec3{r, r, r});
        run.end = n + 1;
    }
    // Pass 1: count per bucket; a bucket whose stamp is old is empty (no clearing needed).
    touched_.clear();
    slotOf_.resize(staged_.size());
    bucketOf_.resize(staged_.size());
    for (size_t n = 0; n < staged_.size(); ++n) {
        const Entry& e = staged_[n];
        const uint32_t h = bucket(e.i, e.j, e.k);
        bucketOf_[n] = h;
        Bucket& b = buckets_[h];
        if (b.stamp != stamp_) {
            b.stamp = stamp_;
            b.count = 0;
            b.soleOwner = e.owner;
            touched_.push_back(h);
        } else if (b.soleOwner != e.owner) {
            b.soleOwner = kMixed;
        }
        slotOf_[n] = b.count++;
    }
    // Offsets over the touched buckets only, in the order they were first touched.
    uint32_t offset = 0;
    for (uint32_t h : touched_) {
        buckets_[h].start = offset;
        offset += buckets_[h].count;
    }
    // Pass 2: place, keeping insertion order within each bucket (deterministic).
    entries_.resize(staged_.size());
    for (size_t n = 0; n < staged_.size(); ++n)
        entries_[buckets_[bucketOf_[n]].start + slotOf_[n]] = staged_[n];
}

} // namespace ffd::detail
