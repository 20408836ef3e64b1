#pragma once
// Bad input (experiment file, CSV, command line) is reported as one line
//   FILE:LINE: key: what is wrong
// and the program exits with status 2.

#include <stdexcept>
#include <string>

namespace tvid {

class InputError : public std::runtime_error {
public:
    /// `file` may be empty (command line), `line` 0 when unknown, `key` the YAML key path
    /// (e.g. "parameters.rho1.min") or a CSV column ("column Tds").
    InputError(std::string file, int line, std::string key, std::string what_is_wrong);

    const std::string& file() const { return file_; }
    int line() const { return line_; }
    const std::string& key() const { return key_; }
    const std::string& problem() const { return problem_; }

private:
    std::string file_;
    int line_;
    std::string key_;
    std::string problem_;
};

}  // namespace tvid
