// A headless OpenGL 3.3 core context through EGL: no display, no window. The renderer draws
// into its own framebuffer object, so the context needs no surface where EGL allows that
// (EGL_KHR_surfaceless_context), else a 1x1 pbuffer.
#pragma once

#include <memory>
#include <string>

namespace ffd::render::detail {

class EglContext {
public:
    /// Tries, in order: hardware EGL devices (a GPU), Mesa's surfaceless platform, software
    /// EGL devices, the default display. $FFD_EGL_PLATFORM = device | surfaceless | default
    /// keeps only that kind. RenderError listing what each attempt said when none gives a GL
    /// 3.3 core context.
    EglContext();
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    /// Makes the context current on the calling thread.
    void makeCurrent();
    /// E.g. "EGL 1.5 (Mesa Project), platform surfaceless".
    const std::string& description() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace ffd::render::detail
