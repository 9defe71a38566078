#include "ffdaabb/render.h"
#include "render/egl_context.h"

namespace ffd::render {

struct OffscreenRenderer::Impl {
    // Declared in this order so that the renderer's GL objects go before their context.
    detail::EglContext context;
    std::unique_ptr<Renderer> renderer;
    std::string description;
};

OffscreenRenderer::OffscreenRenderer() : impl_(std::make_unique<Impl>()) {
    impl_->renderer = std::make_unique<Renderer>();
    impl_->description = impl_->context.description() + "; GL " + impl_->renderer->glInfo();
}

OffscreenRenderer::~OffscreenRenderer() {
    try {
        impl_->context.makeCurrent();
    } catch (const RenderError&) {
        // Nothing better to do in a destructor: the context goes away with its objects anyway.
    }
    impl_->renderer.reset();
}

Image OffscreenRenderer::render(const World& world, const Camera& camera,
                                const DrawOptions& options, int width, int height) {
    impl_->context.makeCurrent();
    impl_->renderer->draw(world, camera, options, width, height);
    return impl_->renderer->readImage();
}

Image OffscreenRenderer::render(const World& world, const DrawOptions& options, int width,
                                int height) {
    return render(world, frameWorld(world, float(width) / float(std::max(height, 1))), options,
                  width, height);
}

std::string OffscreenRenderer::description() const {
    return impl_->description;
}

} // namespace ffd::render
