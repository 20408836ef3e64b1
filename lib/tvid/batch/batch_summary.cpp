#include "tvid/batch/batch_summary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tvid/batch/robust_statistics.hpp"

namespace tvid {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// JSON has no NaN: null instead.
nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json spread_json(const ColumnSpread& s) {
    return {{"count", s.count},         {"mean", number_or_null(s.mean)}, {"std", number_or_null(s.std_dev)},
            {"min", number_or_null(s.min)}, {"max", number_or_null(s.max)}};
}

}  // namespace

ColumnSpread column_spread(const std::vector<std::string>& header, const std::vector<BatchRow>& rows,
                           const std::string& column) {
    ColumnSpread s{column, 0, kNaN, kNaN, kNaN, kNaN};
    const auto at = std::find(header.begin(), header.end(), column);
    if (at == header.end()) return s;
    const auto c = static_cast<std::size_t>(at - header.begin());
    std::vector<double> values;
    for (const BatchRow& row : rows) {
        if (row[1] != kBatchOk) continue;
        const double v = batch_cell_value(row[c]);
        if (std::isfinite(v)) values.push_back(v);
    }
    const Stability spread = stability(values);
    s.count = spread.count;
    if (spread.count == 0) return s;
    s.mean = spread.mean;
    s.std_dev = spread.std_dev;
    s.min = spread.min;
    s.max = spread.max;
    return s;
}

BatchSummary summarize_batch(const BatchColumns& columns, const std::vector<BatchRow>& rows, std::size_t run,
                             double wall_seconds, int threads) {
    BatchSummary s;
    s.jobs = rows.size();
    for (const BatchRow& row : rows) {
        s.ok += row[1] == kBatchOk;
        s.failed += row[1] == kBatchFailed;
        s.bad_input += row[1] == kBatchBadInput;
        const std::string& verdict = row[columns.index("verdict")];
        if (verdict.empty()) continue;  // not fitted
        if (verdict == "clean") ++s.verdict_clean;
        else if (verdict.find("error") != std::string::npos) {
            ++s.verdict_errors;
            s.jobs_with_errors.push_back(row[0]);
        } else ++s.verdict_warnings;
    }
    s.run = run;
    for (const std::string& p : columns.parameters()) s.parameters.push_back(column_spread(columns.header(), rows, p));
    for (const std::string& c : columns.header())
        if (c == "cost" || c.rfind("q_", 0) == 0) s.metrics.push_back(column_spread(columns.header(), rows, c));
    s.wall_seconds = wall_seconds;
    s.jobs_per_second = run > 0 && wall_seconds > 0 ? static_cast<double>(run) / wall_seconds : kNaN;
    s.threads = threads;
    return s;
}

nlohmann::json batch_summary_json(const BatchSummary& summary, const BatchRunContext& context) {
    nlohmann::json parameters = nlohmann::json::object(), metrics = nlohmann::json::object();
    for (const ColumnSpread& p : summary.parameters) parameters[p.column] = spread_json(p);
    for (const ColumnSpread& m : summary.metrics) metrics[m.column] = spread_json(m);
    return {{"tool", "tvid"},
            {"version", context.version},
            {"command", context.command_line},
            {"config", context.experiment},
            {"experiment", context.name},
            {"output_dir", context.output_dir},
            {"jobs", summary.jobs},
            {"ok", summary.ok},
            {"failed", summary.failed},
            {"verdicts", {{"clean", summary.verdict_clean},
                          {"warnings", summary.verdict_warnings},
                          {"errors", summary.verdict_errors},
                          {"jobs_with_errors", summary.jobs_with_errors}}},
            {"bad_input", summary.bad_input},
            {"run", summary.run},
            {"resumed", summary.jobs - summary.run},
            {"threads", summary.threads},
            {"processes", summary.processes},
            {"wall_time_s", summary.wall_seconds},
            {"jobs_per_second", number_or_null(summary.jobs_per_second)},
            {"parameters", parameters},
            {"metrics", metrics}};
}

}  // namespace tvid
