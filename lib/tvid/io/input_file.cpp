#include "tvid/io/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <vector>

#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

// What a file that is not a regular file is, for the message.
std::string kind_of(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
    if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// Closes the descriptor however the read ends.
struct Descriptor {
    int fd;
    ~Descriptor() {
        if (fd >= 0) ::close(fd);
    }
};

// The files this run has read as input, by device and inode (a hard link or another
// spelling of the path is the same file).
struct InputRecord {
    dev_t device;
    ino_t inode;
    std::filesystem::path path;  ///< as it was read
    std::string description;     ///< "the data file rec.csv"
};

struct InputRegistry {
    std::mutex mutex;
    std::vector<InputRecord> files;
};

InputRegistry& input_registry() {
    static InputRegistry registry;
    return registry;
}

void note_input(const struct stat& st, const std::filesystem::path& file, const std::string& what) {
    InputRegistry& r = input_registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    for (const InputRecord& f : r.files)
        if (f.device == st.st_dev && f.inode == st.st_ino) return;
    r.files.push_back(InputRecord{st.st_dev, st.st_ino, file, "the " + what + " " + file.string()});
}

std::string read_file(const std::filesystem::path& file, const std::string& what, std::size_t max_bytes, bool input);

}  // namespace

void note_input_file(const std::filesystem::path& file, const std::string& what) {
    struct stat st {};
    if (::stat(file.c_str(), &st) == 0) note_input(st, file, what);
}

std::string input_file_at(const std::filesystem::path& target) {
    struct stat st {};
    if (::stat(target.c_str(), &st) != 0) return "";
    InputRegistry& r = input_registry();
    const std::lock_guard<std::mutex> lock(r.mutex);
    for (const InputRecord& f : r.files) {
        if (f.device != st.st_dev || f.inode != st.st_ino) continue;
        // Still the file that was read (not a new file that got the inode of one deleted since)?
        struct stat now {};
        if (::stat(f.path.c_str(), &now) == 0 && now.st_dev == f.device && now.st_ino == f.inode) return f.description;
    }
    return "";
}

std::string read_input_file(const std::filesystem::path& file, const std::string& what, std::size_t max_bytes) {
    return read_file(file, what, max_bytes, true);
}

std::string read_earlier_output(const std::filesystem::path& file, const std::string& what, std::size_t max_bytes) {
    return read_file(file, what, max_bytes, false);
}

std::string not_a_file_reason(const std::filesystem::path& file) {
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0) {
        if (errno == ELOOP) return "is a symbolic link loop";
        if (errno == ENOENT || errno == ENOTDIR) return "does not exist";
        return std::string("cannot be read: ") + std::strerror(errno);
    }
    return S_ISREG(st.st_mode) ? std::string() : "is " + kind_of(st.st_mode);
}

std::string byte_size_text(double bytes) {
    const char* units[] = {"bytes", "kB", "MB", "GB", "TB"};
    int u = 0;
    while (bytes >= 1000.0 && u < 4) bytes /= 1000.0, ++u;
    char buf[32];
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
    return buf;
}

namespace {

std::string read_file(const std::filesystem::path& file, const std::string& what, std::size_t max_bytes, bool input) {
    const std::string name = file.string();
    // O_NONBLOCK: opening a FIFO must not wait for a writer (it is refused below).
    const Descriptor d{::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY)};
    if (d.fd < 0) {
        const int err = errno;
        if (err == ENOENT || err == ENOTDIR) throw InputError(name, 0, "", "no such " + what);
        if (err == ELOOP) throw InputError(name, 0, "", "the " + what + " is a symbolic link loop");
        throw InputError(name, 0, "", "cannot open the " + what + ": " + std::strerror(err));
    }
    struct stat st {};
    if (::fstat(d.fd, &st) != 0)
        throw InputError(name, 0, "", "cannot open the " + what + ": " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw InputError(name, 0, "", "the " + what + " is " + kind_of(st.st_mode) + ", not a file");
    if (input) note_input(st, file, what);
    const auto too_large = [&](double bytes) {
        return InputError(name, 0, "", "the " + what + " is " + byte_size_text(bytes) + ", more than the " +
                                           byte_size_text(static_cast<double>(max_bytes)) + " tvid reads");
    };
    if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) throw too_large(static_cast<double>(st.st_size));
    std::string data;
    data.resize(static_cast<std::size_t>(st.st_size) + 1);  // one more: a file that grew is seen
    std::size_t got = 0;
    for (;;) {
        if (got == data.size()) {
            if (data.size() > max_bytes) throw too_large(static_cast<double>(data.size()));
            data.resize(std::min(max_bytes + 1, 2 * data.size() + 4096));
        }
        const ssize_t n = ::read(d.fd, data.data() + got, data.size() - got);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw InputError(name, 0, "", "cannot read the " + what + ": " + std::strerror(errno));
        }
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    if (got > max_bytes) throw too_large(static_cast<double>(got));
    data.resize(got);
    return data;
}

}  // namespace

}  // namespace tvid
