// Reference: Teschner et al., "Optimized Spatial Hashing for Collision Detection of Deformable
// Objects", VMV 2003.
#include "collision/spatial_hash.h"

#include <algorithm>

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
        // By half again at least: a pile that forms adds entries substep after substep, and
        // growing to each new count rebuilt the table 73 times in the alphabets' 360 frames.
        const size_t grown = std::max(wanted, buckets_.size() + buckets_.size() / 2);
        buckets_.assign(nextPrime(uint32_t(grown)), Bucket{});
        tableSize_ = uint32_t(buckets_.size());
        modMagic_ = fastModMagic(tableSize_);
        stamp_ = 1; // nothing in the fresh table is current
    }
}

void SpatialHash::addBatches(std::span<const Batch> batches, Workers& workers) {
    std::vector<size_t> at(batches.size() + 1, staged_.size());
    for (size_t b = 0; b < batches.size(); ++b) {
        at[b + 1] = at[b] + batches[b].staged.size();
        wide_.insert(wide_.end(), batches[b].wide.begin(), batches[b].wide.end());
    }
    staged_.resize(at.back());
    workers.forChunks(batches.size(), 1, [&](size_t b, size_t, int) {
        std::copy(batches[b].staged.begin(), batches[b].staged.end(),
                  staged_.begin() + ptrdiff_t(at[b]));
    });
}

// How many entries ahead the build's passes prefetch the bucket they will touch: the buckets lie
// at random in a table larger than the cache.
constexpr size_t kPrefetchAhead = 16;

void SpatialHash::build(Workers* workers) {
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
    // The buckets split in `parts` ranges, one per thread: each part takes the entries of its
    // buckets in staged order, so a bucket's entries keep their staged order whatever the
    // split, and no two threads touch one bucket. The layout of the buckets in memory depends on
    // the split, what each bucket holds does not.
    const size_t parts = workers ? size_t(workers->count()) : 1;
    bucketOf_.resize(staged_.size());
    slotOf_.resize(staged_.size());
    touchedBy_.resize(parts);
    const uint32_t perPart = uint32_t((uint64_t(tableSize_) + parts - 1) / parts);
    auto forParts = [&](auto&& fn) {
        if (parts == 1) return fn(size_t(0));
        workers->forChunks(parts, 1, [&](size_t part, size_t, int) { fn(part); });
    };
    // Each range of entries its buckets, and with several parts, its entries sorted by part
    // (in order): a part then visits its own entries alone, where scanning every entry and
    // skipping the others' mispredicted a branch per entry.
    if (parts > 1) inPart_.resize(parts * parts);
    forParts([&](size_t range) {
        const size_t n0 = staged_.size() * range / parts, n1 = staged_.size() * (range + 1) / parts;
        if (parts > 1)
            for (size_t p = 0; p < parts; ++p) inPart_[range * parts + p].clear();
        for (size_t n = n0; n < n1; ++n) {
            const Entry& e = staged_[n];
            bucketOf_[n] = bucket(e.i, e.j, e.k);
            if (parts > 1) inPart_[range * parts + bucketOf_[n] / perPart].push_back(uint32_t(n));
        }
    });
    // Pass 1: count per bucket; a bucket whose stamp is old is empty (no clearing needed).
    // Part p's entries in staged order: range by range, each range's in order.
    auto count = [&](size_t n, std::vector<uint32_t>& touched) {
        const Entry& e = staged_[n];
        Bucket& b = buckets_[bucketOf_[n]];
        if (b.stamp != stamp_) {
            b.open(stamp_, e.owner);
            touched.push_back(bucketOf_[n]);
        }
        slotOf_[n] = b.count;
        b.push(e.owner);
    };
    forParts([&](size_t part) {
        std::vector<uint32_t>& touched = touchedBy_[part];
        touched.clear();
        if (parts == 1) {
            for (size_t n = 0; n < staged_.size(); ++n) {
                if (n + kPrefetchAhead < staged_.size())
                    __builtin_prefetch(&buckets_[bucketOf_[n + kPrefetchAhead]]);
                count(n, touched);
            }
            return;
        }
        for (size_t range = 0; range < parts; ++range) {
            const std::vector<uint32_t>& mine = inPart_[range * parts + part];
            for (size_t m = 0; m < mine.size(); ++m) {
                if (m + kPrefetchAhead < mine.size())
                    __builtin_prefetch(&buckets_[bucketOf_[mine[m + kPrefetchAhead]]]);
                count(mine[m], touched);
            }
        }
    });
    // Offsets over the touched buckets only, part by part, in the order first touched.
    uint32_t offset = 0;
    for (const std::vector<uint32_t>& touched : touchedBy_)
        for (size_t t = 0; t < touched.size(); ++t) {
            if (t + kPrefetchAhead < touched.size())
                __builtin_prefetch(&buckets_[touched[t + kPrefetchAhead]]);
            Bucket& b = buckets_[touched[t]];
            b.start = offset;
            offset += b.count;
        }
    // Pass 2: place, keeping the staged order within each bucket.
    entries_.resize(staged_.size());
    probes_.resize(staged_.size() + kProbePadding);
    forParts([&](size_t part) {
        const size_t n0 = staged_.size() * part / parts, n1 = staged_.size() * (part + 1) / parts;
        for (size_t n = n0; n < n1; ++n) {
            if (n + kPrefetchAhead < n1)
                __builtin_prefetch(&buckets_[bucketOf_[n + kPrefetchAhead]]);
            const Entry& e = staged_[n];
            const uint32_t at = buckets_[bucketOf_[n]].start + slotOf_[n];
            entries_[at] = e;
            probes_[at] = {e.position.x, e.position.y, e.position.z, reach_[e.owner]};
        }
    });
    prefetchRun_ = entries_.size() >= kPrefetchRunsFrom ? kPrefetchRun : 1;
}

} // namespace ffd::detail
