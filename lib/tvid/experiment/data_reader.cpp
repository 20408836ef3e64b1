#include "tvid/experiment/data_reader.hpp"

#include <algorithm>
#include <cctype>

#include "tvid/io/input_file.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

namespace {

// The crank angle [deg] made cumulative: a wrapped channel (0 … cycle) jumps back by about
// one cycle at every cycle start. Fails unless the result advances at every sample.
std::vector<double> cumulative_crank_angle(const CsvTable& data, const std::string& column, double cycle) {
    const std::vector<double>& raw = data.column(column);
    std::vector<double> a = raw;
    double offset = 0.0;
    for (std::size_t i = 1; i < a.size(); ++i) {
        if (raw[i] < raw[i - 1] - 0.5 * cycle) offset += cycle;  // wrapped into the next cycle
        a[i] = raw[i] + offset;
        if (!(a[i] > a[i - 1]))
            throw InputError(data.file().string(), data.line_of_row(i), "column " + column,
                             "the crank angle does not advance: " + number_text(raw[i]) + " deg after " +
                                 number_text(raw[i - 1]) + " deg");
    }
    return a;
}

// A recording's name labels its windows in the report ("run2: time 0 to 4", a CSV cell).
bool is_recording_name(const std::string& name) {
    return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    });
}

// One recording: `file` under `entry` (data itself for data.file), its time column named
// under `time_holder` (the entry, or data for a time shared by the entries).
RecordingRead read_one_recording(const YamlMap& entry, const YamlMap& time_holder, const std::filesystem::path& folder) {
    RecordingRead r;
    const std::string data_name = entry.text("file");
    r.recording.file = (std::filesystem::path(data_name).is_absolute() ? std::filesystem::path(data_name) : folder / data_name)
                           .lexically_normal();
    const std::filesystem::path& file = r.recording.file;
    if (const std::string why = not_a_file_reason(file); !why.empty())
        entry.fail("file", why == "does not exist" ? "no such data file: " + file.string()
                                                   : "the data file " + file.string() + " " + why + ", not a file");
    r.time_column = time_holder.text("time");
    r.table = CsvTable::read(file);
    r.recording.sha256 = r.table.content_sha256();
    r.recording.where = entry.source().where(entry.node(), entry.path());
    if (!r.table.has_column(r.time_column))
        time_holder.fail("time", "no column '" + r.time_column + "' in " + file.string());
    r.table.require_strictly_increasing(r.time_column);
    if (r.table.rows() < 2) entry.fail("file", "the recording needs at least two samples");
    return r;
}

// data.recordings: a list of { name, file, time }, names unique.
std::vector<RecordingRead> read_recording_entries(const YamlMap& data, const std::filesystem::path& folder) {
    const YAML::Node list = data.get("recordings");
    const std::string path = data.key_path("recordings");
    const YamlSource& src = data.source();
    if (!list.IsSequence())
        src.fail(list, path, "expected a list of recordings, e.g. [ { name: run1, file: run1.csv, time: t } ]");
    if (list.size() == 0) src.fail(list, path, "at least one recording is needed");
    std::vector<RecordingRead> out;
    for (std::size_t k = 0; k < list.size(); ++k) {
        const YamlMap entry(src, list[k], path + "[" + std::to_string(k) + "]");
        entry.allow_only({"name", "file", "time"});
        const std::string name = entry.text("name");
        if (!is_recording_name(name))
            entry.fail("name", "'" + name + "' is not a recording name: use letters, digits, '_', '-' and '.' (it "
                                            "labels the recording's windows in the report)");
        for (const RecordingRead& before : out)
            if (before.recording.name == name) entry.fail("name", "a second recording named '" + name + "'");
        if (!entry.has("file")) entry.fail_missing("file", "(the recording's CSV file)");
        if (!entry.has("time") && !data.has("time"))
            entry.fail_missing("time", "(the time column: give it here, or as data.time for every recording)");
        out.push_back(read_one_recording(entry, entry.has("time") ? entry : data, folder));
        out.back().recording.name = name;
    }
    return out;
}

}  // namespace

double RecordingRead::seconds() const {
    const std::vector<double>& time = table.column(time_column);
    return time.back() - time.front();
}

std::string RecordingRead::phrase() const {
    return recording.name.empty() ? "the recording" : "recording " + recording.name;
}

DataSection read_data_section(const YamlMap& data, const std::filesystem::path& folder) {
    DataSection d;
    d.listed = data.has("recordings");
    if (d.listed) {
        if (data.has("file"))
            data.fail("file", "give data.file (one recording) or data.recordings (several), not both");
        data.allow_only({"recordings", "time", "angle", "angle_node", "cycle_deg"});
        d.recordings = read_recording_entries(data, folder);
    } else {
        data.allow_only({"file", "time", "angle", "angle_node", "cycle_deg"});
        d.recordings.push_back(read_one_recording(data, data, folder));
    }
    if (data.has("cycle_deg")) {
        d.cycle_deg = data.number("cycle_deg");
        if (d.cycle_deg != 360.0 && d.cycle_deg != 720.0)
            data.fail("cycle_deg", "an engine cycle is 720 (four-stroke) or 360 (two-stroke) degrees");
    }
    if (data.has("angle")) {
        d.angle_column = data.text("angle");
        for (RecordingRead& r : d.recordings) {
            if (!r.table.has_column(d.angle_column))
                data.fail("angle", "no column '" + d.angle_column + "' in " + r.recording.file.string());
            r.crank_deg = cumulative_crank_angle(r.table, d.angle_column, d.cycle_deg);
        }
    }
    return d;
}

std::vector<RowSpan> recording_rows(const DataSection& data) {
    std::vector<RowSpan> rows;
    std::size_t next = 0;
    for (const RecordingRead& r : data.recordings) {
        rows.push_back({next, next + r.table.rows()});
        next += r.table.rows();
    }
    return rows;
}

const RecordingRead& shortest_recording(const DataSection& data) {
    return *std::min_element(data.recordings.begin(), data.recordings.end(),
                             [](const RecordingRead& a, const RecordingRead& b) { return a.seconds() < b.seconds(); });
}

}  // namespace tvid
