// A small viewer program for the render tests, run under xvfb-run:
//   ffdaabb_viewer_probe OUT.png [FRAMES]           scripted mode (runViewer, frames + screenshot)
//   ffdaabb_viewer_probe --drive OUT.png [FRAMES]   drives the controls (mode switch, overlays,
//                                                   pause/step, restart, drop) while it runs
// Prints "frames F steps S hash H" on success.
#include "ffdaabb/error.h"
#include "ffdaabb/viewer.h"
#include "probe_scene.h"

#include <cstdio>
#include <cstdlib>
#include <string>

using namespace ffd;

int main(int argc, char** argv) {
    int arg = 1;
    const bool drive = argc > 1 && std::string(argv[1]) == "--drive";
    if (drive) ++arg;
    if (argc <= arg) {
        std::fprintf(stderr, "usage: %s [--drive] OUT.png [FRAMES]\n", argv[0]);
        return 2;
    }
    const std::string out = argv[arg];
    const int frames = argc > arg + 1 ? std::atoi(argv[arg + 1]) : 60;
    render::ViewerSettings settings;
    settings.width = 800, settings.height = 500;
    settings.title = "ffdaabb viewer probe";
    settings.dropObjects = test::probeDrop;
    settings.draw.overlays.spheres = true;
    try {
        render::ViewerResult r;
        if (!drive) {
            settings.frames = frames;
            settings.screenshot = out;
            r = render::runViewer(test::probeScene, settings);
        } else {
            render::Viewer viewer(test::probeScene, settings);
            int width = 0, height = 0;
            BodyId grabbed;
            float grabY = 0;
            for (int f = 0; f < frames; ++f) {
                if (f == 3) {
                    // Grab the front sphere at its centre and pull it 1.5 m up.
                    viewer.windowSize(width, height);
                    const BodyId front = viewer.world().bodies()[3];
                    const Vec3 c = viewer.world().centreOfMass(front);
                    const Vec3 at = render::projectToPixel(viewer.camera(), width, height, c);
                    const Vec3 to = render::projectToPixel(viewer.camera(), width, height,
                                                           c + Vec3{0, 1.5f, 0});
                    if (!viewer.grab(at.x, at.y)) return 4;
                    viewer.moveGrab(to.x, to.y);
                    grabbed = front;
                    grabY = c.y;
                }
                if (f == 10) viewer.setMode(CollisionMode::Previous);
                if (f == 15) viewer.drawOptions().overlays = {true, true, true, true};
                if (f == 18) {
                    viewer.release();
                    std::printf("lift %.3f\n", viewer.world().centreOfMass(grabbed).y - grabY);
                }
                if (f == 20) viewer.setPlaying(false);
                if (f == 22) viewer.stepOnce();
                if (f == 25) viewer.setPlaying(true), viewer.setMode(CollisionMode::Enhanced);
                if (f == 30) viewer.restart();
                if (f == 35) test::probeDrop(viewer.world());
                if (f == frames - 1) viewer.captureNextFrame();
                if (!viewer.frame()) return 3;
            }
            render::writePng(viewer.lastCapture(), out);
            r.frames = frames;
            r.steps = viewer.world().frame();
            r.stateHash = viewer.world().stateHash();
        }
        std::printf("frames %d steps %llu hash %llu\n", r.frames, (unsigned long long)r.steps,
                    (unsigned long long)r.stateHash);
        return 0;
    } catch (const InputError& e) {
        std::fprintf(stderr, "viewer probe: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "viewer probe: %s\n", e.what());
        return 1;
    }
}
