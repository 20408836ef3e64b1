#include "tvid/report/report_directory.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

// Why the files already in `dir` are not a tvid report of `experiment`; "" when they are
// (or when there is none): any of the report's files without a summary.json of tvid's
// beside it (foreign_output), or the report of another experiment.
std::string foreign_report(const std::filesystem::path& dir, const std::string& experiment) {
    namespace fs = std::filesystem;
    if (std::string why = foreign_output(dir, fit_report_files(), "summary.json"); !why.empty()) return why;
    std::error_code ec;
    if (!fs::exists(dir / "summary.json", ec)) return "";
    std::ifstream in(dir / "summary.json");
    const nlohmann::json manifest = nlohmann::json::parse(in, nullptr, false);
    const std::string theirs = manifest.is_object() ? manifest.value("experiment", "") : "";
    if (theirs != experiment) return "already holds the fit report of experiment '" + theirs + "'";
    return "";
}

}  // namespace

const std::vector<std::string>& fit_report_files() {
    static const std::vector<std::string> names = {"params.json",  "params.csv", "estimation.csv", "validation.csv",
                                                   "spectra.csv",  "orders.csv", "history.csv",    "starts.csv",
                                                   "summary.json"};
    return names;
}

std::filesystem::path report_directory(const Experiment& ex, const std::string& output_dir) {
    if (!output_dir.empty()) return output_dir;
    if (!ex.report_dir.empty()) return ex.report_dir;
    return std::filesystem::path("results") / ex.name;
}

OutputDirectoryLock prepare_report_directory(const std::filesystem::path& dir, bool force, const std::string& experiment) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw InputError(dir.string(), 0, "", "the report directory is a file");
    // Before summary.json is looked into: a FIFO of that name would block the reading.
    check_output_files(dir, fit_report_files());
    if (!force)
        if (const std::string why = foreign_report(dir, experiment); !why.empty())
            throw InputError(dir.string(), 0, "", why + ": use --force to replace it, or -o for another directory");
    return prepare_output_directory(dir, "report directory", fit_report_files());
}

}  // namespace tvid
