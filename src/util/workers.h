// The worker threads of one World: its own task arena (TBB), never shared with another world
// or with the caller's other work; or the caller's job system (ffd::TaskSystem).
#pragma once

#include "ffdaabb/tasks.h"

#include <cstddef>
#include <functional>
#include <memory>

namespace ffd::detail {

/// A thread count as the settings give it: 0 is the hardware's count (at least 1).
int resolveThreads(int threads);

class Workers {
public:
    Workers();
    ~Workers();
    Workers(Workers&&) noexcept;
    Workers& operator=(Workers&&) noexcept;

    /// The threads the loops run on without a task system (WorldSettings::threads; 0: all
    /// cores). Takes effect at the next loop.
    void setThreads(int threads);
    /// Runs the loops on `tasks` instead (null: back to the world's own threads).
    void setTaskSystem(std::shared_ptr<TaskSystem> tasks);
    const std::shared_ptr<TaskSystem>& taskSystem() const { return tasks_; }
    /// How many threads the loops use (>= 1), so how many slots they name.
    int count() const { return tasks_ ? tasks_->slotCount() : count_; }

    /// Calls fn(first, last, slot) for the chunks [c * grain, min(n, (c + 1) * grain)) of
    /// [0, n), on the world's threads; `slot` (< count()) names the thread running the chunk,
    /// for per-thread scratch. The chunks are the same for every thread count and run in any
    /// order: where a result must not depend on the thread count, write it per item or per
    /// chunk (c = first / grain), never per slot.
    void forChunks(size_t n, size_t grain, const std::function<void(size_t, size_t, int)>& fn);

    /// Calls fn(first, last, slot) over [0, n) split as the scheduler balances it (at least
    /// one item per call), for loops whose items are independent.
    void forRange(size_t n, const std::function<void(size_t, size_t, int)>& fn);

private:
    struct Arena;
    std::unique_ptr<Arena> arena_;
    std::shared_ptr<TaskSystem> tasks_;
    int count_ = 1;
};

} // namespace ffd::detail
