// A world on threads of your choosing. By default a world runs its step on a TBB arena of its
// own (WorldSettings::threads). A program with a job system of its own hands it to the world as
// an ffd::TaskSystem instead; here, a deliberately plain one that starts a thread per slot for
// every loop, beside the library's ThreadPool. Whichever runs the step, and on however many
// threads, the results are bit-identical: the program checks it.
#include <ffdaabb/scene.h>
#include <ffdaabb/tasks.h>
#include <ffdaabb/world.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

namespace {

// The smallest correct TaskSystem: `slots` threads take indices from a shared counter, each
// passing its own slot number, and run() returns when all have finished. A real engine would
// hand the indices to its existing workers instead of starting threads.
class SpawningTasks final : public ffd::TaskSystem {
public:
    explicit SpawningTasks(int slots) : slots_(slots) {}
    int slotCount() const override { return slots_; }
    void run(size_t count, const std::function<void(size_t, int)>& task) override {
        std::atomic<size_t> next{0};
        auto work = [&](int slot) {
            for (size_t i; (i = next.fetch_add(1)) < count;) task(i, slot);
        };
        std::vector<std::thread> helpers;
        for (int slot = 1; slot < slots_; ++slot) helpers.emplace_back(work, slot);
        work(0);
        for (std::thread& t : helpers) t.join();
    }

private:
    int slots_;
};

// Steps the spheres scene for `frames` frames on `tasks` (null: the world's own threads, as
// many as `threads`) and returns its state hash; prints the time per frame.
uint64_t simulate(const char* label, std::shared_ptr<ffd::TaskSystem> tasks, int threads,
                  int frames) {
    ffd::Scene scene = ffd::loadScene("spheres");
    scene.world.threads = threads;
    ffd::SceneBuild build = ffd::buildScene(scene);
    build.world.setTaskSystem(std::move(tasks));
    const auto start = std::chrono::steady_clock::now();
    for (int f = 0; f < frames; ++f) build.world.step();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("%-34s %7.2f ms per frame   state hash %016llx\n", label, ms / frames,
                static_cast<unsigned long long>(build.world.stateHash()));
    return build.world.stateHash();
}

} // namespace

int main() {
    const int frames = 120; // the spheres land and pile up from frame 20 or so
    const uint64_t one = simulate("own threads, 1", nullptr, 1, frames);
    const uint64_t two = simulate("own threads, 2", nullptr, 2, frames);
    const uint64_t pool =
        simulate("ffd::ThreadPool(3)", std::make_shared<ffd::ThreadPool>(3), 1, frames);
    const uint64_t spawning = simulate("a TaskSystem of your own, 2 slots",
                                       std::make_shared<SpawningTasks>(2), 1, frames);
    const bool same = two == one && pool == one && spawning == one;
    std::printf(same ? "every run stepped the same trajectory\n"
                     : "the trajectories differ: this is a bug\n");
    return same ? 0 : 1;
}
