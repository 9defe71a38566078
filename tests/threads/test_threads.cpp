// Threads: the library's ThreadPool, the TaskSystem interface, and bit-identical steps at any
// thread count on the paper's scenes at full size. CI also runs these under ThreadSanitizer
// (the tsan preset, label "threads").
#include "ffdaabb/error.h"
#include "ffdaabb/scene.h"
#include "ffdaabb/tasks.h"
#include "ffdaabb/world.h"
#include "world/world_data.h"

#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

using namespace ffd;

namespace {

// A TaskSystem that runs a loop's indices on the caller, last index first, each on the next
// slot in turn: the world must not depend on the order of its tasks or on which slot runs
// which (the threaded order is ThreadPool's; examples/own_threads.cpp spawns threads).
class ReversedTasks final : public TaskSystem {
public:
    explicit ReversedTasks(int slots) : slots_(slots) {}
    int slotCount() const override { return slots_; }
    void run(size_t count, const std::function<void(size_t, int)>& task) override {
        for (size_t i = count; i-- > 0;) task(i, int((count - 1 - i + size_t(runs)) % slots_));
        ++runs;
    }
    int runs = 0;

private:
    int slots_;
};

// The state hash of a shipped scene after `frames` frames, on `threads` of the world's own
// or on `tasks`.
uint64_t hashAfter(const std::string& name, int frames, int threads,
                   std::shared_ptr<TaskSystem> tasks = nullptr) {
    Scene scene = loadScene(name);
    scene.world.threads = threads;
    SceneBuild build = buildScene(scene);
    build.world.setTaskSystem(std::move(tasks));
    for (int f = 0; f < frames; ++f) build.world.step();
    return build.world.stateHash();
}

} // namespace

TEST(ThreadPool, RunsEveryIndexOnceOnDistinctSlots) {
    ThreadPool pool(4);
    EXPECT_EQ(pool.slotCount(), 4);
    for (size_t count : {1u, 2u, 7u, 1000u}) {
        std::vector<std::atomic<int>> calls(count);
        std::vector<std::atomic<int>> busy(4);
        std::atomic<bool> overlap{false}, badSlot{false};
        pool.run(count, [&](size_t i, int slot) {
            if (slot < 0 || slot >= 4) {
                badSlot = true;
                return;
            }
            // No two calls that run at the same time share a slot.
            if (busy[size_t(slot)].fetch_add(1) != 0) overlap = true;
            calls[i].fetch_add(1);
            busy[size_t(slot)].fetch_sub(1);
        });
        for (size_t i = 0; i < count; ++i) EXPECT_EQ(calls[i].load(), 1) << "index " << i;
        EXPECT_FALSE(overlap);
        EXPECT_FALSE(badSlot);
    }
}

TEST(ThreadPool, ManyShortJobsInARowLoseNothing) {
    // Jobs follow each other faster than workers wake: each must still see all its indices run
    // once, and never an index of another job.
    ThreadPool pool(3);
    std::vector<int> sums(2000, 0);
    for (size_t job = 0; job < sums.size(); ++job) {
        std::atomic<int> sum{0};
        pool.run(job % 9 + 1, [&](size_t i, int) { sum.fetch_add(int(i) + 1); });
        sums[job] = sum.load();
    }
    for (size_t job = 0; job < sums.size(); ++job) {
        const int n = int(job % 9 + 1);
        ASSERT_EQ(sums[job], n * (n + 1) / 2) << "job " << job;
    }
}

TEST(ThreadPool, ThreadCountOutOfRangeIsAnInputError) {
    try {
        ThreadPool pool(-1);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("-1"), std::string::npos) << e.what();
    }
    EXPECT_THROW(ThreadPool(1025), InputError);
    EXPECT_GE(ThreadPool(0).slotCount(), 1);
}

TEST(ThreadCounts, PaperScenesAtFullSizeStepTheSameOnOneToFourThreads) {
    // Enough frames for the layers to land on the floor and on each other, so that every
    // parallel stage has contacts to share out: box pairs, the floor, the solver's zones.
    const std::pair<const char*, int> scenes[] = {
        {"alphabets", 55}, {"spheres", 50}, {"teapots", 50}, {"buddhas", 40}};
    for (const auto& [name, frames] : scenes) {
        const uint64_t one = hashAfter(name, frames, 1);
        for (int threads : {2, 3, 4})
            EXPECT_EQ(hashAfter(name, frames, threads), one)
                << name << " after " << frames << " frames on " << threads << " threads";
    }
}

// The contacts a world lists come in an order set by the bodies' places (the solver's zones,
// then each point's node and box: World::contacts), whichever threads found and sorted them:
// the same list, bit for bit and in the same order, on one thread and on three.
TEST(ThreadCounts, TheContactsListedAreTheSameInTheSameOrderOnOneAndThreeThreads) {
    std::vector<ContactInfo> listed[2];
    for (int k = 0; k < 2; ++k) {
        Scene scene = loadScene("spheres");
        scene.world.threads = k == 0 ? 1 : 3;
        SceneBuild build = buildScene(scene);
        for (int f = 0; f < 50; ++f) build.world.step();
        build.world.contacts(listed[k]);
    }
    ASSERT_GT(listed[0].size(), 200u); // the spheres lie on each other and on the floor
    ASSERT_EQ(listed[1].size(), listed[0].size());
    size_t objectContacts = 0;
    for (size_t n = 0; n < listed[0].size(); ++n) {
        const ContactInfo &a = listed[0][n], &b = listed[1][n];
        ASSERT_TRUE(a.bodyA == b.bodyA && a.bodyB == b.bodyB) << "contact " << n;
        ASSERT_TRUE(a.point == b.point && a.normal == b.normal) << "contact " << n;
        ASSERT_EQ(a.depth, b.depth) << "contact " << n;
        ASSERT_EQ(a.impulse, b.impulse) << "contact " << n;
        objectContacts += !a.bodyB.isNull();
    }
    EXPECT_GT(objectContacts, 100u);
}

// A pile whose contacts are swept in blocks (bands of the solver's zones, each through all its
// sweeps before the next: collision/contact.h, SolverSchedule), as piles of more than
// kBandContacts contacts are: here the spheres with blocks of 128, so that a small scene has
// several.
TEST(ThreadCounts, APileSweptInBlocksStepsTheSameOnOneToThreeThreads) {
    uint64_t hash[3] = {};
    size_t blocks = 0;
    for (int threads : {1, 2, 3}) {
        Scene scene = loadScene("spheres");
        scene.world.threads = threads;
        SceneBuild build = buildScene(scene);
        detail::dataOf(build.world).collision.solver.bandContacts = 128;
        for (int f = 0; f < 50; ++f) build.world.step();
        hash[threads - 1] = build.world.stateHash();
        blocks = detail::dataOf(build.world).collision.solver.schedule.blockCount();
    }
    EXPECT_GT(blocks, 2u); // the last substep's schedule
    EXPECT_EQ(hash[1], hash[0]);
    EXPECT_EQ(hash[2], hash[0]);
    EXPECT_NE(hash[0], hashAfter("spheres", 50, 1)) << "the blocks changed nothing";
}

TEST(ThreadCounts, ChangingTheThreadCountBetweenStepsChangesNothing) {
    Scene scene = loadScene("spheres");
    SceneBuild steady = buildScene(scene), changing = buildScene(scene);
    for (int f = 0; f < 60; ++f) {
        WorldSettings s = changing.world.settings();
        s.threads = 1 + f % 4;
        changing.world.setSettings(s);
        steady.world.step();
        changing.world.step();
    }
    EXPECT_EQ(changing.world.stateHash(), steady.world.stateHash());
}

TEST(TaskSystems, AJobSystemOfTheCallersStepsTheSameAsTheWorldsOwnThreads) {
    const uint64_t own = hashAfter("spheres", 60, 1);
    auto reversed = std::make_shared<ReversedTasks>(3);
    EXPECT_EQ(hashAfter("spheres", 60, 1, reversed), own);
    EXPECT_GT(reversed->runs, 60) << "the world did not run its loops on the task system";
    EXPECT_EQ(hashAfter("spheres", 60, 1, std::make_shared<ThreadPool>(2)), own);
}

TEST(TaskSystems, ClearingTheTaskSystemReturnsToTheWorldsThreads) {
    Scene scene = loadScene("spheres");
    scene.world.threads = 2;
    SceneBuild build = buildScene(scene);
    auto tasks = std::make_shared<ReversedTasks>(2);
    build.world.setTaskSystem(tasks);
    EXPECT_EQ(build.world.taskSystem(), tasks);
    build.world.step();
    const int runs = tasks->runs;
    EXPECT_GT(runs, 0);
    build.world.setTaskSystem(nullptr);
    EXPECT_EQ(build.world.taskSystem(), nullptr);
    build.world.step();
    EXPECT_EQ(tasks->runs, runs);
}
