// Bad command lines for mesh-info, run, soak, bench, render and view: each ends with exit status 2
// and one message naming the flag (or file), the value and what was expected; outputs are never
// left behind by a run that fails or is killed.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace ffd::test;
namespace fs = std::filesystem;

namespace {

// Runs the CLI and expects exit status 2 with every part in stderr and nothing on stdout.
// `noDisplay`: with DISPLAY and WAYLAND_DISPLAY unset, for commands that would open a window.
void expectBadInput(const std::vector<std::string>& args, const std::vector<std::string>& parts,
                    bool noDisplay = false) {
    std::string line;
    for (const std::string& a : args) line += a + " ";
    std::vector<std::string> command = {
        "env", "-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", cliPath().string()};
    command.insert(command.end(), args.begin(), args.end());
    const RunResult r = noDisplay ? runProgram(command) : runCli(args);
    EXPECT_EQ(r.status, 2) << line << "\n" << r.err;
    EXPECT_EQ(r.out, "") << line;
    for (const std::string& p : parts)
        EXPECT_NE(r.err.find(p), std::string::npos)
            << line << ": missing \"" << p << "\" in " << r.err;
    // One message, not a crash report or a help text.
    EXPECT_LT(std::count(r.err.begin(), r.err.end(), '\n'), 3) << line << "\n" << r.err;
}

// One bad flag value and the parts its message must contain.
struct BadFlag {
    std::vector<std::string> flag;
    std::vector<std::string> parts;
};

// Runs `command` with each case's flag appended; each must be refused as expectBadInput says.
void expectEachBadFlag(const std::vector<std::string>& command, const std::vector<BadFlag>& cases,
                       bool noDisplay = false) {
    for (const BadFlag& c : cases) {
        std::vector<std::string> args = command;
        args.insert(args.end(), c.flag.begin(), c.flag.end());
        expectBadInput(args, c.parts, noDisplay);
    }
}

// The files in a folder, by name.
std::vector<std::string> listing(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    return names;
}

// A small scene that runs quickly: a few spheres.
// `awake`: the spheres never sleep, so that every frame costs its time.
std::string smallScene(int count = 4, bool awake = false) {
    return R"({"name": "small", "objects": [{"mesh": "sphere", "count": )" + std::to_string(count) +
           R"(, "size": 1.0, "lattice": {"cells": 38}}],
              "world": {"sleep_speed": )" +
           (awake ? "0" : "0.05") + R"(}, "layout": {"columns": [2, 2], "spacing": 1.3}})";
}

// Starts the CLI without waiting; stdout and stderr go to /dev/null.
pid_t startCli(const std::vector<std::string>& args) {
    const std::string exe = cliPath().string();
    std::vector<char*> argv{const_cast<char*>(exe.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, 1);
        ::dup2(null, 2);
        ::execv(exe.c_str(), argv.data());
        std::_Exit(127);
    }
    return pid;
}

// CPU time (user + system) a running child has used, from /proc/<pid>/stat; -1 once it is gone.
double cpuSeconds(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string stat;
    std::getline(in, stat);
    const size_t close = stat.rfind(')'); // the command name may hold spaces
    if (close == std::string::npos) return -1;
    std::istringstream fields(stat.substr(close + 2));
    std::string field;
    unsigned long long utime = 0, stime = 0;
    for (int i = 3; i <= 15 && fields >> field; ++i) {
        if (i == 14) utime = std::stoull(field);
        if (i == 15) stime = std::stoull(field);
    }
    if (stat.substr(close + 2, 1) == "Z") return 1e9; // exited: stop waiting
    return double(utime + stime) / double(::sysconf(_SC_CLK_TCK));
}

int waitExit(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

} // namespace

TEST(CliInput, MeshInfoFlags) {
    TempDir dir;
    expectBadInput({"mesh-info", "--generate", "sphere", "--cells", "abc"},
                   {"--cells", "\"abc\"", "not a whole number", "1..1000000"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cells", "-4"},
                   {"--cells", "-4", "1..1000000"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cells", "0"}, {"--cells", "0"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cells", "99999999999999999999"},
                   {"--cells", "out of range"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cells", "2.5"},
                   {"--cells", "\"2.5\"", "not a whole number"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cell-size", "x"},
                   {"--cell-size", "\"x\"", "not a number"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cell-size", "-0.1"},
                   {"--cell-size", "-0.1", "out of range"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cell-size", "nan"},
                   {"--cell-size", "nan"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cell-size", "inf"},
                   {"--cell-size", "inf"});
    // A cell size the lattice refuses for this object is reported against the flag.
    expectBadInput({"mesh-info", "--generate", "sphere", "--cell-size", "1e-9"},
                   {"--cell-size", "1e-09", "too small", "sphere"});
    // Conflicting options.
    expectBadInput({"mesh-info", "--generate", "sphere", "--cells", "10", "--cell-size", "0.1"},
                   {"--cells", "--cell-size", "not both"});
    writeFile(dir / "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"
                             "f 2 3 4\n");
    expectBadInput({"mesh-info", (dir / "t.obj").string(), "--generate", "sphere"},
                   {"FILE", "--generate", "not both"});
    expectBadInput({"mesh-info"}, {"FILE", "--generate"});
    expectBadInput({"mesh-info", "--generate", "icosphere:9"},
                   {"--generate", "icosphere:9", "0..8"});
    expectBadInput({"mesh-info", "--generate", "teapot:x"}, {"--generate", "teapot:x"});
    expectBadInput({"mesh-info", "--generate", "cube"}, {"--generate", "cube", "alphabet"});
    // Flag syntax errors come from the parser, still with exit status 2 and the flag named.
    expectBadInput({"mesh-info", "--generate"}, {"--generate"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cels", "5"}, {"--cels"});
    expectBadInput({"mesh-info", "--generate", "sphere", "--cells", "5", "--cells", "6"},
                   {"--cells"});
    expectBadInput({"mesh-info", (dir / "t.obj").string(), (dir / "t.obj").string()}, {"t.obj"});
    // Files that are not meshes.
    expectBadInput({"mesh-info", dir.path().string()}, {dir.path().string(), "directory"});
    expectBadInput({"mesh-info", (dir / "t.txt").string()}, {"t.txt"});
    // And the file given works.
    const RunResult ok = runCli({"mesh-info", (dir / "t.obj").string(), "--cells", "8", "--json"});
    EXPECT_EQ(ok.status, 0) << ok.err;
}

TEST(CliInput, RunNumericFlags) {
    const std::vector<BadFlag> cases = {
        {{"--frames", "abc"}, {"--frames", "\"abc\"", "not a whole number", "1..10000000"}},
        {{"--frames", "0"}, {"--frames", "value 0", "1..10000000"}},
        {{"--frames", "-5"}, {"--frames", "-5"}},
        {{"--frames", "99999999999"}, {"--frames", "99999999999", "out of range"}},
        {{"--frames", ""}, {"--frames", "\"\""}},
        {{"--frames", "1e3"}, {"--frames", "\"1e3\""}},
        {{"--frames", " 5"}, {"--frames", "\" 5\""}},
        {{"--warmup", "-1"}, {"--warmup", "-1", "0..10000000"}},
        {{"--measure-every", "-1"}, {"--measure-every", "-1", "0..10000000"}},
        {{"--measure-every", "often"}, {"--measure-every", "\"often\"", "not a whole number"}},
        {{"--objects", "0"}, {"--objects", "value 0", "1..100000"}},
        {{"--objects", "-3"}, {"--objects", "-3"}},
        {{"--objects", "100001"}, {"--objects", "100001"}},
        {{"--objects", "ten"}, {"--objects", "\"ten\""}},
        {{"--threads", "-1"}, {"--threads", "-1", "0 (all cores)..1024"}},
        {{"--threads", "5000"}, {"--threads", "5000"}},
        {{"--seed", "-1"}, {"--seed", "-1", "0..2147483647"}},
        {{"--seed", "4294967296"}, {"--seed", "4294967296"}},
        {{"--mode", "fast"}, {"--mode", "\"fast\"", "enhanced, previous, brute or none"}},
        {{"--mode", ""}, {"--mode", "\"\""}},
    };
    expectEachBadFlag({"run", "--scene", "spheres", "--quiet"}, cases);
    // Missing values, unknown flags, repeated flags, a missing --scene.
    expectBadInput({"run", "--scene", "spheres", "--frames"}, {"--frames"});
    expectBadInput({"run", "--scene"}, {"--scene"});
    expectBadInput({"run", "--frames", "5"}, {"--scene"});
    expectBadInput({"run", "--scene", "spheres", "--frame", "5"}, {"--frame"});
    expectBadInput({"run", "--scene", "spheres", "--frames", "5", "--frames", "6"}, {"--frames"});
    expectBadInput({"run", "--scene", "spheres", "extra"}, {"extra"});
    // A bad flag is reported even when the scene is bad too.
    expectBadInput({"run", "--scene", "no-such-scene", "--frames", "x"}, {"--frames"});
}

TEST(CliInput, RunSceneFiles) {
    TempDir dir;
    expectBadInput({"run", "--scene", "no-such-scene"}, {"no-such-scene", "spheres"});
    expectBadInput({"run", "--scene", (dir / "absent.json").string()},
                   {(dir / "absent.json").string(), "does not exist"});
    expectBadInput({"run", "--scene", dir.path().string() + "/"}, {"is a folder"});
    writeFile(dir / "empty.json", "");
    expectBadInput({"run", "--scene", (dir / "empty.json").string()}, {"empty.json", "is empty"});
    writeFile(dir / "bad.json", "{\"objects\": [{\"mesh\": \"sphere\", \"count\": \"x\"}]}");
    expectBadInput({"run", "--scene", (dir / "bad.json").string()},
                   {"bad.json", "objects[0].count", "\"x\"", "expected an integer"});
    writeFile(dir / "deep.json", std::string(100000, '[') + std::string(100000, ']'));
    expectBadInput({"run", "--scene", (dir / "deep.json").string()}, {"deep.json", "nested"});
    writeFile(dir / "broken.obj", "v 0 0 0\nf 1 2 3\n");
    writeFile(dir / "mesh.json", R"({"objects": [{"mesh": {"file": "broken.obj"}}]})");
    expectBadInput({"run", "--scene", (dir / "mesh.json").string(), "--frames", "1"},
                   {"mesh.json", "objects[0]", "broken.obj"});
}

TEST(CliInput, RunOutputPaths) {
    TempDir dir;
    const std::vector<std::string> base = {"run", "--scene",   "spheres", "--frames",
                                           "1",   "--objects", "1",       "--quiet"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> args = base;
        args.insert(args.end(), extra.begin(), extra.end());
        return args;
    };
    const std::string missing = (dir / "no" / "such" / "stats.json").string();
    expectBadInput(with({"--stats", missing}), {"--stats", missing, "does not exist"});
    expectBadInput(with({"--export-obj", missing}), {"--export-obj", "does not exist"});
    expectBadInput(with({"--stats", dir.path().string()}), {"--stats", "is a folder"});
    expectBadInput(with({"--export-obj", dir.path().string() + "/"}), {"--export-obj", "folder"});
    writeFile(dir / "file", "x");
    expectBadInput(with({"--stats", (dir / "file" / "stats.json").string()}),
                   {"--stats", "is not a folder"});
    // Outputs are renamed into place: a device would be replaced, so it is refused.
    expectBadInput(with({"--stats", "/dev/null"}), {"--stats", "/dev/null", "not a regular file"});
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    // Both outputs in one file.
    expectBadInput(
        with({"--stats", (dir / "out").string(), "--export-obj", (dir / "." / "out").string()}),
        {"--export-obj", "same file as --stats"});
    // The file is first written under a longer temporary name, which must fit.
    expectBadInput(with({"--stats", (dir / std::string(220, 's')).string()}),
                   {"--stats", "220 characters", "at most 200"});
    EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"file"});
    // And the good case writes both.
    const RunResult ok = runCli(
        with({"--stats", (dir / "s.json").string(), "--export-obj", (dir / "m.obj").string()}));
    ASSERT_EQ(ok.status, 0) << ok.err;
    EXPECT_EQ(listing(dir.path()), (std::vector<std::string>{"file", "m.obj", "s.json"}));
    EXPECT_TRUE(nlohmann::json::parse(readFile(dir / "s.json")).contains("state_hash"));
}

TEST(CliInput, AFailedRunLeavesNoOutputs) {
    TempDir dir;
    // The scene parses (the mesh file exists) but cannot be built: the failure comes after the
    // run has started and its outputs were checked.
    writeFile(dir / "broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    writeFile(dir / "scene.json", R"({"objects": [{"mesh": {"file": "broken.obj"}}]})");
    fs::create_directories(dir / "out");
    const RunResult r = runCli({"run", "--scene", (dir / "scene.json").string(), "--quiet",
                                "--stats", (dir / "out" / "stats.json").string(), "--export-obj",
                                (dir / "out" / "final.obj").string()});
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(fs::is_empty(dir / "out")) << "left behind: " << listing(dir / "out").front();
}

TEST(CliInput, ARunWhoseOutputFolderVanishesLeavesNoOutputs) {
    // The stats folder exists when the run starts and is gone when the outputs are written at
    // the end: the stats cannot be written, and the mesh export, which could, is not left
    // behind either (outputs are all or nothing).
    TempDir dir;
    writeFile(dir / "scene.json", smallScene(2, true));
    fs::create_directories(dir / "out");
    fs::create_directories(dir / "keep");
    // 10,000 frames of two spheres awake: about 1 s in a release build, 7 s under ASan.
    const pid_t pid =
        startCli({"run", "--scene", (dir / "scene.json").string(), "--quiet", "--frames", "10000",
                  "--stats", (dir / "out" / "stats.json").string(), "--export-obj",
                  (dir / "keep" / "final.obj").string()});
    // Once the process has used 0.3 s of CPU time it is stepping frames (the scene builds in
    // milliseconds); then the folder goes.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (cpuSeconds(pid) < 0.3 && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    fs::remove_all(dir / "out");
    EXPECT_EQ(waitExit(pid), 2);
    EXPECT_EQ(listing(dir.path()), (std::vector<std::string>{"keep", "scene.json"}));
    EXPECT_TRUE(fs::is_empty(dir / "keep")) << listing(dir / "keep").front();
}

TEST(CliInput, AKilledRunLeavesNoOutputs) {
    TempDir dir;
    writeFile(dir / "scene.json", smallScene(4, true));
    const pid_t pid = startCli({"run", "--scene", (dir / "scene.json").string(), "--quiet",
                                "--frames", "10000000", "--stats", (dir / "stats.json").string(),
                                "--export-obj", (dir / "final.obj").string()});
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    ::kill(pid, SIGTERM);
    EXPECT_EQ(waitExit(pid), 128 + SIGTERM);
    EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"scene.json"});
}

TEST(CliInput, SoakFlags) {
    expectBadInput({"soak", "--scene", "spheres", "--frames", "0"}, {"--frames", "value 0"});
    expectBadInput({"soak", "--scene", "spheres", "--check-every", "x"},
                   {"--check-every", "\"x\""});
    expectBadInput({"soak", "--scene", "spheres", "--floor-tolerance", "-1"},
                   {"--floor-tolerance", "-1", "0..1"});
    expectBadInput({"soak", "--scene", "spheres", "--depth-tolerance", "2"},
                   {"--depth-tolerance", "0..1"});
    expectBadInput({"soak", "--scene", "spheres", "--energy-tolerance", "nan"},
                   {"--energy-tolerance", "nan"});
    expectBadInput({"soak", "--scene", "spheres", "--settle-time", "-1"}, {"--settle-time"});
    expectBadInput({"soak", "--scene", "spheres", "--threads", "-2"}, {"--threads", "-2"});
    expectBadInput({"soak"}, {"--scene"});
}

TEST(CliInput, BenchFlags) {
    TempDir dir;
    const std::string out = (dir / "b").string();
    const auto bench = [&](std::vector<std::string> flag) {
        std::vector<std::string> args = {"bench", "--scenes", "spheres", "--quiet", "--out", out};
        args.insert(args.end(), flag.begin(), flag.end());
        return args;
    };
    expectBadInput(bench({"--frames", "abc"}),
                   {"--frames", "\"abc\"", "not a whole number", "1..1000000"});
    expectBadInput(bench({"--frames", "0"}), {"--frames", "value 0", "1..1000000"});
    expectBadInput(bench({"--frames", "-1"}), {"--frames", "-1", "1..1000000"});
    expectBadInput(bench({"--frames", "1000001"}), {"--frames", "1000001", "out of range"});
    expectBadInput(bench({"--frames", "2.5"}), {"--frames", "\"2.5\""});
    expectBadInput(bench({"--warmup", "-1"}), {"--warmup", "-1", "0..10000000"});
    expectBadInput(bench({"--warmup", "x"}), {"--warmup", "\"x\"", "not a whole number"});
    expectBadInput(bench({"--objects", "0"}), {"--objects", "value 0", "1..100000"});
    expectBadInput(bench({"--objects", "many"}), {"--objects", "\"many\"", "1..100000"});
    expectBadInput(bench({"--objects", ""}), {"--objects", "\"\""});
    expectBadInput(bench({"--modes", "enhanced"}), {"--modes", "\"enhanced\"", "expected two"});
    expectBadInput(bench({"--modes", "enhanced,fast"}),
                   {"--modes", "unknown mode \"fast\"", "enhanced, previous, brute, none"});
    expectBadInput(bench({"--modes", "previous,enhanced,none"}),
                   {"--modes", "names 3 modes", "expected two"});
    expectBadInput(bench({"--modes", "none,none"}), {"--modes", "\"none,none\"", "same mode"});
    // Nothing is written for a bad flag.
    EXPECT_FALSE(fs::exists(dir / "b"));
}

TEST(CliInput, RenderFlags) {
    TempDir dir;
    const std::string out = (dir / "r.mp4").string();
    const std::vector<BadFlag> cases = {
        {{"--width", "-5"}, {"--width", "-5", "16..8192"}},
        {{"--width", "abc"}, {"--width", "\"abc\"", "not a whole number", "16..8192"}},
        {{"--width", "5"}, {"--width", "value 5", "16..8192"}},
        {{"--height", "100000"}, {"--height", "100000", "16..8192"}},
        {{"--height", "7.5"}, {"--height", "\"7.5\""}},
        {{"--fov", "200"}, {"--fov", "200", "out of range", "1..170"}},
        {{"--fov", "0"}, {"--fov", "\"0\"", "1..170"}},
        {{"--fov", "wide"}, {"--fov", "\"wide\"", "not a number"}},
        {{"--fps", "abc"}, {"--fps", "\"abc\"", "not a number", "1..1000"}},
        {{"--fps", "0"}, {"--fps", "\"0\"", "1..1000"}},
        {{"--fps", "inf"}, {"--fps", "inf"}},
        {{"--frames", "0"}, {"--frames", "value 0", "1..100000"}},
        {{"--frames", "abc"}, {"--frames", "\"abc\"", "not a whole number"}},
        {{"--steps", "0"}, {"--steps", "value 0", "1..1000"}},
        {{"--azimuth", "nan"}, {"--azimuth", "nan", "-360..360"}},
        {{"--azimuth", "361"}, {"--azimuth", "361", "-360..360"}},
        {{"--elevation", "91"}, {"--elevation", "91", "-90..90"}},
        {{"--elevation", "up"}, {"--elevation", "\"up\""}},
        {{"--objects", "0"}, {"--objects", "value 0", "1..100000"}},
        {{"--objects", "x"}, {"--objects", "\"x\""}},
        {{"--seed", "-1"}, {"--seed", "-1", "0..2147483647"}},
        {{"--mode", "fast"}, {"--mode", "\"fast\""}},
    };
    expectEachBadFlag({"render", "--scene", "spheres", "--quiet", "--out", out}, cases);
    // Reported even when the scene is bad too; render has no --threads.
    expectBadInput({"render", "--scene", "no-such-scene", "--out", out, "--fps", "x"}, {"--fps"});
    expectBadInput({"render", "--scene", "spheres", "--out", out, "--threads", "2"}, {"--threads"});
    // Nothing is written for a bad flag.
    EXPECT_TRUE(listing(dir.path()).empty());
}

TEST(CliInput, ViewFlagsAreCheckedBeforeAnyWindow) {
    // No display: a bad flag must be reported before the viewer opens a window.
    TempDir dir;
    const std::string shot = (dir / "shot.png").string();
    const std::vector<BadFlag> cases = {
        {{"--frames", "-1"}, {"--frames", "-1", "0..10000000"}},
        {{"--frames", "abc"}, {"--frames", "\"abc\"", "not a whole number"}},
        {{"--width", "-5"}, {"--width", "-5", "64..8192"}},
        {{"--width", "32"}, {"--width", "value 32", "64..8192"}}, // the viewer's minimum
        {{"--height", "0"}, {"--height", "value 0", "64..8192"}},
        {{"--fov", "200"}, {"--fov", "200", "1..170"}},
        {{"--steps", "x"}, {"--steps", "\"x\""}},
        {{"--elevation", "-100"}, {"--elevation", "-100", "-90..90"}},
        {{"--seed", "abc"}, {"--seed", "\"abc\""}},
    };
    expectEachBadFlag({"view", "--scene", "spheres", "--quiet", "--screenshot", shot}, cases, true);
    // The view takes no --fps.
    expectBadInput({"view", "--scene", "spheres", "--fps", "30"}, {"--fps"}, true);
    EXPECT_FALSE(fs::exists(shot));
}
