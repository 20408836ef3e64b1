#include "tvid/io/output_directory.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>

#include "tvid/util/input_error.hpp"

namespace tvid {

bool is_leftover_temporary(const std::string& name) {
    const auto at = name.rfind(".tmp.");
    if (at == std::string::npos || at == 0 || at + 5 == name.size()) return false;
    for (std::size_t i = at + 5; i < name.size(); ++i)
        if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
    return true;
}

void prepare_output_directory(const std::filesystem::path& dir, const std::string& what) {
    namespace fs = std::filesystem;
    const std::string where = dir.string();
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw InputError(where, 0, "", "the " + what + " is a file");
    fs::create_directories(dir, ec);
    if (ec) throw InputError(where, 0, "", "cannot create the " + what + ": " + ec.message());
    const fs::path probe = dir / (".tvid-write-test." + std::to_string(::getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        throw InputError(where, 0, "",
                         "the " + what + " is not writable: cannot create a file in it (" + std::strerror(errno) + ")");
    ::close(fd);
    ::unlink(probe.c_str());
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
        if (e.is_regular_file(ec) && is_leftover_temporary(e.path().filename().string())) fs::remove(e.path(), ec);
}

}  // namespace tvid
