#pragma once
// Several recordings laid end to end in one table (data.recordings), so that the
// simulation and the scoring see one table as for a single file, and each window the span
// of its own recording (its rows: recording_rows). A recording keeps its own time stamps
// when they start after the previous recording's last sample (files cut from one log);
// otherwise its clock is moved to start one sample interval after it, or on to the next
// whole number of the sampled controllers' common period, so that a controller samples at
// multiples of its period on each recording's own clock. Its crank angle
// likewise, by whole cycles, at least a cycle after the previous one's last sample (the
// cylinders and order torques repeat every cycle). No window spans two recordings, and the
// channels are read within their own (channels/recording_spans.hpp).

#include "tvid/experiment/data_reader.hpp"

namespace tvid {

/// Sets ex.data, ex.recordings and ex.crank_angle from `data` (a single recording as
/// read). Refuses (naming the recording's entry) a crank angle moved by whole cycles when
/// an output measures an angle, which would see the move.
void join_recordings(DataSection data, Experiment& ex);

}  // namespace tvid
