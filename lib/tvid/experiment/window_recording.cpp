#include "tvid/experiment/window_recording.hpp"

namespace tvid {

namespace {
const ExperimentRecording* recording_of(const Experiment& ex, const Window& w) {
    return w.recording < ex.recordings.size() ? &ex.recordings[w.recording] : nullptr;
}
}  // namespace

std::vector<RowSpan> recording_spans(const Experiment& ex) {
    std::vector<RowSpan> spans;
    for (const ExperimentRecording& r : ex.recordings) spans.push_back(r.rows);
    if (spans.empty()) spans.push_back({0, ex.data.rows()});
    return spans;
}

bool lists_recordings(const Experiment& ex) { return !ex.recordings.empty() && !ex.recordings.front().name.empty(); }

const std::string& recording_name(const Experiment& ex, const Window& w) {
    static const std::string none;
    const ExperimentRecording* r = recording_of(ex, w);
    return r ? r->name : none;
}

double recording_time(const Experiment& ex, const Window& w, double t) {
    const ExperimentRecording* r = recording_of(ex, w);
    return r && r->time_offset != 0.0 ? t - r->time_offset : t;
}

double recording_angle_deg(const Experiment& ex, const Window& w, double deg) {
    const ExperimentRecording* r = recording_of(ex, w);
    return r && r->angle_offset != 0.0 ? deg - r->angle_offset : deg;
}

}  // namespace tvid
