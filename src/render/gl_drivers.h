// Keeping the GL driver loaded for LeakSanitizer builds.
#pragma once

namespace ffd::render::detail {

/// In AddressSanitizer builds, marks the loaded Mesa driver modules (dri/, libgallium) as
/// never to be unloaded. The driver keeps process-wide singletons that it frees never, reachable
/// from its globals; when eglTerminate or glfwTerminate unloads it, those globals vanish and
/// LeakSanitizer reports the singletons as leaks with unsymbolisable stacks, which no
/// suppression can match. Kept loaded, they stay reachable and are not reported. A no-op in
/// other builds.
void pinGlDrivers();

} // namespace ffd::render::detail
