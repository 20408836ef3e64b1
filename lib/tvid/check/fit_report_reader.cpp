#include "tvid/check/fit_report_reader.hpp"

#include <algorithm>
#include <fstream>

#include "tvid/io/json_file.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

using nlohmann::json;

json read_json_file(const std::filesystem::path& file, const std::string& missing) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) throw InputError(file.string(), 0, "", missing);
    return tvid::read_json_file(file, "report file");
}

void require(const json& j, const std::string& file, const std::string& key, bool (json::*is_kind)() const noexcept,
             const char* kind) {
    std::string path = "/" + key;  // "estimation.pooled" -> "/estimation/pooled"
    std::replace(path.begin(), path.end(), '.', '/');
    const json::json_pointer pointer(path);
    if (!j.contains(pointer)) throw InputError(file, 0, key, "missing: not a tvid fit report");
    if (!(j.at(pointer).*is_kind)()) throw InputError(file, 0, key, std::string("expected ") + kind);
}

}  // namespace

FitReportFiles read_fit_report(const std::filesystem::path& dir) {
    if (!std::filesystem::exists(dir)) throw InputError(dir.string(), 0, "", "no such report directory");
    if (!std::filesystem::is_directory(dir))
        throw InputError(dir.string(), 0, "", "not a directory (give the report directory of tvid fit)");
    FitReportFiles r;
    r.dir = dir;
    r.summary = read_json_file(dir / "summary.json",
                               "missing: not a complete tvid fit report (summary.json is written last)");
    const std::string summary = r.summary_file();
    if (!r.summary.is_object() || r.summary.value("tool", "") != "tvid")
        throw InputError(summary, 0, "tool", "not \"tvid\": not a tvid fit report");
    require(r.summary, summary, "status", &json::is_string, "a string");
    require(r.summary, summary, "cost", &json::is_object, "an object");
    require(r.summary, summary, "optimizer", &json::is_object, "an object");
    for (const char* split : {"estimation", "validation"}) {
        require(r.summary, summary, split, &json::is_object, "an object");
        require(r.summary, summary, std::string(split) + ".pooled", &json::is_object, "an object");
        require(r.summary, summary, std::string(split) + ".windows", &json::is_array, "an array");
    }

    r.params = read_json_file(dir / "params.json", "missing: not a complete tvid fit report");
    const std::string params = r.params_file();
    if (!r.params.is_object()) throw InputError(params, 0, "", "expected a JSON object: not a tvid fit report");
    require(r.params, params, "parameters", &json::is_array, "an array");
    for (const json& p : r.params["parameters"])
        if (!p.is_object() || !p.contains("name") || !p["name"].is_string() || !p.contains("value"))
            throw InputError(params, 0, "parameters", "each entry needs a name and a value");
    return r;
}

}  // namespace tvid
