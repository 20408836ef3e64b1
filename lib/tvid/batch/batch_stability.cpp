#include "tvid/batch/batch_stability.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace tvid {

namespace {

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string short_value(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.5g", v);
    return buf;
}

// Flags the values whose robust z-score exceeds the threshold.
void flag_outliers(const std::vector<std::string>& ids, const std::vector<double>& values, const std::string& subject,
                   const std::string& describe_prefix, const std::string& unit, std::vector<OutlierJob>& out) {
    std::size_t finite = 0;
    for (double v : values) finite += std::isfinite(v) ? 1 : 0;
    if (finite < kOutlierMinimumJobs) return;
    const std::vector<double> z = robust_z_scores(values);
    const double med = median(values), mad = median_absolute_deviation(values);
    const std::string u = unit.empty() ? "" : " " + unit;
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (!std::isfinite(z[i]) || std::abs(z[i]) <= kOutlierRobustZ) continue;
        char zt[32];
        std::snprintf(zt, sizeof zt, "%+.2f", z[i]);
        out.push_back({ids[i], subject, values[i], med, mad, z[i],
                       describe_prefix + " = " + short_value(values[i]) + u + ", robust z " + zt + " (median " +
                           short_value(med) + u + ", MAD " + short_value(mad) + u + ")"});
    }
}

}  // namespace

BatchStability batch_stability(const BatchColumns& columns, const std::vector<BatchRow>& rows,
                               const std::vector<std::string>& units, const CrossMatrix* cross) {
    BatchStability s;
    std::vector<std::string> ids;
    std::vector<const BatchRow*> ok;
    for (const BatchRow& row : rows)
        if (row.size() > 1 && row[1] == kBatchOk) {
            ids.push_back(row[0]);
            ok.push_back(&row);
        }
    std::vector<OutlierJob> flagged;
    for (std::size_t p = 0; p < columns.parameters().size(); ++p) {
        const std::string& name = columns.parameters()[p];
        const std::string unit = p < units.size() ? units[p] : "";
        std::vector<double> values;
        for (const BatchRow* row : ok) values.push_back(batch_cell_value((*row)[columns.index(name)]));
        s.parameters.push_back({name, unit, stability(values)});
        flag_outliers(ids, values, name, name, unit, flagged);
    }
    if (cross) flag_outliers(cross->jobs, mean_cross_fit(*cross), "mean_cross_fit", "mean cross-validation fit", "%",
                             flagged);
    // Job order, then the order the quantities were judged in.
    for (const std::string& id : ids)
        for (const OutlierJob& o : flagged)
            if (o.id == id) s.outliers.push_back(o);
    return s;
}

std::string parameter_stability_csv(const BatchStability& s) {
    std::string text =
        batch_csv_line({"parameter", "unit", "count", "mean", "std", "cv", "median", "mad", "min", "max", "outliers"});
    for (const ParameterStability& p : s.parameters) {
        std::string outliers;
        for (const OutlierJob& o : s.outliers)
            if (o.subject == p.name) outliers += (outliers.empty() ? "" : ";") + o.id;
        const Stability& t = p.stats;
        text += batch_csv_line({p.name, p.unit, std::to_string(t.count), batch_number(t.mean), batch_number(t.std_dev),
                                batch_number(t.cv), batch_number(t.median), batch_number(t.mad), batch_number(t.min),
                                batch_number(t.max), outliers});
    }
    return text;
}

nlohmann::json parameter_stability_json(const BatchStability& s) {
    nlohmann::json out = nlohmann::json::object();
    for (const ParameterStability& p : s.parameters) {
        const Stability& t = p.stats;
        out[p.name] = {{"unit", p.unit},          {"count", t.count},
                       {"mean", finite_or_null(t.mean)}, {"std", finite_or_null(t.std_dev)},
                       {"cv", finite_or_null(t.cv)},     {"median", finite_or_null(t.median)},
                       {"mad", finite_or_null(t.mad)},   {"min", finite_or_null(t.min)},
                       {"max", finite_or_null(t.max)}};
    }
    return out;
}

nlohmann::json outliers_json(const BatchStability& s) {
    nlohmann::json out = nlohmann::json::array();
    for (const OutlierJob& o : s.outliers)
        out.push_back({{"id", o.id},
                       {"subject", o.subject},
                       {"value", finite_or_null(o.value)},
                       {"median", finite_or_null(o.median)},
                       {"mad", finite_or_null(o.mad)},
                       {"robust_z", finite_or_null(o.z)},
                       {"reason", o.reason}});
    return out;
}

nlohmann::json cross_matrix_json(const CrossMatrix& m) {
    const std::vector<double> mean = mean_cross_fit(m);
    nlohmann::json jobs = nlohmann::json::array();
    double diagonal = 0.0, off = 0.0, worst = std::numeric_limits<double>::quiet_NaN();
    std::size_t n_diagonal = 0, n_off = 0;
    std::vector<double> off_values;  // for the median, which one failing cell cannot drag
    std::string worst_cell;
    for (std::size_t i = 0; i < m.cells.size(); ++i) {
        nlohmann::json own = nlohmann::json::array();
        for (double f : m.cells[i][i].fit_percent) own.push_back(finite_or_null(f));
        jobs.push_back(
            {{"id", m.jobs[i]}, {"own_fit_percent", own}, {"mean_cross_fit_percent", finite_or_null(mean[i])}});
        for (std::size_t j = 0; j < m.cells[i].size(); ++j)
            for (double f : m.cells[i][j].fit_percent) {
                if (!std::isfinite(f)) continue;
                if (i == j) {
                    diagonal += f;
                    ++n_diagonal;
                    continue;
                }
                off += f;
                ++n_off;
                off_values.push_back(f);
                if (!(f >= worst)) {
                    worst = f;
                    worst_cell = m.jobs[i] + " on " + m.jobs[j];
                }
            }
    }
    std::size_t failed = 0;
    for (const auto& row : m.cells)
        for (const CrossCell& c : row) failed += c.ok ? 0 : 1;
    return {{"matrix", "matrix.csv"},
            {"long", "matrix_long.csv"},
            {"jobs", jobs},
            {"outputs", m.outputs},
            {"failed_cells", failed},
            {"diagonal_mean_fit_percent",
             n_diagonal ? finite_or_null(diagonal / static_cast<double>(n_diagonal)) : nullptr},
            {"off_diagonal_mean_fit_percent", n_off ? finite_or_null(off / static_cast<double>(n_off)) : nullptr},
            {"off_diagonal_median_fit_percent", finite_or_null(median(off_values))},
            {"off_diagonal_min_fit_percent", finite_or_null(worst)},
            {"off_diagonal_min_cell", worst_cell}};
}

}  // namespace tvid
