#pragma once
// Every file tvid writes (report files, a batch's files, `-o FILE`, a written reference)
// is written by write_output_file, and nothing else writes or removes one:
// - whole or not at all: the content goes to a temporary name in the same folder, is
//   flushed to disk, and is renamed over the target (rename is atomic on POSIX), so a
//   crash, Ctrl-C or kill never leaves a torn file;
// - only as a plain file name inside the folder it is given (no '/', no "." or ".."), so
//   no name a user chose can lead it elsewhere;
// - only over a regular file: a FIFO, a device (/dev/null), a socket or a directory of
//   that name is refused, never replaced;
// - never over a file the run reads (the experiment, a recording, a parameter file, a
//   reference: io/input_file.hpp notes each one).
// Each refusal is an InputError naming the target (exit status 2).

#include <filesystem>
#include <string>
#include <string_view>

namespace tvid {

/// The temporary file's name is the target's + this + the process id ("params.json.tvid-tmp.4242"):
/// distinct enough that clearing a killed run's leftovers never touches a user's file.
inline constexpr const char* kAtomicTemporaryMarker = ".tvid-tmp.";

/// Writes `content` as the file `name` in the folder `dir` (empty: the current folder).
/// Throws InputError when the target may not be written (check_output_target), and
/// std::runtime_error naming the path when the write itself fails.
void write_output_file(const std::filesystem::path& dir, const std::string& name, std::string_view content);

/// The one file the user named (`-o FILE`, `--write-reference FILE`): write_output_file
/// of its name in its folder.
void write_named_output_file(const std::filesystem::path& file, std::string_view content);

/// Removes the file `name` from `dir` if it is there (a stale file of an earlier report),
/// under the same rules: a target that is not a regular file or is read by this run is
/// refused.
void remove_output_file(const std::filesystem::path& dir, const std::string& name);

/// Throws InputError naming `target` unless write_output_file may write it: it must not
/// be anything but a regular file (a FIFO, a device, a socket, a directory), nor a file
/// this run reads. A target that does not exist yet passes. Commands call it before
/// their work, so that a refusal comes first.
void check_output_target(const std::filesystem::path& target);

/// How a file of one kind that tvid writes is known by its own structure, never by a text
/// found anywhere in it (a user's notes may quote a heading or a JSON key):
/// - `csv_heading`: its first line begins with `text` (a CSV's first headings);
/// - `json_string`: it is one JSON object whose member `text` is a string that begins with
///   `value` ("written_by": "tvid validate");
/// - `json_member`: it is one JSON object with a member `text` ("tvid_batch").
struct WrittenFileMark {
    enum class Form { csv_heading, json_string, json_member };
    Form form = Form::csv_heading;
    std::string_view text;
    std::string_view value;
};

/// Whether the file at `path` has `mark`'s structure (false when it is not a regular file
/// or cannot be read).
bool has_written_file_mark(const std::filesystem::path& path, const WrittenFileMark& mark);

/// Unless `force`, throws InputError naming `target` when it is an existing file without
/// `mark` (has_written_file_mark): a file tvid did not write is replaced only when asked
/// (--force). `what` names the kind for the message ("a simulation CSV"). A target that
/// does not exist passes, when its folder exists (else refused, before the work).
void check_replaceable(const std::filesystem::path& target, bool force, const WrittenFileMark& mark,
                       const std::string& what);

/// Why `name` (of a parameter, output, node or element, as the user chose it) cannot be
/// part of a file or folder name: empty, "." or "..", or holding '/' or '\\'; "" when it
/// is a plain name. The experiment reader refuses such names with this text.
std::string plain_name_problem(const std::string& name);

}  // namespace tvid
