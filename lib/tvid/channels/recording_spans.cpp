#include "tvid/channels/recording_spans.hpp"

namespace tvid {

double mean_sample_interval(const std::vector<double>& time, const std::vector<RowSpan>& recordings) {
    if (recordings.size() <= 1) {
        if (time.size() < 2) return 0.0;
        return (time.back() - time.front()) / static_cast<double>(time.size() - 1);
    }
    double span = 0.0, intervals = 0.0;
    for (const RowSpan& r : recordings) {
        if (r.size() < 2) continue;
        span += time[r.end - 1] - time[r.begin];
        intervals += static_cast<double>(r.size() - 1);
    }
    return intervals > 0 ? span / intervals : 0.0;
}

}  // namespace tvid
