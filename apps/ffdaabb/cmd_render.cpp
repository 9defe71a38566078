// ffdaabb render / view: a scene to images or video (headless, EGL), or in a window with
// controls (GLFW + Dear ImGui). Thin layers over ffdaabb_render.
#include "commands.h"
#include "runner.h"

#include "ffdaabb/error.h"

#include <fmt/core.h>

#include <cmath>
#include <sstream>

#ifdef FFD_HAVE_RENDER
#include "ffdaabb/render.h"
#include "ffdaabb/viewer.h"
#endif

namespace ffd::cli {

namespace {

struct RenderCommandOptions {
    std::string scene, mode, out, overlay, camera;
    int objects = 0, frames = 120, width = 1280, height = 720, steps = 1;
    long long seed = -1;
    float fps = 60, azimuth = 30, elevation = 20, fov = 40;
    std::string screenshot;
    bool paused = false, quiet = false;
};

#ifdef FFD_HAVE_RENDER

render::Overlays parseOverlays(const std::string& list) {
    render::Overlays o;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty()) continue;
        if (item == "spheres")
            o.spheres = true;
        else if (item == "boxes")
            o.boxes = true;
        else if (item == "lattice")
            o.lattice = true;
        else if (item == "contacts")
            o.contacts = true;
        else if (item == "all")
            o.spheres = o.boxes = o.lattice = o.contacts = true;
        else
            throw InputError("--overlay",
                             "unknown overlay \"" + item +
                                 "\" (expected spheres, boxes, lattice, contacts or all)");
    }
    return o;
}

// "ex,ey,ez:tx,ty,tz" -> eye and target.
std::optional<render::Camera> parseCamera(const std::string& text, float fov) {
    if (text.empty()) return std::nullopt;
    float v[6];
    char sep = 0;
    std::istringstream in(text);
    bool ok = true;
    for (int i = 0; i < 6 && ok; ++i) {
        ok = bool(in >> v[i]) && std::isfinite(v[i]);
        if (i < 5 && ok) {
            ok = bool(in >> sep) && sep == (i == 2 ? ':' : ',');
        }
    }
    std::string rest;
    if (!ok || (in >> rest))
        throw InputError("--camera", "\"" + text +
                                         "\" is not of the form ex,ey,ez:tx,ty,tz (eye and "
                                         "target, metres)");
    render::Camera c;
    c.eye = {v[0], v[1], v[2]};
    c.target = {v[3], v[4], v[5]};
    c.fovYDegrees = fov;
    return c;
}

void checkCommon(const RenderCommandOptions& o) {
    if (o.width < 16 || o.width > 8192 || o.height < 16 || o.height > 8192)
        throw InputError(
            "--width/--height",
            fmt::format("{}x{} is out of range (expected 16..8192 each)", o.width, o.height));
    if (!(o.fov > 1 && o.fov < 170))
        throw InputError("--fov",
                         fmt::format("{} is out of range (expected 1..170 degrees)", o.fov));
    if (o.steps < 1 || o.steps > 1000)
        throw InputError("--steps", fmt::format("{} is out of range (expected 1..1000)", o.steps));
}

int runRender(const RenderCommandOptions& o) {
    checkCommon(o);
    if (o.out.empty())
        throw InputError("--out", "missing (expected FILE.mp4, a folder, or name_%04d.png)");
    if (o.frames < 1 || o.frames > 100000)
        throw InputError("--frames",
                         fmt::format("{} is out of range (expected 1..100000)", o.frames));
    if (!(o.fps > 0 && o.fps <= 1000))
        throw InputError("--fps", fmt::format("{} is out of range (expected 0..1000)", o.fps));
    const Scene scene = sceneFromOptions(o.scene, o.objects, o.mode, -1, o.seed);
    render::RenderSettings s;
    s.width = o.width, s.height = o.height, s.frames = o.frames, s.stepsPerFrame = o.steps;
    s.fps = o.fps;
    s.camera = parseCamera(o.camera, o.fov);
    s.framing.azimuthDegrees = o.azimuth, s.framing.elevationDegrees = o.elevation;
    s.framing.fovYDegrees = o.fov;
    s.draw.overlays = parseOverlays(o.overlay);
    if (!o.quiet) s.progress = progressBar(scene.name);
    const render::RenderStats r = renderFrames([&] { return buildScene(scene).world; }, s, o.out);
    if (!o.quiet)
        fmt::print(
            "{} frames of {} ({} steps) to {}: simulate {:.1f} s, render {:.1f} s, write {:.1f} s "
            "({})\n",
            r.frames, scene.name, r.steps, o.out, r.simulateSeconds, r.renderSeconds,
            r.writeSeconds, r.context);
    return 0;
}

int runView(const RenderCommandOptions& o) {
    checkCommon(o);
    if (o.frames < 0) throw InputError("--frames", fmt::format("{} must be >= 0", o.frames));
    if (!o.screenshot.empty() && o.frames == 0)
        throw InputError("--screenshot", "needs --frames N (the frame to capture)");
    const Scene scene = sceneFromOptions(o.scene, o.objects, o.mode, -1, o.seed);
    render::ViewerSettings s;
    s.width = o.width, s.height = o.height;
    s.title = "ffdaabb: " + scene.name;
    s.startPaused = o.paused;
    s.stepsPerFrame = o.steps;
    s.camera = parseCamera(o.camera, o.fov);
    s.framing.azimuthDegrees = o.azimuth, s.framing.elevationDegrees = o.elevation;
    s.framing.fovYDegrees = o.fov;
    s.draw.overlays = parseOverlays(o.overlay);
    s.frames = o.frames;
    s.screenshot = o.screenshot;
    // "Drop more objects": five more of the scene's first kind, above the highest body.
    int dropped = 0;
    s.dropObjects = [&scene, &dropped](World& world) {
        const SceneObject& kind = scene.objects.front();
        float top = 0;
        for (BodyId id : world.bodies()) top = std::max(top, world.bounds(id).hi.y);
        for (int i = 0; i < 5; ++i, ++dropped) {
            BodySettings b = kind.body;
            const float angle = 2.39996f * float(dropped);
            b.position = {0.6f * std::cos(angle), top + 1.0f + kind.size * 1.3f * float(i),
                          0.6f * std::sin(angle)};
            b.rotation = Quat::fromAxisAngle({std::sin(angle), 1, std::cos(angle)}, angle);
            world.addBody(sceneObjectMesh(kind, dropped), b);
        }
    };
    const render::ViewerResult r = render::runViewer([&] { return buildScene(scene).world; }, s);
    if (!o.quiet && o.frames > 0)
        fmt::print("{} frames ({} steps), state hash {:016x}{}\n", r.frames, r.steps, r.stateHash,
                   o.screenshot.empty() ? "" : ", screenshot " + o.screenshot);
    return 0;
}

#else

int unavailable(const RenderCommandOptions&) {
    throw InputError("ffdaabb",
                     "this build has no rendering (configure with -DFFD_BUILD_RENDER=ON and "
                     "the packages from scripts/setup.sh)");
}

#endif

void addCommonOptions(CLI::App* cmd, RenderCommandOptions& o) {
    cmd->add_option("--scene", o.scene, "Scene name or .json file")->required();
    cmd->add_option("--objects", o.objects, "Total number of objects (default: the scene's)");
    cmd->add_option("--mode", o.mode, "Collision mode: enhanced, previous, brute or none");
    cmd->add_option("--seed", o.seed, "Layout seed (default: the scene's)");
    cmd->add_option("--width", o.width, "Image or window width in pixels (default 1280)");
    cmd->add_option("--height", o.height, "Image or window height in pixels (default 720)");
    cmd->add_option("--steps", o.steps, "Simulation frames per displayed frame (default 1)");
    cmd->add_option(
        "--overlay", o.overlay,
        "Comma-separated overlays: spheres (bounding spheres), boxes (FFD-AABB), lattice, "
        "contacts, all");
    cmd->add_option("--camera", o.camera,
                    "Fixed camera ex,ey,ez:tx,ty,tz (default: framed automatically)");
    cmd->add_option("--azimuth", o.azimuth, "Automatic framing: azimuth in degrees (default 30)");
    cmd->add_option("--elevation", o.elevation,
                    "Automatic framing: elevation in degrees (default 20)");
    cmd->add_option("--fov", o.fov, "Vertical field of view in degrees (default 40)");
    cmd->add_flag("--quiet", o.quiet, "No progress and no summary");
}

} // namespace

void addRenderCommands(CLI::App& app, Action& action) {
    auto o = std::make_shared<RenderCommandOptions>();
    CLI::App* render = app.add_subcommand(
        "render", "Render a scene to an MP4 video or a PNG sequence, headless (EGL)");
    addCommonOptions(render, *o);
    render->add_option("--frames", o->frames, "Images to produce (default 120)");
    render->add_option("--out", o->out,
                       "FILE.mp4, a folder (frame_00000.png ...), or name_%04d.png");
    render->add_option("--fps", o->fps, "Video frame rate (default 60)");
    auto v = std::make_shared<RenderCommandOptions>();
    v->frames = 0;
    CLI::App* view = app.add_subcommand(
        "view",
        "Interactive viewer (GLFW + Dear ImGui): play, step, modes, overlays, drag objects");
    addCommonOptions(view, *v);
    view->add_option("--frames", v->frames, "Scripted: close after N frames (0: run until closed)");
    view->add_option("--screenshot", v->screenshot, "Scripted: save the last frame to this PNG");
    view->add_flag("--paused", v->paused, "Start paused");
#ifdef FFD_HAVE_RENDER
    render->callback([o, &action] { action = [o] { return runRender(*o); }; });
    view->callback([v, &action] { action = [v] { return runView(*v); }; });
#else
    render->callback([o, &action] { action = [o] { return unavailable(*o); }; });
    view->callback([v, &action] { action = [v] { return unavailable(*v); }; });
#endif
}

} // namespace ffd::cli
