#pragma once
// Several recordings laid end to end in one table (an experiment's data.recordings,
// docs/experiment-format.md): the rows each one holds. A channel is read within its own
// recording: a delay, a slope at a sample or a held end never reaches into the next one,
// so a window of a later recording reads its samples as that recording read alone would.

#include <cstddef>
#include <vector>

namespace tvid {

/// Rows [begin, end) of one recording in the joined table.
struct RowSpan {
    std::size_t begin = 0;
    std::size_t end = 0;
    std::size_t size() const { return end - begin; }
};

/// The mean sample interval of the recordings on the joined clock `time`, leaving out the
/// gaps between them: (last − first time) / (samples − 1) of a single recording.
double mean_sample_interval(const std::vector<double>& time, const std::vector<RowSpan>& recordings);

}  // namespace tvid
