// The viewer in a real window: ffdaabb_viewer_probe under xvfb-run (Xvfb + llvmpipe GLX).
#include "ffdaabb/error.h"
#include "ffdaabb/viewer.h"
#include "render_test_util.h"
#include "tools/probe_scene.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <set>
#include <string>

using namespace ffd;
using namespace ffd::test;

namespace {

/// Runs the probe in a fresh X server; the arguments follow the program.
RunResult runProbe(const std::vector<std::string>& args) {
    std::vector<std::string> command = {"xvfb-run", "-a", "-s", "-screen 0 1024x768x24",
                                        FFD_VIEWER_PROBE};
    command.insert(command.end(), args.begin(), args.end());
    return runProgram(command, 120);
}

/// A picture with something in it: many colours, no colour everywhere, bodies (palette
/// colours) and the yellow of the sphere overlay.
void expectNonBlank(const render::Image& img) {
    std::set<uint32_t> colours;
    std::map<uint32_t, int> histogram;
    int bodies = 0, yellow = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const uint8_t* p = img.pixel(x, y);
            const uint32_t key = uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2];
            colours.insert(key);
            ++histogram[key];
            const Hsv c = pixelHsv(p);
            if (isBodyPixel(p) && std::abs(c.h - 53) > 12) ++bodies; // not the overlay's yellow
            if (c.s > 0.6f && c.v > 0.7f && std::abs(c.h - 53) < 8) ++yellow;
        }
    int most = 0;
    for (const auto& [key, n] : histogram) most = std::max(most, n);
    EXPECT_GT(colours.size(), 200u);
    EXPECT_LT(double(most), 0.5 * img.width * img.height);
    EXPECT_GT(bodies, 300);
    EXPECT_GT(yellow, 50);
}

} // namespace

TEST(Viewer, ScriptedRunUnderXvfbWritesTheWindow) {
    ASSERT_TRUE(inPath("xvfb-run"))
        << "xvfb-run is not installed (Debian packages xvfb and xauth): the viewer needs an X "
           "server to be tested";
    TempDir dir;
    const std::string png = (dir / "shot.png").string();
    const RunResult r = runProbe({png, "60"});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    // The viewer stepped the world exactly as a plain loop does.
    World plain = probeScene();
    for (int i = 0; i < 60; ++i) plain.step();
    EXPECT_NE(r.out.find("frames 60 steps 60 hash " + std::to_string(plain.stateHash())),
              std::string::npos)
        << r.out;
    const render::Image img = render::readPng(png);
    EXPECT_EQ(img.width, 800);
    EXPECT_EQ(img.height, 500);
    expectNonBlank(img);
}

TEST(Viewer, ControlsDriveTheWorld) {
    ASSERT_TRUE(inPath("xvfb-run")) << "xvfb-run is not installed (Debian packages xvfb, xauth)";
    TempDir dir;
    const std::string png = (dir / "drive.png").string();
    const RunResult r = runProbe({"--drive", png, "60"});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    // Restarted at frame 30, playing since: 30 steps.
    EXPECT_NE(r.out.find("frames 60 steps 30 "), std::string::npos) << r.out;
    // The grabbed sphere was pulled up while it would otherwise have fallen.
    const size_t lift = r.out.find("lift ");
    ASSERT_NE(lift, std::string::npos) << r.out;
    EXPECT_GT(std::stod(r.out.substr(lift + 5)), 0.2) << r.out;
    expectNonBlank(render::readPng(png));
}

TEST(Viewer, WithoutDisplayFailsWithAMessage) {
    // GLFW reads the display at initialisation, in this process.
    const char* display = std::getenv("DISPLAY");
    const std::string saved = display ? display : "";
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    const std::string savedWayland = wayland ? wayland : "";
    ::unsetenv("DISPLAY");
    ::unsetenv("WAYLAND_DISPLAY");
    try {
        render::Viewer viewer(probeScene, {});
        ADD_FAILURE() << "a window opened without a display";
    } catch (const render::RenderError& e) {
        EXPECT_NE(std::string(e.what()).find("xvfb-run"), std::string::npos) << e.what();
    }
    if (display) ::setenv("DISPLAY", saved.c_str(), 1);
    if (wayland) ::setenv("WAYLAND_DISPLAY", savedWayland.c_str(), 1);
}
