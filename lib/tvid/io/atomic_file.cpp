#include "tvid/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tvid/io/input_file.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const char* what) {
    throw std::runtime_error("cannot write " + path.string() + ": " + what + ": " + std::strerror(errno));
}

bool is_plain_name(const std::string& name) {
    return !name.empty() && name != "." && name != ".." && name.find_first_of("/\\") == std::string::npos &&
           name.find('\0') == std::string::npos;
}

std::filesystem::path target_of(const std::filesystem::path& dir, const std::string& name) {
    if (!is_plain_name(name))
        throw InputError((dir / name).string(), 0, "", "'" + name + "' is not a plain file name: tvid writes only into its folder");
    return dir.empty() ? std::filesystem::path(name) : dir / name;
}

}  // namespace

std::string plain_name_problem(const std::string& name) {
    if (is_plain_name(name)) return "";
    return "'" + name + "' is not a plain name: names become parts of file and folder names (a profile's folder), "
           "so a name may not be empty, '.' or '..', nor hold '/' or '\\'";
}

void check_output_target(const std::filesystem::path& target) {
    const std::string why = not_a_file_reason(target);
    if (!why.empty() && why != "does not exist")
        throw InputError(target.string(), 0, "",
                         why + ": tvid writes only regular files, and replaces nothing else; give a file name");
    if (const std::string input = input_file_at(target); !input.empty())
        throw InputError(target.string(), 0, "",
                         "is " + input + " that this run reads: tvid never replaces a file it reads; write elsewhere (-o)");
}

bool has_written_file_mark(const std::filesystem::path& path, const WrittenFileMark& mark) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the reading
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    if (mark.form == WrittenFileMark::Form::csv_heading) {
        std::string head(mark.text.size(), '\0');
        in.read(head.data(), static_cast<std::streamsize>(head.size()));
        return in.gcount() == static_cast<std::streamsize>(head.size()) && head == mark.text;
    }
    // A JSON object: read whole, up to the size of the largest report of the kind.
    constexpr std::uintmax_t kLargestMarkedJson = 256u << 20;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec || size > kLargestMarkedJson) return false;
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) return false;
    const auto it = j.find(std::string(mark.text));
    if (mark.form == WrittenFileMark::Form::json_member) return it != j.end();
    return it != j.end() && it->is_string() && it->get_ref<const std::string&>().rfind(mark.value, 0) == 0;
}

void check_replaceable(const std::filesystem::path& target, bool force, const WrittenFileMark& mark,
                       const std::string& what) {
    check_output_target(target);
    // The folder it goes into must be there before the work, not found missing after it.
    const std::filesystem::path folder = target.parent_path();
    if (std::error_code ec; !folder.empty() && !std::filesystem::is_directory(folder, ec))
        throw InputError(target.string(), 0, "",
                         "its folder " + folder.string() +
                             (std::filesystem::exists(folder, ec) ? " is not a folder" : " does not exist") +
                             ": create it first, or give another name");
    if (force || not_a_file_reason(target) == "does not exist") return;
    if (!has_written_file_mark(target, mark))
        throw InputError(target.string(), 0, "",
                         "exists and is not " + what + " that tvid wrote: give --force to replace it, or another name");
}

void write_output_file(const std::filesystem::path& dir, const std::string& name, std::string_view content) {
    const std::filesystem::path path = target_of(dir, name);
    check_output_target(path);
    const std::filesystem::path tmp = path.string() + kAtomicTemporaryMarker + std::to_string(::getpid());
    // A leftover of this process id (or anything a user put there) goes first; O_EXCL and
    // O_NOFOLLOW then make sure that the file opened is a new regular file, not a FIFO or a
    // link that happens to have the temporary name.
    ::unlink(tmp.c_str());
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) fail(path, "open");
    const char* data = content.data();
    std::size_t left = content.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, data, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int saved = errno;
            ::close(fd);
            ::unlink(tmp.c_str());
            errno = saved;
            fail(path, "write");
        }
        data += n;
        left -= static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0) {
        const int saved = errno;
        ::unlink(tmp.c_str());
        errno = saved;
        fail(path, "flush");
    }
    // Checked again right before the rename: the work between the first check and here
    // may have taken hours.
    try {
        check_output_target(path);
    } catch (...) {
        ::unlink(tmp.c_str());
        throw;
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int saved = errno;
        ::unlink(tmp.c_str());
        errno = saved;
        fail(path, "rename");
    }
}

void write_named_output_file(const std::filesystem::path& file, std::string_view content) {
    write_output_file(file.parent_path(), file.filename().string(), content);
}

void remove_output_file(const std::filesystem::path& dir, const std::string& name) {
    const std::filesystem::path path = target_of(dir, name);
    if (not_a_file_reason(path) == "does not exist") return;
    check_output_target(path);
    std::error_code ec;
    std::filesystem::remove(path, ec);
}

}  // namespace tvid
