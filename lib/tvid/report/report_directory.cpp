#include "tvid/report/report_directory.hpp"

#include <string>

#include "tvid/io/output_directory.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

OutputDirectoryLock prepare_report_directory(const std::filesystem::path& dir, bool force) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw InputError(dir.string(), 0, "", "the report directory is a file");
    for (const char* name : {"summary.json", "params.json"})
        if (!force && fs::exists(dir / name, ec))
            throw InputError(dir.string(), 0, "",
                             std::string("already holds a fit report (") + name +
                                 "): use --force to replace it, or -o for another directory");
    return prepare_output_directory(dir, "report directory");
}

}  // namespace tvid
