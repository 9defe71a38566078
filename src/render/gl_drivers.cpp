#include "render/gl_drivers.h"

#if defined(__SANITIZE_ADDRESS__)
#include <dlfcn.h>
#include <link.h>

#include <string_view>
#endif

namespace ffd::render::detail {

void pinGlDrivers() {
#if defined(__SANITIZE_ADDRESS__)
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void*) {
            const std::string_view name = info->dlpi_name ? info->dlpi_name : "";
            if (name.find("/dri/") != std::string_view::npos ||
                name.find("libgallium") != std::string_view::npos)
                // RTLD_NOLOAD: only a module already loaded; RTLD_NODELETE: never unload it.
                dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
            return 0;
        },
        nullptr);
#endif
}

} // namespace ffd::render::detail
