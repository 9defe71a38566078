// Threads for the world's parallel loops: its own TBB arena by default (WorldSettings::threads),
// or a job system of yours (World::setTaskSystem). Whichever runs them, and on however many
// threads, a step gives bit-identical results: every loop splits its work in the same chunks,
// and what depends on order is merged in chunk order.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace ffd {

/// A job system to run the world's parallel loops on (World::setTaskSystem): a game engine's
/// workers, say, so that the world's work shares their threads instead of starting its own.
class TaskSystem {
public:
    virtual ~TaskSystem() = default;

    /// How many tasks of one loop may run at once (>= 1): the world keeps scratch for each slot.
    virtual int slotCount() const = 0;

    /// Calls task(index, slot) once for every index in [0, count), on any threads and in any
    /// order, and returns when every call has returned. Calls that run at the same time must
    /// be given different slots in [0, slotCount()) (a worker's own index, say). The world calls
    /// run() from one thread at a time and never from inside a task.
    virtual void run(size_t count, const std::function<void(size_t index, int slot)>& task) = 0;
};

/// A TaskSystem on threads of its own: `threads` - 1 workers and the caller of run(). Workers
/// wait for work spinning a little, then sleeping. For programs without a job system, and an
/// example of one (examples/own_threads.cpp).
class ThreadPool final : public TaskSystem {
public:
    /// threads: 1..1024; 0: the hardware's count.
    explicit ThreadPool(int threads = 0);
    ~ThreadPool() override;
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int slotCount() const override { return threads_; }
    void run(size_t count, const std::function<void(size_t index, int slot)>& task) override;

private:
    struct Shared;
    std::unique_ptr<Shared> shared_;
    int threads_ = 1;
};

} // namespace ffd
