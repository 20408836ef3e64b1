#include "tvid/batch/batch_plan.hpp"

#include <glob.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "tvid/experiment/window_recording.hpp"
#include "tvid/io/input_file.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

[[noreturn]] void fail_cycles(const std::string& what) { throw InputError("--cycles", 0, "", what); }

int parse_cycle_number(const std::string& text, const std::string& whole) {
    if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos)
        fail_cycles("'" + whole + "' is not a cycle list (e.g. 3-9 or 3,5,7)");
    return std::stoi(text);
}

std::string trimmed(const std::string& s) {
    const std::size_t a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

// A path as YAML text: double-quoted, so that ':', '#', '[' … stay part of the name.
std::string yaml_quoted(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + '"';
}

// The path without its extension, relative to `base`.
std::string relative_stem(const std::filesystem::path& p, const std::filesystem::path& base) {
    return (p.lexically_relative(base).parent_path() / p.stem()).generic_string();
}

// The deepest folder that holds every path.
std::filesystem::path common_folder(const std::vector<std::filesystem::path>& paths) {
    std::filesystem::path common = paths.front().parent_path();
    for (const auto& p : paths) {
        const std::filesystem::path folder = p.parent_path();
        std::filesystem::path shared;
        auto a = common.begin();
        auto b = folder.begin();
        for (; a != common.end() && b != folder.end() && *a == *b; ++a, ++b) shared /= *a;
        common = shared;
    }
    return common;
}

bool all_distinct(const std::vector<std::string>& ids) {
    return std::set<std::string>(ids.begin(), ids.end()).size() == ids.size();
}

// File stems as ids; where two recordings share a stem, their paths below the common
// folder (without, then with, the extension) tell them apart.
std::vector<std::string> recording_ids(const std::vector<std::filesystem::path>& paths) {
    std::vector<std::string> ids;
    for (const auto& p : paths) ids.push_back(p.stem().string());
    if (all_distinct(ids)) return ids;
    const std::filesystem::path base = common_folder(paths);
    ids.clear();
    for (const auto& p : paths) ids.push_back(relative_stem(p, base));
    if (all_distinct(ids)) return ids;
    ids.clear();
    for (const auto& p : paths) ids.push_back(p.lexically_relative(base).generic_string());
    return ids;
}

}  // namespace

std::vector<int> parse_cycle_list(const std::string& text) {
    // More jobs than any recording has cycles would only exhaust the memory.
    constexpr long long kMaxCycles = 100000;
    std::vector<int> cycles;
    std::set<int> given;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = text.find(',', start);
        const std::size_t length = comma == std::string::npos ? std::string::npos : comma - start;
        const std::string part = trimmed(text.substr(start, length));
        const std::size_t dash = part.find('-');
        const int first = parse_cycle_number(trimmed(part.substr(0, dash)), text);
        const int last = dash == std::string::npos ? first : parse_cycle_number(trimmed(part.substr(dash + 1)), text);
        if (last < first) fail_cycles("the range " + part + " runs backwards");
        if (static_cast<long long>(last) - first + 1 + static_cast<long long>(cycles.size()) > kMaxCycles)
            fail_cycles("more than " + std::to_string(kMaxCycles) + " cycles");
        for (int k = first; k <= last; ++k) {
            if (!given.insert(k).second) fail_cycles("cycle " + std::to_string(k) + " is given twice");
            cycles.push_back(k);
        }
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return cycles;
}

std::vector<std::filesystem::path> expand_recording_glob(const std::string& pattern) {
    glob_t found{};
    const int status = ::glob(pattern.c_str(), 0, nullptr, &found);
    std::vector<std::filesystem::path> files;
    if (status == 0)
        for (std::size_t i = 0; i < found.gl_pathc; ++i) {
            std::error_code ec;
            if (std::filesystem::is_regular_file(found.gl_pathv[i], ec)) files.emplace_back(found.gl_pathv[i]);
        }
    ::globfree(&found);
    if (files.empty()) throw InputError("--data", 0, "", "no file matches '" + pattern + "'");
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<std::filesystem::path> read_recording_list(const std::filesystem::path& list_file) {
    std::string text = read_input_file(list_file, "recording list", kMaxListBytes);
    if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // a UTF-8 byte-order mark, as editors write
    std::replace(text.begin(), text.end(), '\r', '\n');          // CRLF and lone CR line ends (blank lines are skipped)
    std::istringstream in(text);
    std::vector<std::filesystem::path> files;
    std::string line;
    while (std::getline(in, line)) {
        const std::string name = trimmed(line);
        if (name.empty() || name.front() == '#') continue;
        const std::filesystem::path p(name);
        files.push_back(p.is_absolute() ? p : list_file.parent_path() / p);
    }
    if (files.empty()) throw InputError(list_file.string(), 0, "", "the recording list names no file");
    return files;
}

int complete_cycles(const Experiment& experiment) {
    if (experiment.crank_angle.empty()) return 0;
    const double c = experiment.cycle_deg;
    const double to_deg = 180.0 / std::numbers::pi;
    // As the window reader counts: cycle 0 starts at the first multiple of the cycle at or
    // after the first sample.
    const double first_start = std::ceil(experiment.crank_angle.front() * to_deg / c - 1e-9) * c;
    const double cycles = std::floor((experiment.crank_angle.back() * to_deg - first_start) / c + 1e-9);
    return static_cast<int>(std::min(cycles, 2e9));  // a crank angle of 1e300 deg must not overflow the count
}

void check_cycles_in_recording(const Experiment& experiment, const std::vector<int>& cycles, bool validation) {
    if (experiment.crank_angle.empty())
        fail_cycles("cycle windows need the crank-angle channel: give data.angle in " + experiment.file.string());
    const int count = complete_cycles(experiment);
    const std::string holds = count > 0 ? "the recording holds complete cycles 0 … " + std::to_string(count - 1)
                                        : "the recording holds no complete cycle";
    for (int k : cycles)
        if (k >= count) fail_cycles("cycle " + std::to_string(k) + " is outside the data: " + holds);
    for (int k : cycles) {
        if (k < experiment.warmup_cycles)
            fail_cycles("cycle " + std::to_string(k) + " needs a warm-up of " +
                        std::to_string(experiment.warmup_cycles) +
                        " cycle(s) before it: the first usable cycle is " + std::to_string(experiment.warmup_cycles));
        if (validation && k + 1 >= count)
            fail_cycles("cycle " + std::to_string(k) + " is validated on cycle " + std::to_string(k + 1) +
                        ", which is outside the data (" + holds + "); end at " + std::to_string(count - 2) +
                        " or add --no-validation");
    }
}

void check_batch_of_one_recording(const Experiment& experiment, const BatchRequest& request) {
    if (!lists_recordings(experiment)) return;
    std::string names;
    for (const ExperimentRecording& r : experiment.recordings) names += (names.empty() ? "" : ", ") + r.name;
    const std::size_t count = experiment.recordings.size();
    const std::string reads = experiment.file.string() +
                              (count == 1 ? " reads its recording through data.recordings ("
                                          : " reads " + std::to_string(count) + " recordings end to end (data.recordings: ") +
                              names + "): ";
    const std::string instead = "; fit it with tvid fit, or batch an experiment that reads one data.file";
    if (!request.recordings.empty())
        throw InputError(request.recordings_option, 0, "", reads + "a batch fits each recording given with --data or --data-list on its "
                                                 "own, in place of data.file" + instead);
    if (!request.cycles.empty())
        throw InputError("--cycles", 0, "", reads + "a batch of --cycles fits the cycles of one recording" + instead);
}

std::vector<BatchJob> plan_batch_jobs(const BatchRequest& request) {
    if (request.recordings.empty() && request.cycles.empty())
        throw InputError("", 0, "", "nothing to batch: give --data, --data-list or --cycles");
    std::vector<std::filesystem::path> recordings;
    for (const auto& r : request.recordings) {
        const std::filesystem::path p = std::filesystem::absolute(r).lexically_normal();
        if (std::find(recordings.begin(), recordings.end(), p) != recordings.end())
            throw InputError(request.recordings_option, 0, "", r.string() + " is listed twice");
        recordings.push_back(p);
    }
    const std::vector<std::string> ids = recordings.empty() ? std::vector<std::string>{""} : recording_ids(recordings);

    std::vector<BatchJob> jobs;
    for (std::size_t r = 0; r < ids.size(); ++r) {
        BatchJob base{ids[r], {}};
        if (!recordings.empty()) base.overrides.push_back(Override{"data.file", yaml_quoted(recordings[r].string())});
        if (request.cycles.empty()) {
            if (!request.validation) base.overrides.push_back(Override{"windows.validation", "[]"});
            jobs.push_back(base);
            continue;
        }
        for (int k : request.cycles) {
            BatchJob job = base;
            job.id = (base.id.empty() ? "" : base.id + "/") + "cycle-" + std::to_string(k);
            job.overrides.push_back(Override{"windows.estimation", "[ { cycle: " + std::to_string(k) + " } ]"});
            job.overrides.push_back(Override{"windows.validation", request.validation
                                                                        ? "[ { cycle: " + std::to_string(k + 1) + " } ]"
                                                                        : "[]"});
            jobs.push_back(job);
        }
    }
    return jobs;
}

}  // namespace tvid
