#include "tvid/io/output_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "tvid/io/atomic_file.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

OutputDirectoryLock& OutputDirectoryLock::operator=(OutputDirectoryLock&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = other.fd_;
        other.fd_ = -1;
    }
    return *this;
}

OutputDirectoryLock::~OutputDirectoryLock() {
    if (fd_ >= 0) ::close(fd_);  // closing the descriptor releases the lock
}

bool is_leftover_temporary(const std::string& name) {
    const std::string marker = kAtomicTemporaryMarker;
    const auto at = name.rfind(marker);
    if (at == std::string::npos || at == 0 || at + marker.size() == name.size()) return false;
    for (std::size_t i = at + marker.size(); i < name.size(); ++i)
        if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
    return true;
}

namespace {

// The lock file's descriptor, locked, or an InputError naming the run that holds it.
int lock_directory(const std::filesystem::path& dir, const std::string& what) {
    const std::filesystem::path lock_file = dir / ".tvid.lock";
    const int fd = ::open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0)
        throw InputError(dir.string(), 0, "",
                         "the " + what + " is not writable: cannot create its lock file (" + std::strerror(errno) + ")");
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        const int saved = errno;
        char holder[32] = {};
        const ssize_t n = ::pread(fd, holder, sizeof holder - 1, 0);
        ::close(fd);
        if (saved == EWOULDBLOCK) {
            const std::string pid = n > 0 ? std::string(holder, static_cast<std::size_t>(n)) : std::string();
            throw InputError(dir.string(), 0, "",
                             "the " + what + " is in use by another tvid run" +
                                 (pid.empty() ? std::string() : " (process " + pid + ")") +
                                 ": wait for it to finish, or use -o for another directory");
        }
        throw InputError(dir.string(), 0, "", "cannot lock the " + what + " (" + std::strerror(saved) + ")");
    }
    // Who holds it, for the message another run prints.
    const std::string pid = std::to_string(::getpid());
    if (::ftruncate(fd, 0) == 0) {
        [[maybe_unused]] const ssize_t written = ::pwrite(fd, pid.data(), pid.size(), 0);
    }
    return fd;
}

}  // namespace

void check_output_files(const std::filesystem::path& dir, const std::vector<std::string>& files) {
    for (const std::string& name : files) check_output_target(dir / name);
}

std::string foreign_output(const std::filesystem::path& dir, const std::vector<std::string>& files,
                           const std::string& manifest) {
    namespace fs = std::filesystem;
    std::error_code ec;
    std::string first;
    for (const std::string& name : files)
        if (fs::exists(dir / name, ec)) {
            first = name;
            break;
        }
    if (first.empty()) return "";
    if (!fs::exists(dir / manifest, ec))
        return "already holds " + first + ", and no " + manifest + " of tvid's says tvid wrote it";
    // Read aside (not as one of the run's inputs, which it would then refuse to replace);
    // check_output_files has made sure it is a regular file. A manifest of tvid's is small.
    constexpr std::uintmax_t kLargestManifest = 64u << 20;
    const std::uintmax_t size = fs::file_size(dir / manifest, ec);
    if (!ec && size <= kLargestManifest) {
        std::ifstream in(dir / manifest, std::ios::binary);
        const nlohmann::json m = nlohmann::json::parse(in, nullptr, false);
        if (!m.is_discarded() && m.is_object() && m.value("tool", "") == "tvid") return "";
    }
    return "already holds a " + manifest + " that tvid did not write";
}

OutputDirectoryLock prepare_output_directory(const std::filesystem::path& dir, const std::string& what,
                                             const std::vector<std::string>& files, const std::string& manifest,
                                             bool force) {
    namespace fs = std::filesystem;
    const std::string where = dir.string();
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw InputError(where, 0, "", "the " + what + " is a file");
    // Before the manifest is looked into: a FIFO of that name would block the reading.
    check_output_files(dir, files);
    if (!manifest.empty() && !force)
        if (const std::string why = foreign_output(dir, files, manifest); !why.empty())
            throw InputError(where, 0, "", "the " + what + " " + why + ": use --force to replace it, or -o for another directory");
    fs::create_directories(dir, ec);
    if (ec) throw InputError(where, 0, "", "cannot create the " + what + ": " + ec.message());
    const fs::path probe = dir / (".tvid-write-test." + std::to_string(::getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        throw InputError(where, 0, "",
                         "the " + what + " is not writable: cannot create a file in it (" + std::strerror(errno) + ")");
    ::close(fd);
    ::unlink(probe.c_str());
    OutputDirectoryLock lock(lock_directory(dir, what));
    // Under the lock no other run writes here: a tvid temporary file is a killed run's.
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
        if (e.is_regular_file(ec) && is_leftover_temporary(e.path().filename().string())) fs::remove(e.path(), ec);
    return lock;
}

}  // namespace tvid
