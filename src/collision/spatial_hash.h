// Phase 2 of the Enhanced FFD-AABB pipeline: spatial hashing of boundary nodes.
//
// Reference: M. Teschner, B. Heidelberger, M. Mueller, D. Pomeranets, M. Gross, "Optimized
// Spatial Hashing for Collision Detection of Deformable Objects", VMV 2003. A point p falls in
// grid cell floor(p / l); cell (i,j,k) maps to bucket cellKey(i,j,k) mod T with T prime: the
// hash of its block of 4 x 4 x 4 cells and its place in the block (the paper hashes each cell,
// its coordinates xor-ed, which mixed too little: cellHash). Buckets carry a
// timestamp instead of being cleared, so a step costs nothing for the buckets it does not
// touch.
//
// The table is filled in two passes (count, then place: a counting sort into the touched
// buckets), so each bucket's entries lie contiguous in memory and a query scans an array
// instead of chasing a linked list. Each entry keeps its exact cell and its owner, so two
// cells sharing a bucket never mix and a query can skip entries cheaply.
//
// Items may have a reach, one per owner (how far an object's nodes can travel in a substep):
// an item then stands for the cube of that half-width around its point, and a range query
// reports the items whose cubes meet its bounds. So a query's size depends on the querying box
// alone and an item's reach on its own owner alone, not on the fastest owner anywhere. Every
// query covers a fixed `allowance` of reach beyond its bounds; an item whose reach exceeds it
// is stored in every cell its cube shrunk by the allowance overlaps, and reported once, from
// the cell of the lowest corner of that shrunk cube's overlap with the query's cells.
#pragma once

#include "dynamics/simd4.h"
#include "ffdaabb/math.h"
#include "util/workers.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
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

    /// Starts a new step: a table of at least 2 * expectedEntries buckets (prime), cell size l;
    /// `ownerReach[o]` (>= 0) is the reach of owner o's items (none: 0 for all), `allowance`
    /// (>= 0) the reach every range query covers beyond its bounds.
    void begin(size_t expectedEntries, float cellSize, std::span<const float> ownerReach = {},
               float allowance = 0);

    /// An item whose cube would lie in more cells than this is kept apart, in a list that every
    /// query scans owner by owner (a body thrown at tens of metres per second would otherwise
    /// fill thousands of cells with each of its nodes).
    static constexpr int64_t kMaxCopies = 27;

    /// Items staged apart (on a thread of their own), then added in order by addBatches.
    struct Batch {
        std::vector<Entry> staged, wide;
    };

    /// Stages an item at point p, in each cell its owner's reach less the allowance reaches
    /// (one cell for most; the wide list past kMaxCopies); the table is built by build().
    void add(uint32_t item, uint32_t owner, Vec3 p) {
        if (owner >= reach_.size()) reach_.resize(owner + 1, 0.0f), extent_.resize(owner + 1, 0.0f);
        stage(staged_, wide_, item, owner, p);
    }

    /// add() into a batch, for owners that begin() was given the reach of; safe to call on
    /// several threads, each with its own batch.
    void add(Batch& batch, uint32_t item, uint32_t owner, Vec3 p) const {
        stage(batch.staged, batch.wide, item, owner, p);
    }

    /// Adds the batches' items, batch after batch, as add() would have in that order.
    void addBatches(std::span<const Batch> batches, Workers& workers);

private:
    void stage(std::vector<Entry>& staged, std::vector<Entry>& wide, uint32_t item, uint32_t owner,
               Vec3 p) const {
        const float e = extent_[owner];
        if (e == 0) {
            staged.push_back({cell(p.x), cell(p.y), cell(p.z), item, owner, p});
            return;
        }
        const int32_t i0 = cell(p.x - e), i1 = cell(p.x + e);
        const int32_t j0 = cell(p.y - e), j1 = cell(p.y + e);
        const int32_t k0 = cell(p.z - e), k1 = cell(p.z + e);
        if (int64_t(i1 - int64_t(i0) + 1) * (j1 - int64_t(j0) + 1) * (k1 - int64_t(k0) + 1) >
            kMaxCopies) {
            wide.push_back({0, 0, 0, item, owner, p});
            return;
        }
        for (int32_t k = k0; k <= k1; ++k)
            for (int32_t j = j0; j <= j1; ++j)
                for (int32_t i = i0; i <= i1; ++i) staged.push_back({i, j, k, item, owner, p});
    }

public:
    /// Grows the table to at least 2 * entries buckets (prime) if it has fewer (to fit the
    /// copies staged so far, say); before build().
    void reserveTable(size_t entries);
    size_t stagedCount() const { return staged_.size(); }

    /// Sorts the staged items into their buckets (two passes, timestamps, no clearing), on the
    /// workers' threads when given. Each bucket holds its items in the order they were added,
    /// whatever the thread count.
    void build(Workers* workers = nullptr);

    /// Whether the cube of half-width `reach` around p meets closed bounds `within`: the test
    /// of forEachNear, shared with callers that test without the table.
    static bool cubeMeets(Vec3 p, float reach, const Aabb& within) {
        return p.x + reach >= within.lo.x && p.x - reach <= within.hi.x &&
               p.y + reach >= within.lo.y && p.y - reach <= within.hi.y &&
               p.z + reach >= within.lo.z && p.z - reach <= within.hi.z;
    }

    /// Calls f(entry) once for each item whose owner is not `skipOwner` and whose cube (its
    /// owner's reach) meets `within` (cubeMeets). Scans the wide items of the owners whose
    /// cubes' bounds meet `within`, then visits the cells of `within` grown by the allowance
    /// (and a little more than rounding can shift a bound).
    template <class F>
    void forEachNear(const Aabb& within, uint32_t skipOwner, F&& f) const {
        const Aabb range = padded(within);
        const int32_t r[6] = {cell(range.lo.x), cell(range.hi.x), cell(range.lo.y),
                              cell(range.hi.y), cell(range.lo.z), cell(range.hi.z)};
        forEachWide(within, skipOwner, f);
        forEachInBox(within, r, skipOwner, f);
    }

    /// What forEachNearAll keeps between calls (one per thread).
    struct GroupScratch {
        std::vector<int32_t> range;      ///< per query: i0, i1, j0, j1, k0, k1 of its cells
        std::vector<uint32_t> cellStart; ///< per cell of the group's block: its queries (CSR)
        std::vector<uint32_t> cellQueries;
        /// The block's cells with any query, in order: coordinates and index in the block.
        struct LiveCell {
            int32_t i, j, k;
            uint32_t cell;
        };
        std::vector<LiveCell> live;
    };

    /// The largest block of cells forEachNearAll groups its queries in; past it, it queries them
    /// one by one.
    static constexpr int64_t kMaxGroupCells = 1 << 15;

    /// forEachNear(within[q], skipOwner, ...) for every q, calling f(q, entry) for each item
    /// reported, the same (q, entry) pairs, in another order: each cell that several queries
    /// visit (neighbouring boxes of one body overlap) is looked up and its entries read once
    /// for all of them, query after query while they stay in the cache.
    ///
    /// `reach` (>= 0), when less than the allowance: the largest reach of the owners whose items
    /// the caller wants; the cells visited are then those of `within` grown by it alone, which
    /// hold every such item whose cube meets `within` (stored in its own cell only). Items of
    /// other owners may then be missed.
    template <class F>
    void forEachNearAll(std::span<const Aabb> within, uint32_t skipOwner, GroupScratch& g, F&& f,
                        float reach = INFINITY) const {
        const size_t queries = within.size();
        if (queries == 0) return;
        const float pad = std::min(reach, allowance_);
        g.range.resize(queries * 6);
        int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX},
                hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
        for (size_t q = 0; q < queries; ++q) {
            const Aabb range = padded(within[q], pad);
            int32_t* r = &g.range[q * 6];
            for (int a = 0; a < 3; ++a) {
                r[2 * a] = cell(range.lo[a]), r[2 * a + 1] = cell(range.hi[a]);
                lo[a] = std::min(lo[a], r[2 * a]), hi[a] = std::max(hi[a], r[2 * a + 1]);
            }
            forEachWide(within[q], skipOwner, [&](const Entry& e) { f(uint32_t(q), e); });
        }
        const int64_t ni = int64_t(hi[0]) - lo[0] + 1, nj = int64_t(hi[1]) - lo[1] + 1,
                      nk = int64_t(hi[2]) - lo[2] + 1;
        if (ni * nj * nk > kMaxGroupCells) {
            for (size_t q = 0; q < queries; ++q)
                forEachInBox(within[q], &g.range[q * 6], skipOwner,
                             [&](const Entry& e) { f(uint32_t(q), e); });
            return;
        }
        // The queries of each cell of the block, by counting sort (CSR), in query order.
        const size_t cells = size_t(ni * nj * nk);
        auto at = [&](int32_t i, int32_t j, int32_t k) {
            return size_t((int64_t(k - lo[2]) * nj + (j - lo[1])) * ni + (i - lo[0]));
        };
        g.cellStart.assign(cells + 1, 0);
        auto forCells = [&](const int32_t* r, auto&& fn) {
            for (int32_t k = r[4]; k <= r[5]; ++k)
                for (int32_t j = r[2]; j <= r[3]; ++j)
                    for (int32_t i = r[0]; i <= r[1]; ++i) fn(at(i, j, k));
        };
        for (size_t q = 0; q < queries; ++q)
            forCells(&g.range[q * 6], [&](size_t c) { ++g.cellStart[c + 1]; });
        g.live.clear();
        size_t place = 0; // at(i, j, k), counted along
        for (int32_t k = lo[2]; k <= hi[2]; ++k)
            for (int32_t j = lo[1]; j <= hi[1]; ++j)
                for (int32_t i = lo[0]; i <= hi[0]; ++i, ++place) {
                    if (g.cellStart[place + 1]) g.live.push_back({i, j, k, uint32_t(place)});
                    g.cellStart[place + 1] += g.cellStart[place];
                }
        g.cellQueries.resize(g.cellStart[cells]);
        for (size_t q = 0; q < queries; ++q)
            forCells(&g.range[q * 6],
                     [&](size_t c) { g.cellQueries[g.cellStart[c]++] = uint32_t(q); });
        for (size_t c = cells; c > 0; --c) g.cellStart[c] = g.cellStart[c - 1];
        g.cellStart[0] = 0;
        // The block's live cells, each scanned once for all the queries that visit it.
        forEachLiveCell(
            skipOwner,
            [&](auto&& emit) {
                for (const GroupScratch::LiveCell& c : g.live) emit(c.i, c.j, c.k, c.cell);
            },
            [&](const int32_t* c, size_t cell, uint32_t first, uint32_t end) {
                for (uint32_t k = g.cellStart[cell]; k < g.cellStart[cell + 1]; ++k) {
                    const uint32_t q = g.cellQueries[k];
                    scanCell(c, first, end, within[q], &g.range[q * 6], skipOwner,
                             [&](const Entry& e) { f(q, e); });
                }
            });
    }

    /// Calls f(entry) for every item in grid cell (i,j,k) whose owner is not `skipOwner`. That
    /// owner's run at either end of the bucket is passed over without reading it (Bucket).
    template <class F>
    void forEachInCell(int32_t i, int32_t j, int32_t k, uint32_t skipOwner, F&& f) const {
        const Bucket& b = buckets_[bucket(i, j, k)];
        if (b.stamp != stamp_) return;
        uint32_t first, end;
        b.unskipped(skipOwner, first, end);
        for (uint32_t n = first; n < end; ++n) {
            const Entry& e = entries_[n];
            if (e.owner != skipOwner && e.i == i && e.j == j && e.k == k) f(e);
        }
    }

    static constexpr uint32_t kNoOwner = UINT32_MAX;

    /// The hash of cell (i, j, k): each coordinate times an odd 64-bit constant, xor-ed, then
    /// one multiply-xorshift round (splitmix64's finaliser) so that every bit of the three
    /// reaches the low 32. Teschner et al.'s i·73856093 ⊕ j·19349663 ⊕ k·83492791 sent a
    /// third of the entries a dense pile's queries scan to buckets shared with other cells
    /// (docs/ALGORITHM.md §4, phase 2).
    static uint32_t cellHash(int32_t i, int32_t j, int32_t k) {
        uint64_t x = (uint64_t(uint32_t(i)) * 0x9E3779B97F4A7C15ull) ^
                     (uint64_t(uint32_t(j)) * 0xC2B2AE3D27D4EB4Full) ^
                     (uint64_t(uint32_t(k)) * 0x165667B19E3779F9ull);
        x ^= x >> 29;
        x *= 0xBF58476D1CE4E5B9ull;
        x ^= x >> 32;
        return uint32_t(x);
    }

    /// What a cell's bucket is taken from: the hash of its block of 4 x 4 x 4 cells (cellHash
    /// of its coordinates divided by 4) times 64, plus the cell's place in the block in Morton
    /// order. A block's cells land in 64 consecutive buckets, so the cells around a box share
    /// cache lines and the blocks of neighbouring boxes are read again while cached, where
    /// each cell's bucket at random made every cell a read from memory once the table outgrew
    /// the cache; the blocks land at random, so the buckets fill as random keys would.
    static uint32_t cellKey(int32_t i, int32_t j, int32_t k) {
        const uint32_t a = uint32_t(i), b = uint32_t(j), c = uint32_t(k);
        const uint32_t place =
            (a & 1) | (b & 1) << 1 | (c & 1) << 2 | (a & 2) << 2 | (b & 2) << 3 | (c & 2) << 4;
        return cellHash(i >> 2, j >> 2, k >> 2) << 6 | place;
    }

    int32_t cell(float v) const { return int32_t(std::floor(v * inverseCellSize_)); }
    float cellSize() const { return cellSize_; }
    size_t tableSize() const { return buckets_.size(); }
    size_t entryCount() const { return entries_.size(); }
    size_t wideCount() const { return wide_.size(); } ///< items kept apart (kMaxCopies)

private:
    /// A bucket's entries, and the runs of one owner at its head and its tail (in the order
    /// added): a query skips the querying owner's run unread, which is the whole bucket for most
    /// cells a box visits (its own object's nodes) and one end of it for most of the rest (the
    /// owners added in order).
    struct Bucket {
        uint32_t stamp = 0;
        uint32_t start = 0;
        uint32_t count = 0;
        uint32_t headOwner = kNoOwner, headRun = 0;
        uint32_t tailOwner = kNoOwner, tailRun = 0;
        /// Empties the bucket for step `now`; its first entry will be `owner`'s.
        void open(uint32_t now, uint32_t owner) {
            stamp = now;
            count = headRun = tailRun = 0;
            headOwner = tailOwner = owner;
        }
        /// Counts one more entry, of `owner`, at the tail.
        void push(uint32_t owner) {
            if (owner == tailOwner) {
                if (headRun == count) ++headRun;
                ++tailRun;
            } else {
                tailOwner = owner;
                tailRun = 1;
            }
            ++count;
        }
        /// The entries [first, end) left when the runs of `skip` at either end are taken off
        /// (end <= first: none).
        void unskipped(uint32_t skip, uint32_t& first, uint32_t& end) const {
            first = start + (headOwner == skip ? headRun : 0);
            end = start + count - (tailOwner == skip ? tailRun : 0);
        }
    };

    /// `within` grown by the allowance and a few float roundings of its coordinates, so that a
    /// cube meeting `within` always has its shrunk cube overlap the cells of the result.
    Aabb padded(const Aabb& within) const { return padded(within, allowance_); }
    /// The same, grown by `allowance` (at most the table's) instead.
    Aabb padded(const Aabb& within, float allowance) const {
        auto pad = [&](float v) { return allowance > 0 ? allowance + 1e-6f * std::abs(v) : 0; };
        return {within.lo - Vec3{pad(within.lo.x), pad(within.lo.y), pad(within.lo.z)},
                within.hi + Vec3{pad(within.hi.x), pad(within.hi.y), pad(within.hi.z)}};
    }

    /// Whether a query over cells r (i0, i1, j0, j1, k0, k1) reports entry e from e's cell: an
    /// item stored in several cells is reported from the first cell of its shrunk cube's
    /// overlap with the query's cells along each axis.
    bool reportsFrom(const Entry& e, const int32_t* r) const {
        const float x = extent_[e.owner];
        return !(x > 0) || (std::max(cell(e.position.x - x), r[0]) == e.i &&
                            std::max(cell(e.position.y - x), r[2]) == e.j &&
                            std::max(cell(e.position.z - x), r[4]) == e.k);
    }

    /// The wide items (kept apart) of owners other than `skipOwner` whose cubes meet `within`:
    /// each owner's run is passed over when its cubes' bounds miss `within`.
    template <class F>
    void forEachWide(const Aabb& within, uint32_t skipOwner, F&& f) const {
        for (const WideRun& run : wideRuns_) {
            if (run.owner == skipOwner || !run.bounds.overlaps(within)) continue;
            for (uint32_t n = run.start; n < run.end; ++n)
                if (cubeMeets(wide_[n].position, reach_[run.owner], within)) f(wide_[n]);
        }
    }

    /// The entries [first, end) of the bucket of cell c that a query over cells r (i0, i1, j0,
    /// j1, k0, k1) with bounds `within` reports: in cell c (not another cell sharing the
    /// bucket), of an owner other than `skipOwner`, their cubes meeting `within`, and reported
    /// from this cell (reportsFrom). Each entry's stored position is checked before anything
    /// else of it is read.
    template <class F>
    void scanCell(const int32_t* c, uint32_t first, uint32_t end, const Aabb& within,
                  const int32_t* r, uint32_t skipOwner, F&& f) const {
        scanProbes(first, end, within, [&](uint32_t n) {
            const Entry& e = entries_[n];
            if (e.owner != skipOwner && e.i == c[0] && e.j == c[1] && e.k == c[2] &&
                reportsFrom(e, r))
                f(e);
        });
    }

    /// For each cell that `cells` names (cells(emit) calls emit(i, j, k, tag) for each, in
    /// order) whose bucket holds entries of owners other than `skipOwner` at its ends,
    /// visit(cell coordinates, tag, first, end) with the bucket's entries left when that owner's
    /// runs are taken off. The cells go in batches: their buckets looked up (and prefetched)
    /// before any is read, then the probes and entries of those that matter, so their cache
    /// misses overlap instead of queueing.
    template <class Cells, class Visit>
    void forEachLiveCell(uint32_t skipOwner, Cells&& cells, Visit&& visit) const {
        constexpr int kBatch = 32;
        uint32_t hs[kBatch];
        int32_t cs[kBatch][3];
        size_t tags[kBatch];
        int n = 0;
        uint32_t liveFirst[kBatch], liveEnd[kBatch];
        int liveCell[kBatch];
        auto flush = [&] {
            int lives = 0;
            for (int m = 0; m < n; ++m) {
                const Bucket& b = buckets_[hs[m]];
                if (b.stamp != stamp_) continue;
                uint32_t first, end;
                b.unskipped(skipOwner, first, end);
                if (end <= first) continue;
                // The range's probes and entries, the first line of each or, in a table that
                // outgrows the cache, up to kPrefetchRun entries' lines.
                const uint32_t last = std::min(end, first + prefetchRun_);
                for (uint32_t e = first; e < last; e += 4) __builtin_prefetch(probes_.data() + e);
                for (uint32_t e = first; e < last; e += 2) __builtin_prefetch(entries_.data() + e);
                liveFirst[lives] = first;
                liveEnd[lives] = end;
                liveCell[lives++] = m;
            }
            for (int l = 0; l < lives; ++l)
                visit(cs[liveCell[l]], tags[liveCell[l]], liveFirst[l], liveEnd[l]);
            n = 0;
        };
        cells([&](int32_t i, int32_t j, int32_t k, size_t tag) {
            hs[n] = bucket(i, j, k);
            __builtin_prefetch(&buckets_[hs[n]]);
            cs[n][0] = i, cs[n][1] = j, cs[n][2] = k;
            tags[n] = tag;
            if (++n == kBatch) flush();
        });
        flush();
    }

    /// forEachNear's table part: the entries of cells r (i0, i1, j0, j1, k0, k1) whose cubes
    /// meet `within`, each once, the cells in batches (forEachLiveCell).
    template <class F>
    void forEachInBox(const Aabb& within, const int32_t* r, uint32_t skipOwner, F&& f) const {
        forEachLiveCell(
            skipOwner,
            [&](auto&& emit) {
                for (int32_t k = r[4]; k <= r[5]; ++k)
                    for (int32_t j = r[2]; j <= r[3]; ++j)
                        for (int32_t i = r[0]; i <= r[1]; ++i) emit(i, j, k, 0);
            },
            [&](const int32_t* c, size_t, uint32_t first, uint32_t end) {
                scanCell(c, first, end, within, r, skipOwner, f);
            });
    }

    uint32_t bucket(int32_t i, int32_t j, int32_t k) const {
        return fastMod(cellKey(i, j, k), modMagic_, tableSize_);
    }

    /// An entry's position and its owner's reach, beside entries_ (the same index): what a
    /// range query reads of every entry it scans, half an entry's bytes.
    struct alignas(16) Probe {
        float x, y, z, reach;
    };
    /// Probes past the last entry, so that a scan reads four at a time (scanProbes).
    static constexpr size_t kProbePadding = 3;

    /// Calls g(n) for each entry n of [first, end), in order, whose probe's cube meets `within`
    /// (cubeMeets: the same sums and comparisons), four probes at a time.
    template <class G>
    void scanProbes(uint32_t first, uint32_t end, const Aabb& within, G&& g) const {
        const F4 lx = splat(within.lo.x), ly = splat(within.lo.y), lz = splat(within.lo.z);
        const F4 hx = splat(within.hi.x), hy = splat(within.hi.y), hz = splat(within.hi.z);
        for (uint32_t n = first; n < end; n += 4) {
            F4 x = load4(&probes_[n].x), y = load4(&probes_[n + 1].x), z = load4(&probes_[n + 2].x),
               r = load4(&probes_[n + 3].x);
            transpose(x, y, z, r); // each now one coordinate (or the reach) of the four probes
            const I4 in = (x + r >= lx) & (x - r <= hx) & (y + r >= ly) & (y - r <= hy) &
                          (z + r >= lz) & (z - r <= hz);
            uint32_t mask = uint32_t((in[0] & 1) | (in[1] & 2) | (in[2] & 4) | (in[3] & 8));
            if (end - n < 4) mask &= (1u << (end - n)) - 1;
            while (mask) {
                g(n + uint32_t(__builtin_ctz(mask)));
                mask &= mask - 1;
            }
        }
    }

    std::vector<Bucket> buckets_;
    std::vector<Entry> staged_, entries_;
    std::vector<Probe> probes_;
    /// Items past kMaxCopies cells, and their runs of one owner with the bounds of its cubes.
    struct WideRun {
        uint32_t owner, start, end;
        Aabb bounds;
    };
    std::vector<Entry> wide_;
    std::vector<WideRun> wideRuns_;
    std::vector<uint32_t> slotOf_, bucketOf_;
    std::vector<std::vector<uint32_t>> touchedBy_; ///< per part of the table, its touched buckets
    /// With several parts, per range of entries r and part of the table p (r * parts + p), the
    /// range's entries whose bucket lies in the part, in order.
    std::vector<std::vector<uint32_t>> inPart_;
    /// Per owner of a staged item: its reach, and what of it the item's cells cover (the reach
    /// less the allowance).
    std::vector<float> reach_, extent_;
    float allowance_ = 0;
    /// How many of a scanned range's entries forEachLiveCell prefetches: 1 (one line of probes
    /// and one of entries), or kPrefetchRun when the table holds kPrefetchRunsFrom entries or
    /// more (build). Measured interleaved frame by frame: alphabets_x10 (about 485,000 entries,
    /// 23 MB of entries and probes) took 0.967-0.973 of its object_contacts time with 16 or 32,
    /// 0.983 with 8 and 0.975 with a whole range; the spheres (about 20,000) 1.005-1.008 with 32,
    /// the alphabets (40,000-60,000) 0.987 and 1.003.
    static constexpr uint32_t kPrefetchRun = 32;
    static constexpr size_t kPrefetchRunsFrom = size_t(1) << 18;
    uint32_t prefetchRun_ = 1;
    uint32_t stamp_ = 0;
    uint64_t modMagic_ = 0;  ///< ceil(2^64 / T)
    uint32_t tableSize_ = 1; ///< T
    float cellSize_ = 1, inverseCellSize_ = 1;
};

} // namespace ffd::detail
