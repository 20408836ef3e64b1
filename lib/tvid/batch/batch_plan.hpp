#pragma once
// The jobs of `tvid batch`: one fit per recording and/or per engine cycle. Each job is
// the batch's experiment with a few more `--set` overrides (data.file, the windows), so
// the loader checks every job exactly as it checks a `tvid fit`.

#include <filesystem>
#include <string>
#include <vector>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

struct BatchJob {
    std::string id;                      ///< recording stem, `cycle-k`, or `stem/cycle-k`
    std::vector<Override> overrides;     ///< applied after the user's --set
};

struct BatchRequest {
    std::vector<std::filesystem::path> recordings;  ///< empty: the experiment's own data.file
    std::string recordings_option = "--data";        ///< the option(s) they came from, for messages
    std::vector<int> cycles;                        ///< empty: the experiment's own windows
    bool validation = true;                         ///< cycles: validate on the next cycle (false: no validation)
};

/// "3-9", "3,5,7" or a mix ("2-4,7"). Throws InputError("--cycles", …) on bad syntax,
/// a negative number, a descending range or a cycle given twice.
std::vector<int> parse_cycle_list(const std::string& text);

/// The regular files matching a shell glob (`recordings/*.csv`), sorted. Throws
/// InputError("--data", …) when nothing matches.
std::vector<std::filesystem::path> expand_recording_glob(const std::string& pattern);

/// One CSV path per line, relative to the list file; blank lines and `#` comments are
/// skipped. Throws InputError naming the list file when it cannot be read or lists nothing.
std::vector<std::filesystem::path> read_recording_list(const std::filesystem::path& list_file);

/// Complete engine cycles of the experiment's recording (cycle 0 … count − 1), 0 without data.angle.
int complete_cycles(const Experiment& experiment);

/// Checks that every cycle, its warm-up and (with validation) the next cycle lie in the
/// experiment's recording. Throws InputError("--cycles", …) otherwise.
void check_cycles_in_recording(const Experiment& experiment, const std::vector<int>& cycles, bool validation);

/// A batch's job is one recording, or one cycle of it: --data and --data-list replace
/// data.file, --cycles count the cycles of the experiment's one recording. An experiment
/// that reads several recordings end to end (data.recordings) is refused with either:
/// InputError("--data" or "--cycles", …) saying so.
void check_batch_of_one_recording(const Experiment& experiment, const BatchRequest& request);

/// Every cycle of every recording, recordings outermost. Throws InputError when there
/// are neither recordings nor cycles, or ("--data", …) when a recording is listed twice.
std::vector<BatchJob> plan_batch_jobs(const BatchRequest& request);

}  // namespace tvid
