// The OpenGL 3.3 core renderer. One frame:
//   1. floor: a large quad with a procedural anti-aliased grid (screen-space derivatives), faded
//      into the background with distance so that it has no visible edge;
//   2. planar shadows: the meshes flattened onto the floor along the light (Blinn, "Me and My
//      (Fake) Shadow", IEEE CG&A 1988), blended once per pixel through the stencil buffer;
//   3. meshes: smooth normals recomputed from the deformed vertices, key + fill + hemisphere
//      light, lit in linear space and written gamma-encoded;
//   4. overlay lines, then again faintly where hidden behind meshes;
// all into a framebuffer object, multisampled and resolved into a single-sampled one, or
// single-sampled and smoothed by FXAA on the way (software renderers, where multisampling is
// the dearest part of the frame); that one is read back (headless) or blitted to a window.
#include "ffdaabb/error.h"
#include "ffdaabb/render.h"
#include "render/camera_math.h"
#include "render/scene_geometry.h"
#include "render/shaders.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace ffd::render {

namespace {

using namespace shaders;

GLuint compileShader(GLenum type, const char* source, const char* name) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        glDeleteShader(s);
        throw RenderError(std::string("shader ") + name + " does not compile: " + log);
    }
    return s;
}

GLuint linkProgram(const char* vertex, const char* fragment, const char* name) {
    const GLuint vs = compileShader(GL_VERTEX_SHADER, vertex, name);
    const GLuint fs = compileShader(GL_FRAGMENT_SHADER, fragment, name);
    const GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetProgramInfoLog(p, sizeof log, nullptr, log);
        glDeleteProgram(p);
        throw RenderError(std::string("shader program ") + name + " does not link: " + log);
    }
    return p;
}

void setVec3(GLuint program, const char* name, Vec3 v) {
    glUniform3f(glGetUniformLocation(program, name), v.x, v.y, v.z);
}

void setMat4(GLuint program, const char* name, const detail::Mat4& m) {
    glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, m.m);
}

/// Where a model's triangles sit in the shared index buffer of one draw.
struct IndexRange {
    const void* triangles = nullptr;
    size_t offset = 0, count = 0; // indices
};

/// Where a body's vertices sit in the vertex buffer of one draw.
struct BodyDraw {
    BodyId body;
    bool asleep = false; // drawn grey with Overlays::sleeping
    GLint baseVertex = 0;
    size_t range = 0; // into the draw's IndexRange list
};

struct Target {
    GLuint drawFbo = 0, colour = 0, depth = 0;
    GLuint colourTexture = 0; // instead of `colour` when single-sampled (FXAA reads it)
    GLuint resolveFbo = 0, resolved = 0;
    int width = 0, height = 0, samples = 0;
};

} // namespace

struct Renderer::Impl {
    GLuint meshProgram = 0, shadowProgram = 0, floorProgram = 0, lineProgram = 0;
    GLuint fxaaProgram = 0, emptyVao = 0;
    bool software = false;
    GLuint meshVao = 0, meshVbo = 0, meshIbo = 0;
    GLuint lineVao = 0, lineVbo = 0;
    GLuint floorVao = 0, floorVbo = 0;
    Target target;
    int maxSamples = 1, maxSize = 0;
    float lineWidthRange[2] = {1, 1};

    // Scratch reused between draws.
    std::vector<float> vertexData;
    std::vector<uint32_t> indexData;
    std::vector<Vec3> normals;
    std::vector<IndexRange> ranges;
    std::vector<BodyDraw> draws;
    std::vector<detail::LineVertex> lines;

    Impl() {
        if (!epoxy_is_desktop_gl() || epoxy_gl_version() < 33)
            throw RenderError("the current OpenGL context is not desktop OpenGL 3.3 or newer");
        meshProgram = linkProgram(kMeshVertex, kMeshFragment, "mesh");
        shadowProgram = linkProgram(kShadowVertex, kShadowFragment, "shadow");
        floorProgram = linkProgram(kFloorVertex, kFloorFragment, "floor");
        lineProgram = linkProgram(kLineVertex, kLineFragment, "line");
        fxaaProgram = linkProgram(kFullscreenVertex, kFxaaFragment, "fxaa");
        glGenVertexArrays(1, &emptyVao);
        const char* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        const std::string rendererName = name ? name : "";
        for (const char* cpu : {"llvmpipe", "softpipe", "Software Rasterizer", "SwiftShader"})
            software = software || rendererName.find(cpu) != std::string::npos;

        glGenVertexArrays(1, &meshVao);
        glGenBuffers(1, &meshVbo);
        glGenBuffers(1, &meshIbo);
        glBindVertexArray(meshVao);
        glBindBuffer(GL_ARRAY_BUFFER, meshVbo);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, meshIbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                              reinterpret_cast<const void*>(3 * sizeof(float)));

        glGenVertexArrays(1, &lineVao);
        glGenBuffers(1, &lineVbo);
        glBindVertexArray(lineVao);
        glBindBuffer(GL_ARRAY_BUFFER, lineVbo);
        static_assert(sizeof(detail::LineVertex) == 6 * sizeof(float));
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(detail::LineVertex), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(detail::LineVertex),
                              reinterpret_cast<const void*>(sizeof(Vec3)));

        glGenVertexArrays(1, &floorVao);
        glGenBuffers(1, &floorVbo);
        glBindVertexArray(floorVao);
        glBindBuffer(GL_ARRAY_BUFFER, floorVbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
        glBindVertexArray(0);

        glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
        glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
        glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, lineWidthRange);
        const GLenum error = glGetError();
        if (error != GL_NO_ERROR)
            throw RenderError("OpenGL error " + std::to_string(error) + " while setting up");
    }

    ~Impl() {
        releaseTarget();
        glDeleteProgram(meshProgram);
        glDeleteProgram(shadowProgram);
        glDeleteProgram(floorProgram);
        glDeleteProgram(lineProgram);
        glDeleteProgram(fxaaProgram);
        const GLuint buffers[] = {meshVbo, meshIbo, lineVbo, floorVbo};
        glDeleteBuffers(4, buffers);
        const GLuint arrays[] = {meshVao, lineVao, floorVao, emptyVao};
        glDeleteVertexArrays(4, arrays);
    }

    void releaseTarget() {
        Target& t = target;
        if (t.drawFbo) glDeleteFramebuffers(1, &t.drawFbo);
        if (t.resolveFbo) glDeleteFramebuffers(1, &t.resolveFbo);
        const GLuint rbs[] = {t.colour, t.depth, t.resolved};
        for (GLuint rb : rbs)
            if (rb) glDeleteRenderbuffers(1, &rb);
        if (t.colourTexture) glDeleteTextures(1, &t.colourTexture);
        t = Target{};
    }

    void ensureTarget(int width, int height, int samples) {
        if (width < 1 || height < 1 || width > maxSize || height > maxSize)
            throw InputError("image size", std::to_string(width) + " x " + std::to_string(height) +
                                               " is outside 1 .. " + std::to_string(maxSize));
        samples = std::clamp(samples, 1, std::max(maxSamples, 1));
        Target& t = target;
        if (t.drawFbo && t.width == width && t.height == height && t.samples == samples) return;
        releaseTarget();
        auto storage = [&](GLuint rb, GLenum format, int s) {
            glBindRenderbuffer(GL_RENDERBUFFER, rb);
            if (s > 1)
                glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, format, width, height);
            else
                glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
        };
        glGenRenderbuffers(1, &t.depth);
        glGenRenderbuffers(1, &t.resolved);
        storage(t.depth, GL_DEPTH24_STENCIL8, samples);
        storage(t.resolved, GL_RGBA8, 1);
        glGenFramebuffers(1, &t.drawFbo);
        glBindFramebuffer(GL_FRAMEBUFFER, t.drawFbo);
        if (samples > 1) {
            glGenRenderbuffers(1, &t.colour);
            storage(t.colour, GL_RGBA8, samples);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                      t.colour);
        } else {
            glGenTextures(1, &t.colourTexture);
            glBindTexture(GL_TEXTURE_2D, t.colourTexture);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                         nullptr);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            glBindTexture(GL_TEXTURE_2D, 0);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                                   t.colourTexture, 0);
        }
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                  t.depth);
        const GLenum drawStatus = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        glGenFramebuffers(1, &t.resolveFbo);
        glBindFramebuffer(GL_FRAMEBUFFER, t.resolveFbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  t.resolved);
        const GLenum resolveStatus = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (drawStatus != GL_FRAMEBUFFER_COMPLETE || resolveStatus != GL_FRAMEBUFFER_COMPLETE) {
            releaseTarget();
            throw RenderError("incomplete framebuffer for " + std::to_string(width) + " x " +
                              std::to_string(height) + " with " + std::to_string(samples) +
                              " samples");
        }
        t.width = width, t.height = height, t.samples = samples;
    }

    // Fills the mesh buffers: every body's deformed vertices with fresh smooth normals, and
    // each model's triangles once.
    void uploadMeshes(const World& world) {
        vertexData.clear();
        indexData.clear();
        ranges.clear();
        draws.clear();
        GLint baseVertex = 0;
        for (BodyId b : world.bodies()) {
            const std::span<const Vec3> v = world.vertices(b);
            const std::span<const std::array<uint32_t, 3>> t = world.triangles(b);
            if (v.empty() || t.empty()) continue;
            size_t r = 0;
            while (r < ranges.size() && ranges[r].triangles != t.data()) ++r;
            if (r == ranges.size()) {
                ranges.push_back({t.data(), indexData.size(), t.size() * 3});
                for (const auto& tri : t) indexData.insert(indexData.end(), tri.begin(), tri.end());
            }
            detail::smoothNormals(v, t, normals);
            for (size_t i = 0; i < v.size(); ++i) {
                const float row[6] = {v[i].x,       v[i].y,       v[i].z,
                                      normals[i].x, normals[i].y, normals[i].z};
                vertexData.insert(vertexData.end(), row, row + 6);
            }
            draws.push_back({b, !world.isAwake(b), baseVertex, r});
            baseVertex += GLint(v.size());
        }
        glBindVertexArray(meshVao);
        glBindBuffer(GL_ARRAY_BUFFER, meshVbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertexData.size() * sizeof(float)),
                     vertexData.data(), GL_STREAM_DRAW);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indexData.size() * sizeof(uint32_t)),
                     indexData.data(), GL_STREAM_DRAW);
    }

    void drawBodies(GLuint program, bool colours, BodyId highlight, bool sleeping) {
        glBindVertexArray(meshVao);
        const GLint colour = glGetUniformLocation(program, "uColour");
        for (const BodyDraw& d : draws) {
            if (colours) {
                Vec3 c = bodyColour(d.body);
                if (sleeping && d.asleep) { // its own hue, mostly grey
                    const float grey = 0.299f * c.x + 0.587f * c.y + 0.114f * c.z;
                    c = Vec3{grey, grey, grey} * 0.8f + c * 0.2f;
                }
                if (d.body == highlight) c = c + (Vec3{1, 1, 1} - c) * 0.45f;
                glUniform3f(colour, c.x, c.y, c.z);
            }
            const IndexRange& r = ranges[d.range];
            glDrawElementsBaseVertex(GL_TRIANGLES, GLsizei(r.count), GL_UNSIGNED_INT,
                                     reinterpret_cast<const void*>(r.offset * sizeof(uint32_t)),
                                     d.baseVertex);
        }
    }

    void draw(const World& world, const Camera& camera, const DrawOptions& options, int width,
              int height) {
        Antialiasing aa = options.antialiasing;
        if (aa == Antialiasing::Auto) aa = software ? Antialiasing::Fxaa : Antialiasing::Msaa;
        ensureTarget(width, height, aa == Antialiasing::Msaa ? options.samples : 1);
        const float aspect = float(width) / float(height);
        const detail::Mat4 viewProjection =
            detail::projectionMatrix(camera, aspect) * detail::viewMatrix(camera);
        const Vec3 toLight = normalize(Vec3{0.35f, 1.0f, 0.45f});
        const float viewDistance = std::max(length(camera.target - camera.eye), 1e-3f);
        const float fadeStart = 2.5f * viewDistance, fadeEnd = 7.0f * viewDistance;
        const bool floor = options.floor && world.settings().floor;
        const float floorY = world.settings().floorHeight;

        glBindFramebuffer(GL_FRAMEBUFFER, target.drawFbo);
        glViewport(0, 0, width, height);
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_CULL_FACE);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthMask(GL_TRUE);
        glStencilMask(0xFF);
        glClearColor(options.background.x, options.background.y, options.background.z, 1);
        glClearDepth(1);
        glClearStencil(0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDisable(GL_BLEND);
        glDisable(GL_STENCIL_TEST);
        glEnable(GL_MULTISAMPLE);

        if (options.meshes) uploadMeshes(world);

        if (floor) {
            const float half = fadeEnd * 1.2f;
            const float cx = camera.target.x, cz = camera.target.z;
            const float quad[] = {cx - half, floorY, cz - half, cx + half, floorY, cz - half,
                                  cx - half, floorY, cz + half, cx + half, floorY, cz + half};
            glUseProgram(floorProgram);
            setMat4(floorProgram, "uViewProjection", viewProjection);
            setVec3(floorProgram, "uEye", camera.eye);
            glUniform2f(glGetUniformLocation(floorProgram, "uFade"), fadeStart, fadeEnd);
            setVec3(floorProgram, "uFloorColour", {0.70f, 0.70f, 0.68f});
            setVec3(floorProgram, "uLineColour", {0.42f, 0.42f, 0.42f});
            setVec3(floorProgram, "uBackground", options.background);
            const float spacing =
                options.gridSpacing > 0 ? options.gridSpacing : autoGridSpacing(world);
            glUniform1f(glGetUniformLocation(floorProgram, "uSpacing"), spacing);
            glUniform1i(glGetUniformLocation(floorProgram, "uGrid"), options.grid ? 1 : 0);
            glBindVertexArray(floorVao);
            glBindBuffer(GL_ARRAY_BUFFER, floorVbo);
            glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STREAM_DRAW);
            glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        }

        if (floor && options.shadows && options.meshes && !draws.empty()) {
            // Each floor pixel is darkened once however many triangles cover it: the stencil
            // counts the first and rejects the rest.
            glUseProgram(shadowProgram);
            setMat4(shadowProgram, "uViewProjection", viewProjection);
            setMat4(shadowProgram, "uShadow", detail::planarShadow(toLight, floorY));
            setVec3(shadowProgram, "uEye", camera.eye);
            glUniform2f(glGetUniformLocation(shadowProgram, "uFade"), fadeStart, fadeEnd);
            glUniform1f(glGetUniformLocation(shadowProgram, "uAlpha"), 0.35f);
            glEnable(GL_STENCIL_TEST);
            glStencilFunc(GL_EQUAL, 0, 0xFF);
            glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
            glEnable(GL_BLEND);
            // The target's alpha stays 1: images are opaque.
            glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
            glDepthMask(GL_FALSE);
            glDepthFunc(GL_LEQUAL);
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(-1, -4);
            drawBodies(shadowProgram, false, options.highlight, false);
            glDisable(GL_POLYGON_OFFSET_FILL);
            glDisable(GL_STENCIL_TEST);
            glDisable(GL_BLEND);
            glDepthMask(GL_TRUE);
            glDepthFunc(GL_LESS);
        }

        if (options.meshes && !draws.empty()) {
            glUseProgram(meshProgram);
            setMat4(meshProgram, "uViewProjection", viewProjection);
            setVec3(meshProgram, "uEye", camera.eye);
            setVec3(meshProgram, "uToLight", toLight);
            drawBodies(meshProgram, true, options.highlight, options.overlays.sleeping);
        }

        lines.clear();
        detail::appendOverlayLines(world, options, lines);
        if (!lines.empty()) {
            glBindVertexArray(lineVao);
            glBindBuffer(GL_ARRAY_BUFFER, lineVbo);
            glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lines.size() * sizeof(detail::LineVertex)),
                         lines.data(), GL_STREAM_DRAW);
            glUseProgram(lineProgram);
            setMat4(lineProgram, "uViewProjection", viewProjection);
            glLineWidth(std::clamp(options.lineWidth, lineWidthRange[0], lineWidthRange[1]));
            glDepthMask(GL_FALSE);
            glEnable(GL_BLEND);
            glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
            const GLint alpha = glGetUniformLocation(lineProgram, "uAlpha");
            glUniform1f(alpha, 1.0f);
            glDepthFunc(GL_LEQUAL);
            glDrawArrays(GL_LINES, 0, GLsizei(lines.size()));
            if (options.hiddenOverlays) {
                glUniform1f(alpha, 0.3f);
                glDepthFunc(GL_GREATER);
                glDrawArrays(GL_LINES, 0, GLsizei(lines.size()));
            }
            glDepthFunc(GL_LESS);
            glDisable(GL_BLEND);
            glDepthMask(GL_TRUE);
            glLineWidth(1);
        }

        if (aa == Antialiasing::Fxaa && target.colourTexture) {
            glBindFramebuffer(GL_FRAMEBUFFER, target.resolveFbo);
            glDisable(GL_DEPTH_TEST);
            glDisable(GL_STENCIL_TEST);
            glDisable(GL_BLEND);
            glUseProgram(fxaaProgram);
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D, target.colourTexture);
            glUniform1i(glGetUniformLocation(fxaaProgram, "uImage"), 0);
            glUniform2f(glGetUniformLocation(fxaaProgram, "uTexel"), 1.0f / float(width),
                        1.0f / float(height));
            glBindVertexArray(emptyVao);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glBindTexture(GL_TEXTURE_2D, 0);
        } else {
            glBindFramebuffer(GL_READ_FRAMEBUFFER, target.drawFbo);
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.resolveFbo);
            glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT,
                              GL_NEAREST);
        }
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glBindVertexArray(0);
        glUseProgram(0);
        glDisable(GL_DEPTH_TEST);
        const GLenum error = glGetError();
        if (error != GL_NO_ERROR)
            throw RenderError("OpenGL error " + std::to_string(error) + " while drawing");
    }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}

Renderer::~Renderer() = default;

void Renderer::draw(const World& world, const Camera& camera, const DrawOptions& options, int width,
                    int height) {
    impl_->draw(world, camera, options, width, height);
}

Image Renderer::readImage() {
    const Target& t = impl_->target;
    Image image;
    if (!t.resolveFbo) return image;
    image.width = t.width, image.height = t.height;
    image.pixels.resize(size_t(t.width) * size_t(t.height) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.resolveFbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    // GL's rows start at the bottom.
    const size_t row = size_t(t.width) * 4;
    std::vector<uint8_t> swap(row);
    for (int y = 0; y < t.height / 2; ++y) {
        uint8_t* a = image.pixels.data() + size_t(y) * row;
        uint8_t* b = image.pixels.data() + size_t(t.height - 1 - y) * row;
        std::memcpy(swap.data(), a, row);
        std::memcpy(a, b, row);
        std::memcpy(b, swap.data(), row);
    }
    return image;
}

void Renderer::present(int framebufferWidth, int framebufferHeight) {
    const Target& t = impl_->target;
    if (!t.resolveFbo) return;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.resolveFbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    const bool same = framebufferWidth == t.width && framebufferHeight == t.height;
    glBlitFramebuffer(0, 0, t.width, t.height, 0, 0, framebufferWidth, framebufferHeight,
                      GL_COLOR_BUFFER_BIT, same ? GL_NEAREST : GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

bool Renderer::softwareRenderer() const {
    return impl_->software;
}

std::string Renderer::glInfo() const {
    const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return std::string(version ? version : "?") + ", " + (renderer ? renderer : "?");
}

} // namespace ffd::render
