#pragma once
// The `data:` section: one recording (`file:` and `time:`) or several (`recordings:`, a
// list of `{ name, file, time }`), with the keys they share beside it (`angle`,
// `angle_node`, `cycle_deg`, and `time` for entries without their own). Each recording's
// file is read and checked on its own: its time column rising, at least two samples, its
// crank angle advancing (made cumulative). The section readers then check every channel
// against every recording (RecordingRead), and join_recordings lays them end to end.

#include <filesystem>
#include <string>
#include <vector>

#include "tvid/experiment/yaml_reader.hpp"
#include "tvid/io/csv_table.hpp"

namespace tvid {

/// One recording as read, before the join.
struct RecordingRead {
    ExperimentRecording recording;  ///< its name, file, digest and entry (rows and offsets: join_recordings)
    std::string time_column;
    CsvTable table;
    std::vector<double> crank_deg;  ///< its cumulative crank angle [deg], or empty without data.angle
    double seconds() const;         ///< its time span, last minus first time stamp
    /// "the recording" for data.file, "recording NAME" for an entry of data.recordings.
    std::string phrase() const;
};

struct DataSection {
    std::vector<RecordingRead> recordings;  ///< one for data.file
    bool listed = false;                    ///< data.recordings rather than data.file
    std::string angle_column;               ///< data.angle, or empty
    double cycle_deg = 720.0;               ///< data.cycle_deg
};

DataSection read_data_section(const YamlMap& data, const std::filesystem::path& folder);

/// The rows each recording takes in the joined table, in order.
std::vector<RowSpan> recording_rows(const DataSection& data);

/// The recording with the shortest time span (a delay must be shorter than each).
const RecordingRead& shortest_recording(const DataSection& data);

}  // namespace tvid
