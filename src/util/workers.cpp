#include "util/workers.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <thread>

namespace ffd::detail {

// The world's own threads: a TBB arena, or under ThreadSanitizer (FFD_OWN_THREAD_POOL) the
// library's ThreadPool, whose synchronisation the sanitizer sees (Debian's TBB is not built
// for it).
struct Workers::Arena {
#ifdef FFD_OWN_THREAD_POOL
    explicit Arena(int threads) : pool(threads) {}
    int concurrency() const {
        return pool.slotCount();
    }
    ThreadPool pool;
#else
    explicit Arena(int threads) : arena(threads) {}
    int concurrency() const {
        return arena.max_concurrency();
    }
    tbb::task_arena arena;
#endif
};

int resolveThreads(int threads) {
    return threads == 0 ? int(std::max(1u, std::thread::hardware_concurrency())) : threads;
}

Workers::Workers() = default;
Workers::~Workers() = default;
Workers::Workers(Workers&&) noexcept = default;
Workers& Workers::operator=(Workers&&) noexcept = default;

void Workers::setThreads(int threads) {
    count_ = std::max(resolveThreads(threads), 1);
    if (count_ == 1 || (arena_ && arena_->concurrency() != count_)) arena_.reset();
}

void Workers::setTaskSystem(std::shared_ptr<TaskSystem> tasks) {
    tasks_ = std::move(tasks);
}

namespace {

#ifndef FFD_OWN_THREAD_POOL
int slotHere() {
    const int slot = tbb::this_task_arena::current_thread_index();
    return slot < 0 ? 0 : slot;
}
#endif

} // namespace

void Workers::forChunks(size_t n, size_t grain,
                        const std::function<void(size_t, size_t, int)>& fn) {
    grain = std::max<size_t>(grain, 1);
    const size_t chunks = (n + grain - 1) / grain;
    auto chunk = [&](size_t c, int slot) { fn(c * grain, std::min(n, (c + 1) * grain), slot); };
    if (count() == 1 || chunks < 2) {
        for (size_t c = 0; c < chunks; ++c) chunk(c, 0);
        return;
    }
    if (tasks_) {
        tasks_->run(chunks, chunk);
        return;
    }
    if (!arena_) arena_ = std::make_unique<Arena>(count_);
#ifdef FFD_OWN_THREAD_POOL
    arena_->pool.run(chunks, chunk);
#else
    arena_->arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, chunks, 1),
            [&](const tbb::blocked_range<size_t>& r) {
                const int slot = slotHere();
                for (size_t c = r.begin(); c < r.end(); ++c) chunk(c, slot);
            },
            tbb::simple_partitioner());
    });
#endif
}

void Workers::forRange(size_t n, const std::function<void(size_t, size_t, int)>& fn) {
    if (count() == 1 || n < 2) {
        fn(0, n, 0);
        return;
    }
#ifndef FFD_OWN_THREAD_POOL
    if (!tasks_) {
        if (!arena_) arena_ = std::make_unique<Arena>(count_);
        arena_->arena.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<size_t>(0, n, 1),
                [&](const tbb::blocked_range<size_t>& r) { fn(r.begin(), r.end(), slotHere()); });
        });
        return;
    }
#endif
    // A few chunks per thread, for balance.
    const size_t chunks = size_t(count()) * 4;
    forChunks(n, (n + chunks - 1) / chunks, fn);
}

} // namespace ffd::detail
