// Generators by name, for the CLI and scene files.
#include "ffdaabb/generators.h"
#include "ffdaabb/error.h"

#include <charconv>

namespace ffd {

namespace {

bool parseSuffix(std::string_view spec, std::string_view prefix, int& out) {
    if (spec.substr(0, prefix.size()) != prefix) return false;
    const std::string_view digits = spec.substr(prefix.size());
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), out);
    return ec == std::errc() && end == digits.data() + digits.size();
}

} // namespace

const char* generatorNames() {
    return "sphere, icosphere:N, teapot, teapot:N, letter:A..letter:Z, dragon, box, bowl";
}

TriangleMesh generate(std::string_view spec) {
    TriangleMesh mesh;
    int n = 0;
    if (spec == "sphere")
        mesh = icosphere(2);
    else if (parseSuffix(spec, "icosphere:", n))
        mesh = icosphere(n);
    else if (spec == "teapot")
        mesh = teapot(10);
    else if (parseSuffix(spec, "teapot:", n))
        mesh = teapot(n);
    else if (spec.size() == 8 && spec.substr(0, 7) == "letter:")
        mesh = letter(spec[7]);
    else if (spec == "dragon")
        mesh = dragon();
    else if (spec == "box")
        mesh = box({0.5f, 0.5f, 0.5f});
    else if (spec == "bowl")
        mesh = bowl();
    else
        throw InputError(std::string(spec), std::string("unknown generator (expected one of: ") +
                                                generatorNames() + ")");
    mesh.name = std::string(spec);
    return mesh;
}

const PaperObjectFigures* paperFigures(std::string_view spec) {
    if (spec == "sphere") return &kPaperSphere;
    if (spec == "teapot") return &kPaperTeapot;
    if (spec == "dragon") return &kPaperBuddha;
    if (spec.substr(0, 7) == "letter:" || spec == "alphabet") return &kPaperLetter;
    return nullptr;
}

} // namespace ffd
