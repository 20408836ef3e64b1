#pragma once
// An output directory made ready before any work is done: created if needed, checked by
// writing a probe file (permission bits do not tell the whole story: read-only mounts,
// ACLs), and cleared of the temporary files (`NAME.tmp.PID`) that write_file_atomically
// leaves behind when a run is killed mid-write.

#include <filesystem>
#include <string>

namespace tvid {

/// Throws InputError (exit status 2) naming `dir` when it is a file, cannot be created or
/// cannot be written; `what` names it in the message (e.g. "report directory").
void prepare_output_directory(const std::filesystem::path& dir, const std::string& what);

/// True for "NAME.tmp.PID", the temporary name of write_file_atomically.
bool is_leftover_temporary(const std::string& file_name);

}  // namespace tvid
