#include "render/egl_context.h"

#include "ffdaabb/render.h"
#include "render/gl_drivers.h"

#include <epoxy/egl.h>

#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string_view>
#include <vector>

namespace ffd::render::detail {

namespace {

// eglTerminate ends every context of a display, and EGL hands out one display per platform and
// native display: displays are counted so that the last context alive terminates its display.
std::mutex gDisplayMutex;
std::map<EGLDisplay, int> gDisplayUsers;

bool hasExtension(const char* list, std::string_view name) {
    if (!list) return false;
    std::string_view all(list);
    size_t pos = 0;
    while ((pos = all.find(name, pos)) != std::string_view::npos) {
        const size_t end = pos + name.size();
        if ((pos == 0 || all[pos - 1] == ' ') && (end == all.size() || all[end] == ' '))
            return true;
        pos = end;
    }
    return false;
}

std::string eglErrorName(EGLint e) {
    switch (e) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
        return "EGL_BAD_SURFACE";
    default:
        return "EGL error " + std::to_string(e);
    }
}

struct Candidate {
    std::string platform;
    EGLDisplay display = EGL_NO_DISPLAY;
};

} // namespace

struct EglContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    EGLSurface surface = EGL_NO_SURFACE;
    std::string description;

    // One attempt on one display; returns an empty string on success, else why it failed.
    std::string tryDisplay(const Candidate& c) {
        EGLint major = 0, minor = 0;
        {
            std::lock_guard lock(gDisplayMutex);
            if (!eglInitialize(c.display, &major, &minor))
                return c.platform + ": eglInitialize failed (" + eglErrorName(eglGetError()) + ")";
            ++gDisplayUsers[c.display];
        }
        display = c.display;
        std::string why = createContext();
        if (!why.empty()) {
            release();
            return c.platform + ": " + why;
        }
        const char* vendor = eglQueryString(display, EGL_VENDOR);
        description = "EGL " + std::to_string(major) + "." + std::to_string(minor) + " (" +
                      (vendor ? vendor : "unknown vendor") + "), platform " + c.platform;
        return {};
    }

    std::string createContext() {
        if (!eglBindAPI(EGL_OPENGL_API)) return "no desktop OpenGL (eglBindAPI)";
        const char* ext = eglQueryString(display, EGL_EXTENSIONS);
        const bool surfaceless = hasExtension(ext, "EGL_KHR_surfaceless_context");
        const EGLint configAttributes[] = {EGL_SURFACE_TYPE,
                                           EGL_PBUFFER_BIT,
                                           EGL_RENDERABLE_TYPE,
                                           EGL_OPENGL_BIT,
                                           EGL_RED_SIZE,
                                           8,
                                           EGL_GREEN_SIZE,
                                           8,
                                           EGL_BLUE_SIZE,
                                           8,
                                           EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        if (!eglChooseConfig(display, configAttributes, &config, 1, &count) || count == 0) {
            if (!hasExtension(ext, "EGL_KHR_no_config_context") || !surfaceless)
                return "no OpenGL pbuffer config";
            config = EGL_NO_CONFIG_KHR;
        }
        // Core 3.3 is what the shaders need; no forward-compatible flag, so that lines wider
        // than one pixel stay available.
        const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                            3,
                                            EGL_CONTEXT_MINOR_VERSION,
                                            3,
                                            EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                            EGL_NONE};
        context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
        if (context == EGL_NO_CONTEXT)
            return "no OpenGL 3.3 core context (" + eglErrorName(eglGetError()) + ")";
        if (!surfaceless) {
            const EGLint pbufferAttributes[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
            surface = eglCreatePbufferSurface(display, config, pbufferAttributes);
            if (surface == EGL_NO_SURFACE)
                return "no pbuffer surface (" + eglErrorName(eglGetError()) + ")";
        }
        if (!eglMakeCurrent(display, surface, surface, context))
            return "eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")";
        return {};
    }

    void release() {
        if (display == EGL_NO_DISPLAY) return;
        if (eglGetCurrentContext() == context && context != EGL_NO_CONTEXT)
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
        if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
        surface = EGL_NO_SURFACE, context = EGL_NO_CONTEXT;
        std::lock_guard lock(gDisplayMutex);
        if (--gDisplayUsers[display] == 0) {
            gDisplayUsers.erase(display);
            eglTerminate(display);
        }
        display = EGL_NO_DISPLAY;
    }
};

EglContext::EglContext() : impl_(std::make_unique<Impl>()) {
    const char* forced = std::getenv("FFD_EGL_PLATFORM");
    const std::string only = forced ? forced : "";
    auto wanted = [&](const char* name) { return only.empty() || only == name; };
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);

    // A GPU's own EGL device first (hardware rendering), then Mesa's surfaceless platform,
    // then software devices (llvmpipe again, by another road), then the default display.
    std::vector<Candidate> hardware, software;
    if (wanted("device") && hasExtension(clientExtensions, "EGL_EXT_platform_device") &&
        hasExtension(clientExtensions, "EGL_EXT_device_enumeration") &&
        hasExtension(clientExtensions, "EGL_EXT_device_query")) {
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (eglQueryDevicesEXT(16, devices, &count))
            for (EGLint i = 0; i < count; ++i) {
                const char* ext = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
                const bool isSoftware = hasExtension(ext, "EGL_MESA_device_software");
                (isSoftware ? software : hardware)
                    .push_back(
                        {std::string(isSoftware ? "software " : "") + "device " + std::to_string(i),
                         eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr)});
            }
    }
    std::vector<Candidate> candidates = hardware;
    if (wanted("surfaceless") && hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless"))
        candidates.push_back(
            {"surfaceless", eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                     EGL_DEFAULT_DISPLAY, nullptr)});
    candidates.insert(candidates.end(), software.begin(), software.end());
    if (wanted("default")) candidates.push_back({"default", eglGetDisplay(EGL_DEFAULT_DISPLAY)});

    std::string reasons;
    for (const Candidate& c : candidates) {
        if (c.display == EGL_NO_DISPLAY) {
            reasons += "\n  " + c.platform + ": no display";
            continue;
        }
        const std::string why = impl_->tryDisplay(c);
        if (why.empty()) {
            pinGlDrivers();
            return;
        }
        reasons += "\n  " + why;
    }
    if (candidates.empty()) reasons = "\n  no EGL platform to try (FFD_EGL_PLATFORM=" + only + ")";
    throw RenderError("cannot create a headless OpenGL 3.3 context through EGL:" + reasons);
}

EglContext::~EglContext() {
    impl_->release();
}

void EglContext::makeCurrent() {
    // The bound API is per thread, and eglGetCurrentContext answers for it.
    eglBindAPI(EGL_OPENGL_API);
    if (eglGetCurrentContext() == impl_->context) return;
    if (!eglMakeCurrent(impl_->display, impl_->surface, impl_->surface, impl_->context))
        throw RenderError("eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")");
}

const std::string& EglContext::description() const {
    return impl_->description;
}

} // namespace ffd::render::detail
