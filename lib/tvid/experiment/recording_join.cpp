#include "tvid/experiment/recording_join.hpp"

#include <cmath>

#include "tvid/experiment/controller_clock.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

namespace {

// A recording moved past what a double holds (time stamps or angles near 1e308 of
// opposite signs) cannot be laid after the previous one.
void require_finite_end(double end, const RecordingRead& r, const std::string& what) {
    if (std::isfinite(end)) return;
    const SourceLocation& where = r.recording.where;
    throw InputError(where.file, where.line, where.key,
                     "its " + what + " lies too far from the previous recording's to lay the two end to end");
}

// Where each recording's clock starts on the joined one: its own time stamps when they
// start after the previous recording's last, else one sample interval (the previous
// recording's last) after it; with sampled controllers, moved on to a whole number of
// their common period (`period`), so that their instants on the joined clock are the
// instants of the recording's own.
std::vector<double> joined_time_offsets(const DataSection& data, double period) {
    std::vector<double> offsets;
    double end = 0.0, last_interval = 0.0;  // the previous recording's on the joined clock
    for (const RecordingRead& r : data.recordings) {
        const std::vector<double>& t = r.table.column(r.time_column);
        double offset = !offsets.empty() && !(t.front() > end) ? end + last_interval - t.front() : 0.0;
        if (offset > 0.0 && period > 0.0) offset = std::ceil(offset / period - 1e-9) * period;
        offsets.push_back(offset);
        end = t.back() + offset;  // offsets are never negative: every moved time stamp is finite when the last is
        require_finite_end(end, r, "time column (" + r.time_column + ")");
        last_interval = t[t.size() - 1] - t[t.size() - 2];
    }
    return offsets;
}

// Each recording's crank angle [deg] likewise, moved by whole cycles, so that a gap of at
// least one cycle lies between two recordings (CrankAngleChannels::end_to_end holds each
// side flat up to its middle).
std::vector<double> joined_angle_offsets(const DataSection& data) {
    std::vector<double> offsets;
    const double cycle = data.cycle_deg;
    double end = 0.0;
    for (const RecordingRead& r : data.recordings) {
        const double first = r.crank_deg.front();
        double offset = 0.0;
        if (!offsets.empty() && !(first >= end + cycle)) offset = std::ceil((end + cycle - first) / cycle) * cycle;
        offsets.push_back(offset);
        end = r.crank_deg.back() + offset;
        require_finite_end(end, r, "crank angle (" + data.angle_column + ")");
    }
    return offsets;
}

// An output that measures an angle compares the model's angles with a column, and a
// crank angle moved by whole cycles moves the model's start angle with it.
void refuse_moved_angle(const DataSection& data, const std::vector<double>& angle_offsets, const Experiment& ex) {
    std::string angle_output;
    for (std::size_t k = 0; k < ex.outputs.size() && angle_output.empty(); ++k)
        if (output_is_angle(ex.network.outputs[static_cast<std::size_t>(ex.output_indices[k])].kind))
            angle_output = ex.outputs[k].model_name;
    if (angle_output.empty()) return;
    for (std::size_t k = 0; k < angle_offsets.size(); ++k) {
        if (angle_offsets[k] == 0.0) continue;
        const SourceLocation& where = data.recordings[k].recording.where;
        throw InputError(where.file, where.line, where.key,
                         "its crank angle (" + data.angle_column + ") starts at " +
                             number_text(data.recordings[k].crank_deg.front()) +
                             " deg, not a cycle past the previous recording's: laid end to end it would move by " +
                             number_text(angle_offsets[k]) + " deg, which the angle output " + angle_output +
                             " would see; give the recordings a crank angle that keeps rising from one to the next");
    }
}

// The columns every recording holds (in the first one's order), end to end; the time
// column, named as in the first recording, from each recording's own, on the joined clock.
CsvTable joined_table(const DataSection& data, const std::vector<double>& time_offsets) {
    const RecordingRead& first = data.recordings.front();
    std::vector<std::string> names;
    std::vector<std::vector<double>> columns;
    for (const std::string& name : first.table.column_names()) {
        const bool time = name == first.time_column;
        bool shared = true;
        for (const RecordingRead& r : data.recordings) shared = shared && (time || r.table.has_column(name));
        if (!shared) continue;
        std::vector<double> joined;
        for (std::size_t k = 0; k < data.recordings.size(); ++k) {
            const RecordingRead& r = data.recordings[k];
            const std::vector<double>& v = r.table.column(time ? r.time_column : name);
            if (time && time_offsets[k] != 0.0) {
                for (double t : v) joined.push_back(t + time_offsets[k]);
            } else {
                joined.insert(joined.end(), v.begin(), v.end());
            }
        }
        names.push_back(name);
        columns.push_back(std::move(joined));
    }
    return CsvTable::from_columns(first.recording.file, std::move(names), std::move(columns));
}

}  // namespace

void join_recordings(DataSection data, Experiment& ex) {
    const std::vector<RowSpan> rows = recording_rows(data);
    const std::vector<double> time_offsets =
        data.listed ? joined_time_offsets(data, common_controller_period(ex.network))
                    : std::vector<double>(data.recordings.size(), 0.0);
    const std::vector<double> angle_offsets = data.listed && !data.angle_column.empty()
                                                  ? joined_angle_offsets(data)
                                                  : std::vector<double>(data.recordings.size(), 0.0);
    refuse_moved_angle(data, angle_offsets, ex);
    ex.recordings.clear();
    ex.crank_angle.clear();
    for (std::size_t k = 0; k < data.recordings.size(); ++k) {
        ExperimentRecording r = data.recordings[k].recording;
        r.rows = rows[k];
        r.time_offset = time_offsets[k];
        r.angle_offset = angle_offsets[k];
        ex.recordings.push_back(std::move(r));
        for (double deg : data.recordings[k].crank_deg) {
            const double moved = angle_offsets[k] == 0.0 ? deg : deg + angle_offsets[k];
            ex.crank_angle.push_back(moved * 3.14159265358979323846 / 180.0);
        }
    }
    ex.data = data.listed ? joined_table(data, time_offsets) : std::move(data.recordings.front().table);
}

}  // namespace tvid
