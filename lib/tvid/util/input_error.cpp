#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {
std::string format_input_error(const std::string& file, int line, const std::string& key,
                               const std::string& problem) {
    // Built with append() only: GCC 12 warns falsely (-Wrestrict) on operator+ chains here.
    std::string out;
    if (!file.empty()) {
        out.append(file);
        if (line > 0) out.append(":").append(std::to_string(line));
        out.append(": ");
    }
    if (!key.empty()) out.append(key).append(": ");
    out.append(problem);
    return out;
}
}  // namespace

InputError::InputError(std::string file, int line, std::string key, std::string what_is_wrong)
    : std::runtime_error(format_input_error(file, line, key, what_is_wrong)),
      file_(std::move(file)),
      line_(line),
      key_(std::move(key)),
      problem_(std::move(what_is_wrong)) {}

}  // namespace tvid
