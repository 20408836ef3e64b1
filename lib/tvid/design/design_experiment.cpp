#include "tvid/design/design_experiment.hpp"

#include <algorithm>
#include <map>
#include <numeric>

namespace tvid {

namespace {
// The mean of `column` over the first estimation window's samples (a steady start's speed).
double window_mean(const Experiment& ex, const std::string& column) {
    const std::vector<double>& v = ex.data.column(column);
    std::size_t first = 0, last = v.size() - 1;
    if (!ex.estimation.empty()) {
        first = ex.estimation.front().first;
        last = ex.estimation.front().last;
    }
    const std::size_t n = ex.steady.samples > 0 ? std::min(ex.steady.samples, last - first + 1) : last - first + 1;
    return std::accumulate(v.begin() + static_cast<std::ptrdiff_t>(first),
                           v.begin() + static_cast<std::ptrdiff_t>(first + n), 0.0) /
           static_cast<double>(n);
}
}  // namespace

Experiment design_experiment(const Experiment& ex, const DesignSpec& spec, const std::vector<double>& time,
                             const std::vector<double>& input) {
    Experiment d = ex;
    const std::size_t n = time.size();
    // One column per name: the time, each time input at its level (the designed one
    // playing the candidate), each output at zero.
    std::map<std::string, std::vector<double>> columns;
    columns[ex.time_column] = time;
    for (std::size_t k = 0; k < ex.inputs.size(); ++k) {
        if (ex.inputs[k].by_angle) continue;
        if (k == spec.input) continue;
        columns.try_emplace(ex.inputs[k].column, n, spec.levels[k]);
    }
    columns[ex.inputs[spec.input].column] = input;
    for (const ChannelBinding& out : ex.outputs) columns.try_emplace(out.column, n, 0.0);
    if (ex.initial_state == InitialStateKind::steady && !ex.steady.speed_column.empty()) {
        // A column the design plays (a speed source's, the designed input's or a held one)
        // starts at its design level, as the problem reads it (its unit's scale); another
        // column at its recorded mean.
        d.steady.speed = window_mean(ex, ex.steady.speed_column);
        for (std::size_t k = 0; k < ex.inputs.size(); ++k)
            if (!ex.inputs[k].by_angle && ex.inputs[k].column == ex.steady.speed_column) {
                d.steady.speed = spec.levels[k] * ex.inputs[k].scale;
                break;
            }
        d.steady.speed_column.clear();
    }
    std::vector<std::string> names;
    std::vector<std::vector<double>> values;
    for (auto& [name, v] : columns) {
        names.push_back(name);
        values.push_back(std::move(v));
    }
    d.data = CsvTable::from_columns(ex.file.parent_path() / "design", std::move(names), std::move(values));
    ExperimentRecording r;
    r.name = "";
    r.file = d.data.file();
    r.rows = {0, n};
    r.where = spec.where;
    d.recordings = {r};
    d.crank_angle.clear();
    Window w;
    w.label = "design";
    w.start = 0;
    w.first = 0;
    w.last = n - 1;
    w.where = spec.where;
    w.recording = 0;
    d.estimation = {w};
    d.validation.clear();
    d.warmup = 0.0;
    d.warmup_cycles = 0;
    return d;
}

}  // namespace tvid
