#include "ffdaabb/error.h"
#include "ffdaabb/render.h"
#include "util/atomic_file.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <string>

namespace ffd::render {

void writePng(const Image& image, const std::filesystem::path& path) {
    if (image.width < 1 || image.height < 1 ||
        image.pixels.size() != size_t(image.width) * size_t(image.height) * 4)
        throw InputError(path.string(), "cannot write an empty or inconsistent image");
    std::vector<uint8_t> png;
    auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<uint8_t>*>(context);
        const auto* bytes = static_cast<const uint8_t*>(data);
        out->insert(out->end(), bytes, bytes + size);
    };
    if (!stbi_write_png_to_func(append, &png, image.width, image.height, 4, image.pixels.data(),
                                image.width * 4))
        throw InputError(path.string(), "PNG encoding failed");
    AtomicFile file(path);
    if (std::fwrite(png.data(), 1, png.size(), file.handle()) != png.size())
        throw InputError(path.string(), "write failed (disk full?)");
    file.commit();
}

Image readPng(const std::filesystem::path& path) {
    int width = 0, height = 0, channels = 0;
    stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 4);
    if (!data) {
        const char* why = stbi_failure_reason();
        throw InputError(path.string(),
                         std::string("cannot read the image: ") + (why ? why : "unknown reason"));
    }
    Image image;
    image.width = width, image.height = height;
    image.pixels.assign(data, data + size_t(width) * size_t(height) * 4);
    stbi_image_free(data);
    return image;
}

} // namespace ffd::render
