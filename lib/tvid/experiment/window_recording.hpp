#pragma once
// A window's recording as the reports show it (data.recordings): its name, and a sample's
// time and crank angle on that recording's own clock and channel rather than on the table
// the recordings are joined in (experiment/recording_join.hpp). With data.file the
// recording has no name and the values are as they are.

#include <string>
#include <vector>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// The rows of each recording in Experiment::data, in order (the whole table as one when
/// the experiment names none).
std::vector<RowSpan> recording_spans(const Experiment& ex);

/// True when the experiment reads data.recordings: its windows name their recordings.
bool lists_recordings(const Experiment& ex);

/// The name of window w's recording; empty for data.file.
const std::string& recording_name(const Experiment& ex, const Window& w);

/// Time t [s] of the joined table on w's recording's own clock.
double recording_time(const Experiment& ex, const Window& w, double t);

/// Crank angle [deg] of the joined channel as w's recording's own channel reads it (unwrapped).
double recording_angle_deg(const Experiment& ex, const Window& w, double deg);

}  // namespace tvid
