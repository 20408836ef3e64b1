#pragma once
// An output directory made ready before any work is done: created if needed, checked by
// writing a probe file (permission bits do not tell the whole story: read-only mounts,
// ACLs), claimed by this run for as long as it writes there (a lock file, so that two
// runs into one directory cannot mix their files), and cleared of the temporary files
// (`NAME.tvid-tmp.PID`) that write_output_file leaves behind when a run is killed
// mid-write.

#include <filesystem>
#include <string>
#include <vector>

namespace tvid {

/// This run's claim on an output directory: an exclusive lock on `DIR/.tvid.lock`, held
/// until the object is destroyed (or the process ends, however it ends).
class OutputDirectoryLock {
public:
    OutputDirectoryLock() = default;
    explicit OutputDirectoryLock(int fd) : fd_(fd) {}
    OutputDirectoryLock(OutputDirectoryLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
    OutputDirectoryLock& operator=(OutputDirectoryLock&& other) noexcept;
    OutputDirectoryLock(const OutputDirectoryLock&) = delete;
    OutputDirectoryLock& operator=(const OutputDirectoryLock&) = delete;
    ~OutputDirectoryLock();
    bool held() const { return fd_ >= 0; }

private:
    int fd_ = -1;
};

/// Throws InputError (exit status 2) naming `dir` when it is a file, cannot be created or
/// cannot be written, or another run holds it; `what` names it in the message (e.g.
/// "report directory"). `files` are the names the run will write there: each is checked
/// first (check_output_target: not a FIFO, device or folder, not a file the run reads), so
/// that such a report is refused before the work rather than half written after it. Keep
/// the returned lock while writing into `dir`.
///
/// With a `manifest` (one of `files`, a JSON document that names the tool), files another
/// program or a person wrote are never replaced silently: unless `force`, it also throws
/// when `dir` holds any of `files` and no manifest of tvid's beside them (foreign_output).
[[nodiscard]] OutputDirectoryLock prepare_output_directory(const std::filesystem::path& dir, const std::string& what,
                                                           const std::vector<std::string>& files = {},
                                                           const std::string& manifest = "", bool force = false);

/// Why the files of `files` already in `dir` are not tvid's: "" when there is none of them,
/// or when `manifest` there is a JSON object with "tool": "tvid"; else what is there (the
/// first of them, or a manifest another program wrote).
std::string foreign_output(const std::filesystem::path& dir, const std::vector<std::string>& files,
                           const std::string& manifest);

/// check_output_target for each of `files` in `dir`.
void check_output_files(const std::filesystem::path& dir, const std::vector<std::string>& files);

/// True for "NAME.tvid-tmp.PID", the temporary name of write_output_file.
bool is_leftover_temporary(const std::string& file_name);

}  // namespace tvid
