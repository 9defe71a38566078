// ThreadPool: workers that take the indices of one job at a time from a shared counter.
//
// A job lives on the stack of run(); `current` points to it while it runs. A worker announces
// itself (`inside`) before it reads `current`, and run() clears `current` before it waits for
// `inside` to drop to zero, so no worker can still hold the job when run() returns (both in
// one sequentially consistent order: either the worker's announcement comes first and run()
// waits for it, or the clearing does and the worker sees no job).
#include "ffdaabb/error.h"
#include "ffdaabb/tasks.h"
#include "util/workers.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ffd {

namespace {

void pause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
}

// How long a worker looks for work before it sleeps: the loops of one step follow each other
// within microseconds, frames within milliseconds.
constexpr int kSpins = 1 << 14;

} // namespace

struct ThreadPool::Shared {
    struct Job {
        const std::function<void(size_t, int)>* task = nullptr;
        size_t count = 0;
        uint64_t id = 0;
        std::atomic<size_t> next{0}, done{0};
    };

    std::atomic<Job*> current{nullptr};
    std::atomic<uint64_t> currentId{0}; ///< the last job published (read without entering)
    std::atomic<int> inside{0};
    std::atomic<int> sleepers{0};
    std::atomic<bool> stop{false};
    uint64_t lastId = 0;
    std::mutex mutex;
    std::condition_variable wake;
    std::vector<std::thread> workers;

    // Takes indices of `job` until none is left.
    static void work(Job& job, int slot) {
        for (;;) {
            const size_t i = job.next.fetch_add(1);
            if (i >= job.count) return;
            (*job.task)(i, slot);
            job.done.fetch_add(1);
        }
    }

    void worker(int slot) {
        uint64_t seen = 0; // the last job this worker took part in or found finished
        for (;;) {
            bool found = false;
            for (int spin = 0; spin < kSpins && !found; ++spin) {
                if (stop.load()) return;
                found = currentId.load() != seen;
                if (!found) pause();
            }
            if (!found) {
                std::unique_lock lock(mutex);
                sleepers.fetch_add(1);
                wake.wait(lock, [&] { return stop.load() || currentId.load() != seen; });
                sleepers.fetch_sub(1);
                if (stop.load()) return;
            }
            const uint64_t published = currentId.load();
            inside.fetch_add(1);
            // Only inside may the job be read: run() waits for `inside` before it returns.
            if (Job* j = current.load(); j != nullptr && j->id != seen) {
                seen = j->id;
                work(*j, slot);
            } else {
                seen = std::max(seen, published); // finished before this worker came
            }
            inside.fetch_sub(1);
        }
    }
};

ThreadPool::ThreadPool(int threads) : shared_(std::make_unique<Shared>()) {
    if (threads < 0 || threads > 1024)
        throw InputError("threads", "ThreadPool of " + std::to_string(threads) +
                                        " threads (expected 0 for all cores, or 1..1024)");
    threads_ = detail::resolveThreads(threads);
    for (int slot = 1; slot < threads_; ++slot)
        shared_->workers.emplace_back([this, slot] { shared_->worker(slot); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(shared_->mutex);
        shared_->stop.store(true);
    }
    shared_->wake.notify_all();
    for (std::thread& t : shared_->workers) t.join();
}

void ThreadPool::run(size_t count, const std::function<void(size_t, int)>& task) {
    if (count == 0) return;
    if (threads_ == 1 || count == 1) {
        for (size_t i = 0; i < count; ++i) task(i, 0);
        return;
    }
    Shared& s = *shared_;
    Shared::Job job;
    job.task = &task;
    job.count = count;
    job.id = ++s.lastId;
    s.current.store(&job);
    s.currentId.store(job.id);
    if (s.sleepers.load() > 0) {
        std::lock_guard lock(s.mutex);
        s.wake.notify_all();
    }
    Shared::work(job, 0);
    for (int spin = 0; job.done.load() < count; ++spin)
        spin < kSpins ? pause() : std::this_thread::yield();
    s.current.store(nullptr);
    while (s.inside.load() > 0) pause();
}

} // namespace ffd
