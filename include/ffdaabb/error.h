// Errors raised by ffdaabb for bad input (files, scene fields, settings). The simulation step
// itself never throws; everything that reads user input does, with a message that names the
// file, the field and the value, and what was expected.
#pragma once

#include <stdexcept>
#include <string>

namespace ffd {

/// Bad input: a file that cannot be read or parsed, a field with a wrong value, a setting out
/// of range. what() is a complete sentence fit for a user, naming the source (file path or
/// field) first. The CLI maps it to exit status 2.
class InputError : public std::runtime_error {
public:
    InputError(std::string source, const std::string& problem)
        : std::runtime_error(source.empty() ? problem : source + ": " + problem),
          source_(std::move(source)), problem_(problem) {}

    /// The file path or field name the error is about (may be empty).
    const std::string& source() const { return source_; }
    /// The problem, without the source prefix.
    const std::string& problem() const { return problem_; }

private:
    std::string source_;
    std::string problem_;
};

} // namespace ffd
