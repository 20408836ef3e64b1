#include "tvid/report/report_directory.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <string>

#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

// "NAME.tmp.PID": a temporary file of write_file_atomically.
bool is_leftover_temporary(const std::string& name) {
    const auto at = name.rfind(".tmp.");
    if (at == std::string::npos || at == 0 || at + 5 == name.size()) return false;
    for (std::size_t i = at + 5; i < name.size(); ++i)
        if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
    return true;
}

}  // namespace

void prepare_report_directory(const std::filesystem::path& dir, bool force) {
    namespace fs = std::filesystem;
    const std::string where = dir.string();
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw InputError(where, 0, "", "the report directory is a file");
    for (const char* name : {"summary.json", "params.json"})
        if (!force && fs::exists(dir / name, ec))
            throw InputError(where, 0, "",
                             std::string("already holds a fit report (") + name +
                                 "): use --force to replace it, or -o for another directory");
    fs::create_directories(dir, ec);
    if (ec) throw InputError(where, 0, "", "cannot create the report directory: " + ec.message());
    // Writable? Try it: permission bits do not tell the whole story (read-only mounts, ACLs).
    const fs::path probe = dir / (".tvid-write-test." + std::to_string(::getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw InputError(where, 0, "", std::string("the report directory is not writable: ") + std::strerror(errno));
    ::close(fd);
    ::unlink(probe.c_str());
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
        if (e.is_regular_file(ec) && is_leftover_temporary(e.path().filename().string())) fs::remove(e.path(), ec);
}

}  // namespace tvid
