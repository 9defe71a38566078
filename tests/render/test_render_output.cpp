// Rendering and the simulation, and what renderFrames writes: PNG files, sequences, MP4.
#include "ffdaabb/error.h"
#include "render_test_util.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

using namespace ffd;
using namespace ffd::test;
namespace fs = std::filesystem;

namespace {

/// Six spheres in a leaning column: they collide with each other and the floor.
World column() {
    World world;
    for (int i = 0; i < 6; ++i)
        addBall(world, {0.3f * float(i % 2), 1.1f + 2.05f * float(i), 0.2f * float(i % 3)});
    return world;
}

std::vector<std::string> filesIn(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    return names;
}

render::RenderSettings small(int frames) {
    render::RenderSettings s;
    s.width = 96, s.height = 64;
    s.frames = frames;
    return s;
}

} // namespace

TEST(RenderOutput, RenderingNeverChangesTheSimulation) {
    World rendered = column(), plain = column();
    render::OffscreenRenderer renderer;
    render::DrawOptions d;
    d.overlays = {true, true, true, true};
    const render::Camera c = render::frameWorld(rendered, 1.5f);
    int contactFrames = 0;
    for (int f = 0; f < 90; ++f) {
        rendered.step();
        plain.step();
        renderer.render(rendered, c, d, 120, 80);
        contactFrames += rendered.profile().contacts > 0 ? 1 : 0;
        if (f % 30 == 29)
            rendered.setMode(f % 60 == 29 ? CollisionMode::Previous : CollisionMode::Enhanced),
                plain.setMode(rendered.settings().mode);
    }
    EXPECT_GT(contactFrames, 0); // the contact overlay had contacts to draw
    EXPECT_EQ(rendered.stateHash(), plain.stateHash());

    // renderFrames steps the same world the same way.
    render::RenderSettings s = small(20);
    s.stepsPerFrame = 3;
    s.draw.overlays = {true, true, true, true};
    int seen = 0;
    const render::RenderStats stats =
        render::renderFrames(column, s, [&](int index, const render::Image& image) {
            EXPECT_EQ(index, seen++);
            EXPECT_EQ(image.width, 96);
            EXPECT_EQ(image.height, 64);
        });
    World again = column();
    for (int i = 0; i < 60; ++i) again.step();
    EXPECT_EQ(seen, 20);
    EXPECT_EQ(stats.frames, 20);
    EXPECT_EQ(stats.steps, 60u);
    EXPECT_EQ(stats.stateHash, again.stateHash());
    EXPECT_NE(stats.context.find("EGL"), std::string::npos);
}

TEST(RenderOutput, PngRoundTripIsExactAndAtomic) {
    TempDir dir;
    render::Image img;
    img.width = 7, img.height = 5;
    for (int i = 0; i < 7 * 5 * 4; ++i) img.pixels.push_back(uint8_t(i * 37 % 256));
    render::writePng(img, dir / "a.png");
    const render::Image back = render::readPng(dir / "a.png");
    EXPECT_EQ(back.width, 7);
    EXPECT_EQ(back.height, 5);
    EXPECT_EQ(back.pixels, img.pixels);
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"a.png"}); // no temporary left
    EXPECT_THROW(render::writePng(img, dir / "missing" / "a.png"), InputError);
    EXPECT_THROW(render::readPng(dir / "nothing.png"), InputError);
    render::Image bad = img;
    bad.pixels.pop_back();
    EXPECT_THROW(render::writePng(bad, dir / "b.png"), InputError);
    EXPECT_FALSE(fs::exists(dir / "b.png"));
}

TEST(RenderOutput, PngSequenceWritesOneFilePerFrame) {
    TempDir dir;
    render::renderFrames(column, small(5), dir / "f_%03d.png");
    EXPECT_EQ(filesIn(dir.path()), (std::vector<std::string>{"f_000.png", "f_001.png", "f_002.png",
                                                             "f_003.png", "f_004.png"}));
    const render::Image first = render::readPng(dir / "f_000.png");
    EXPECT_EQ(first.width, 96);
    EXPECT_EQ(first.height, 64);

    // A folder: frame_00000.png ...; created when the path ends in '/'.
    const fs::path folder = dir / "seq";
    render::renderFrames(column, small(3), folder.string() + "/");
    EXPECT_EQ(filesIn(folder),
              (std::vector<std::string>{"frame_00000.png", "frame_00001.png", "frame_00002.png"}));

    // A path without an extension is a folder too, made with the parents it lacks.
    const fs::path made = dir / "a" / "new" / "folder";
    render::renderFrames(column, small(2), made);
    EXPECT_EQ(filesIn(made), (std::vector<std::string>{"frame_00000.png", "frame_00001.png"}));

    // A plain .png: the last frame only, identical to the last image of the same run.
    render::Image last;
    render::renderFrames(column, small(4), [&](int, const render::Image& i) { last = i; });
    render::renderFrames(column, small(4), dir / "still.png");
    EXPECT_EQ(render::readPng(dir / "still.png").pixels, last.pixels);
}

TEST(RenderOutput, Mp4HasTheFrameCount) {
    ASSERT_TRUE(inPath("ffmpeg")) << "ffmpeg is not installed (Debian package ffmpeg)";
    ASSERT_TRUE(inPath("ffprobe")) << "ffprobe is not installed (Debian package ffmpeg)";
    TempDir dir;
    render::RenderSettings s = small(12);
    s.width = 97; // odd: padded for yuv420p
    s.fps = 24;
    render::renderFrames(column, s, dir / "out.mp4");
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"out.mp4"});
    const RunResult probe =
        runProgram({"ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
                    "-show_entries", "stream=nb_read_frames,width,height,codec_name", "-of",
                    "default=noprint_wrappers=1", (dir / "out.mp4").string()});
    ASSERT_EQ(probe.status, 0) << probe.err;
    EXPECT_NE(probe.out.find("nb_read_frames=12"), std::string::npos) << probe.out;
    EXPECT_NE(probe.out.find("codec_name=h264"), std::string::npos) << probe.out;
    EXPECT_NE(probe.out.find("width=98"), std::string::npos) << probe.out;
    EXPECT_NE(probe.out.find("height=64"), std::string::npos) << probe.out;
}

TEST(RenderOutput, VideoFailuresLeaveNothingBehind) {
    TempDir dir;
    render::Image frame;
    frame.width = 32, frame.height = 32;
    frame.pixels.assign(32 * 32 * 4, 128);
    {
        render::VideoSettings v;
        v.ffmpeg = (dir / "no-such-ffmpeg").string();
        EXPECT_THROW(render::VideoWriter(dir / "a.mp4", 32, 32, 30, v), render::RenderError);
    }
    {
        // ffmpeg starts but rejects the preset: the error carries its message.
        render::VideoSettings v;
        v.preset = "no-such-preset";
        render::VideoWriter w(dir / "b.mp4", 32, 32, 30, v);
        try {
            for (int i = 0; i < 50; ++i) w.addFrame(frame);
            w.finish();
            ADD_FAILURE() << "an invalid preset was accepted";
        } catch (const render::RenderError& e) {
            EXPECT_NE(std::string(e.what()).find("b.mp4"), std::string::npos) << e.what();
        }
    }
    {
        // Abandoned before finish(): removed.
        render::VideoWriter w(dir / "c.mp4", 32, 32, 30);
        w.addFrame(frame);
    }
    {
        render::VideoWriter w(dir / "d.mp4", 32, 32, 30);
        frame.width = 16;
        EXPECT_THROW(w.addFrame(frame), InputError);
    }
    EXPECT_TRUE(filesIn(dir.path()).empty());
    EXPECT_THROW(render::VideoWriter(dir / "missing" / "e.mp4", 32, 32, 30), InputError);
    EXPECT_THROW(render::VideoWriter(dir / "f.mp4", 32, 32, 0), InputError);
}

TEST(RenderOutput, BadSettingsAndOutputsAreInputErrors) {
    TempDir dir;
    EXPECT_THROW(render::renderFrames(column, small(0), dir / "a.png"), InputError);
    render::RenderSettings s = small(1);
    s.stepsPerFrame = 0;
    EXPECT_THROW(render::renderFrames(column, s, dir / "a.png"), InputError);
    EXPECT_THROW(render::renderFrames(column, small(1), dir / "a.gif"), InputError);
    EXPECT_THROW(render::renderFrames(column, small(1), dir / "f_%s.png"), InputError);
    EXPECT_THROW(render::renderFrames(column, small(1), dir / "missing" / "a.png"), InputError);
    EXPECT_THROW(render::renderFrames(column, small(1), dir / "missing" / "f_%d.png"), InputError);
    EXPECT_TRUE(filesIn(dir.path()).empty());
    // A file where the folder (a path without an extension) would be, or one of its parents.
    writeFile(dir / "plain", "x");
    EXPECT_THROW(render::renderFrames(column, small(1), dir / "plain"), InputError);
    EXPECT_THROW(render::renderFrames(column, small(1), dir / "plain" / "frames"), InputError);
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"plain"});
    // The kinds written are named for an unknown extension.
    try {
        render::renderFrames(column, small(1), dir / "a.jpg");
        ADD_FAILURE() << "a.jpg was accepted";
    } catch (const InputError& e) {
        const std::string m = e.what();
        for (const char* part : {"a.jpg", "\".jpg\"", ".mp4", ".png", "frame_%05d.png", "folder"})
            EXPECT_NE(m.find(part), std::string::npos) << part << " in " << m;
    }
}

TEST(RenderOutput, AFailedSequenceLeavesNothingBehind) {
    TempDir dir;
    // Fails after the second image has been written.
    render::RenderSettings s = small(4);
    s.progress = [](int done, int) {
        if (done == 2) throw render::RenderError("stopped");
    };
    // A folder made for the run: removed with its frames, and the parents made for it.
    EXPECT_THROW(render::renderFrames(column, s, dir / "a" / "b" / "frames"), render::RenderError);
    EXPECT_TRUE(filesIn(dir.path()).empty());
    // A world that cannot be made: nothing rendered, the folder made removed.
    const render::WorldFactory broken = []() -> World { throw InputError("scene", "broken"); };
    EXPECT_THROW(render::renderFrames(broken, small(1), dir / "c" / "frames"), InputError);
    EXPECT_TRUE(filesIn(dir.path()).empty());
    // An existing folder and a pattern: the folder stays, the frames written go.
    fs::create_directory(dir / "kept");
    writeFile(dir / "kept" / "other.txt", "mine");
    EXPECT_THROW(render::renderFrames(column, s, dir / "kept"), render::RenderError);
    EXPECT_THROW(render::renderFrames(column, s, dir / "kept" / "f_%02d.png"), render::RenderError);
    EXPECT_EQ(filesIn(dir / "kept"), std::vector<std::string>{"other.txt"});
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"kept"});
}

TEST(RenderOutput, CliRenderMakesTheOutFolder) {
    // `ffdaabb render --out DIR`: a path without an extension is a folder, made with its parents.
    TempDir dir;
    const fs::path out = dir / "a" / "new" / "folder";
    const RunResult r =
        runCli({"render", "--scene", "spheres", "--objects", "4", "--frames", "3", "--width", "64",
                "--height", "48", "--quiet", "--out", out.string()});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(filesIn(out),
              (std::vector<std::string>{"frame_00000.png", "frame_00001.png", "frame_00002.png"}));
    const render::Image first = render::readPng(out / "frame_00000.png");
    EXPECT_EQ(first.width, 64);
    EXPECT_EQ(first.height, 48);
    // An unknown extension is still refused, naming it, and nothing is made.
    const RunResult bad = runCli({"render", "--scene", "spheres", "--objects", "4", "--frames", "1",
                                  "--quiet", "--out", (dir / "b" / "x.gif").string()});
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("unknown output kind \".gif\""), std::string::npos) << bad.err;
    EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"a"});
}
