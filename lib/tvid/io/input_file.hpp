#pragma once
// Every file tvid reads (experiments, recordings, recording lists, parameter and reference
// files, fit reports) is read through here: only a regular file, never more than a stated
// size, and once. A FIFO would block forever, /dev/zero would grow without bound, and a
// file read twice (once to parse, once to hash) may have changed between the reads; so
// each is refused or read whole, before any work, with one clear message naming the file.

#include <cstddef>
#include <filesystem>
#include <string>

namespace tvid {

/// The most bytes each kind of input may have. A recording of an hour at 1 kHz and 20
/// channels is about 0.9 GB; experiments and the JSON files are small by nature.
inline constexpr std::size_t kMaxRecordingBytes = std::size_t{1} << 30;    // 1 GiB
inline constexpr std::size_t kMaxExperimentBytes = std::size_t{4} << 20;   // 4 MiB
inline constexpr std::size_t kMaxJsonBytes = std::size_t{64} << 20;        // 64 MiB
inline constexpr std::size_t kMaxListBytes = std::size_t{16} << 20;        // 16 MiB

/// The whole content of `file`. Throws InputError naming the file when it does not exist
/// ("no such WHAT"), is not a regular file (a directory, FIFO, device, socket), is a
/// symbolic link loop, cannot be read, or has more than max_bytes. `what` names the file
/// in messages ("data file", "experiment file").
std::string read_input_file(const std::filesystem::path& file, const std::string& what, std::size_t max_bytes);

/// read_input_file for a file this program wrote and now reads back to continue it
/// (batch.csv and .tvid-batch.json on --resume): the same checks, but not noted as an
/// input of the run, since the run writes it again.
std::string read_earlier_output(const std::filesystem::path& file, const std::string& what, std::size_t max_bytes);

/// Notes `file` as an input of this run, as read_input_file does for every file it reads;
/// for files read later (a batch's recordings, before the first job). Nothing is noted
/// for a file that does not exist. Safe to call from several threads.
void note_input_file(const std::filesystem::path& file, const std::string& what);

/// "the data file rec.csv" when `target` is the same file (device and inode) as one this
/// run has read or noted as input; "" otherwise. Every output file is checked against
/// this before it is written, so a report never replaces a file the run reads.
std::string input_file_at(const std::filesystem::path& target);

/// Why `file` cannot be read as a file: "" for a regular file (or a link to one), else
/// "does not exist", "is a directory", "is a named pipe (FIFO)", "is a device", "is a
/// socket" or "is a symbolic link loop".
std::string not_a_file_reason(const std::filesystem::path& file);

/// "1.5 MB", "2 GB": a byte count for messages.
std::string byte_size_text(double bytes);

}  // namespace tvid
