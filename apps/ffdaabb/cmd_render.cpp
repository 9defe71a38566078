// ffdaabb render / view: a scene to images or video (headless, EGL), or in a window with
// controls (GLFW + Dear ImGui). Thin layers over ffdaabb_render.
#include "commands.h"
#include "flags.h"
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

// The command line as given: numbers as text, converted and checked by parseValues.
struct RenderCommandOptions {
    SceneFlags scene;
    std::string out, overlay, camera;
    std::string frames = "120", width = "1280", height = "720", steps = "1";
    std::string fps = "60", azimuth = "30", elevation = "20", fov = "40";
    std::string screenshot;
    bool paused = false, quiet = false;
};

// The smallest image (render) or window (view: the viewer's own minimum) and the largest.
int minSize(bool view) {
    return view ? 64 : 16;
}
constexpr int kMaxSize = 8192;

// The numeric flags, converted.
struct RenderValues {
    int frames = 0, width = 0, height = 0, steps = 0;
    float fps = 0, azimuth = 0, elevation = 0, fov = 0;
};

// Every numeric flag of render (`view` false) or view, checked before anything is loaded or
// opened: InputError naming the flag, the value and the range.
RenderValues parseValues(const RenderCommandOptions& o, bool view) {
    RenderValues v;
    v.width = int(parseInteger("--width", o.width, minSize(view), kMaxSize));
    v.height = int(parseInteger("--height", o.height, minSize(view), kMaxSize));
    v.steps = int(parseInteger("--steps", o.steps, 1, 1000));
    v.azimuth = float(parseNumber("--azimuth", o.azimuth, -360, 360, "degrees, -360..360"));
    v.elevation = float(parseNumber("--elevation", o.elevation, -90, 90, "degrees, -90..90"));
    v.fov = float(parseNumber("--fov", o.fov, 1, 170, "degrees, 1..170"));
    if (view) {
        v.frames = int(parseInteger("--frames", o.frames, 0, 10000000));
    } else {
        v.frames = int(parseInteger("--frames", o.frames, 1, 100000));
        v.fps = float(parseNumber("--fps", o.fps, 1, 1000, "frames per second, 1..1000"));
    }
    return v;
}

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
        else if (item == "sleeping")
            o.sleeping = true;
        else if (item == "all")
            o.spheres = o.boxes = o.lattice = o.contacts = o.sleeping = true;
        else
            throw InputError("--overlay", "unknown overlay \"" + item +
                                              "\" (expected spheres, boxes, lattice, contacts, "
                                              "sleeping or all)");
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

int runRender(const RenderCommandOptions& o) {
    const RenderValues v = parseValues(o, false);
    if (o.out.empty())
        throw InputError("--out", "missing (expected FILE.mp4, FILE.png, a folder, or "
                                  "name_%04d.png)");
    render::RenderSettings s;
    s.width = v.width, s.height = v.height, s.frames = v.frames, s.stepsPerFrame = v.steps;
    s.fps = v.fps;
    s.camera = parseCamera(o.camera, v.fov);
    s.framing.azimuthDegrees = v.azimuth, s.framing.elevationDegrees = v.elevation;
    s.framing.fovYDegrees = v.fov;
    s.draw.overlays = parseOverlays(o.overlay);
    const Scene scene = sceneFromFlags(o.scene);
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
    // Every flag is checked before any window is opened; the numeric ones before the scene loads.
    const RenderValues v = parseValues(o, true);
    render::ViewerSettings s;
    s.width = v.width, s.height = v.height;
    s.startPaused = o.paused;
    s.stepsPerFrame = v.steps;
    s.camera = parseCamera(o.camera, v.fov);
    s.framing.azimuthDegrees = v.azimuth, s.framing.elevationDegrees = v.elevation;
    s.framing.fovYDegrees = v.fov;
    s.draw.overlays = parseOverlays(o.overlay);
    s.frames = v.frames;
    s.screenshot = o.screenshot;
    const Scene scene = sceneFromFlags(o.scene);
    if (!o.screenshot.empty() && v.frames == 0)
        throw InputError("--screenshot", "needs --frames N (the frame to capture)");
    s.title = "ffdaabb: " + scene.name;
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
    if (!o.quiet && v.frames > 0)
        fmt::print("{} frames ({} steps), state hash {:016x}{}\n", r.frames, r.steps, r.stateHash,
                   o.screenshot.empty() ? "" : ", screenshot " + o.screenshot);
    return 0;
}

#else

int unavailable(const RenderCommandOptions& o, bool view) {
    parseValues(o, view); // a bad flag is reported as such in every build
    throw InputError("ffdaabb",
                     "this build has no rendering (configure with -DFFD_BUILD_RENDER=ON and "
                     "the packages from scripts/setup.sh)");
}

#endif

void addCommonOptions(CLI::App* cmd, RenderCommandOptions& o, bool view) {
    addSceneFlags(cmd, o.scene, false);
    const char* what = view ? "Window" : "Image";
    cmd->add_option(
        "--width", o.width,
        fmt::format("{} width in pixels, {}..{} (default 1280)", what, minSize(view), kMaxSize));
    cmd->add_option(
        "--height", o.height,
        fmt::format("{} height in pixels, {}..{} (default 720)", what, minSize(view), kMaxSize));
    cmd->add_option("--steps", o.steps,
                    "Simulation frames per displayed frame, 1..1000 (default 1)");
    cmd->add_option(
        "--overlay", o.overlay,
        "Comma-separated overlays: spheres (bounding spheres), boxes (FFD-AABB), lattice, "
        "contacts, sleeping (sleeping bodies grey), all");
    cmd->add_option("--camera", o.camera,
                    "Fixed camera ex,ey,ez:tx,ty,tz (default: framed automatically)");
    cmd->add_option("--azimuth", o.azimuth,
                    "Automatic framing: azimuth in degrees, -360..360 (default 30)");
    cmd->add_option("--elevation", o.elevation,
                    "Automatic framing: elevation in degrees, -90..90 (default 20)");
    cmd->add_option("--fov", o.fov, "Vertical field of view in degrees, 1..170 (default 40)");
    cmd->add_flag("--quiet", o.quiet, "No progress and no summary");
}

} // namespace

void addRenderCommands(CLI::App& app, Action& action) {
    auto o = std::make_shared<RenderCommandOptions>();
    CLI::App* render = app.add_subcommand(
        "render", "Render a scene to an MP4 video or a PNG sequence, headless (EGL)");
    addCommonOptions(render, *o, false);
    render->add_option("--frames", o->frames, "Images to produce, 1..100000 (default 120)");
    render->add_option("--out", o->out,
                       "FILE.mp4 (video), FILE.png (the last frame), name_%04d.png, or a folder "
                       "(a path without an extension, made if missing): frame_00000.png ...");
    render->add_option("--fps", o->fps, "Video frame rate, 1..1000 (default 60)");
    auto v = std::make_shared<RenderCommandOptions>();
    v->frames = "0";
    CLI::App* view = app.add_subcommand(
        "view",
        "Interactive viewer (GLFW + Dear ImGui): play, step, modes, overlays, drag objects");
    addCommonOptions(view, *v, true);
    view->add_option("--frames", v->frames,
                     "Scripted: close after N frames, 0..10000000 (default 0: run until closed)");
    view->add_option("--screenshot", v->screenshot, "Scripted: save the last frame to this PNG");
    view->add_flag("--paused", v->paused, "Start paused");
#ifdef FFD_HAVE_RENDER
    render->callback([o, &action] { action = [o] { return runRender(*o); }; });
    view->callback([v, &action] { action = [v] { return runView(*v); }; });
#else
    render->callback([o, &action] { action = [o] { return unavailable(*o, false); }; });
    view->callback([v, &action] { action = [v] { return unavailable(*v, true); }; });
#endif
}

} // namespace ffd::cli
