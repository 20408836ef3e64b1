#include "tvid/check/reference_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>

#include "tvid/check/parameter_expression.hpp"
#include "tvid/io/json_file.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

namespace {

using nlohmann::json;
using nlohmann::ordered_json;

constexpr int reference_version = 1;

const std::vector<std::string> top_level_keys = {"tvid_reference", "description", "experiment", "defaults",
                                                 "parameters",     "combinations", "cost",      "estimation",
                                                 "validation",     "status",       "converged", "fields"};
const std::vector<std::string> expectation_keys = {"expected", "rel", "abs", "min", "max"};

bool is_one_of(const std::string& key, const std::vector<std::string>& keys) {
    return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// A JSON number as double; JSON null (how reports write NaN and infinity) as NaN.
double as_double(const json& v) { return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN(); }

json finite_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

// Reads one reference file; every error names the file and the key.
class ReferenceReader {
public:
    explicit ReferenceReader(const std::string& file) : file_(file) {}

    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw InputError(file_, 0, key, what);
    }

    double number(const ordered_json& v, const std::string& key) const {
        if (!v.is_number() || !std::isfinite(v.get<double>())) fail(key, "expected a number");
        return v.get<double>();
    }

    double non_negative(const ordered_json& v, const std::string& key) const {
        const double x = number(v, key);
        if (x < 0) fail(key, "must not be negative");
        return x;
    }

    Tolerance tolerance(const ordered_json& v, const std::string& key) const {
        if (!v.is_object()) fail(key, "expected an object with rel and/or abs");
        Tolerance t;
        for (const auto& [k, x] : v.items()) {
            if (k == "rel") t.rel = non_negative(x, key + ".rel");
            else if (k == "abs") t.abs = non_negative(x, key + ".abs");
            else fail(key + "." + k, "unknown key (known: rel, abs)");
        }
        return t;
    }

    // A number (the expected value, default tolerance), an object {expected, rel, abs,
    // min, max}, or where `allow_equals`, a string or true/false that must match.
    Expectation expectation(const ordered_json& v, const std::string& key, const Tolerance& defaults,
                            bool allow_equals, bool* each_window = nullptr) const {
        Expectation e;
        e.tolerance = defaults;
        if (v.is_number()) {
            e.expected = number(v, key);
            return e;
        }
        if (allow_equals && (v.is_string() || v.is_boolean())) {
            e.equals = v;
            return e;
        }
        if (!v.is_object())
            fail(key, allow_equals ? "expected a number, a string, true/false or an object with expected, min or max"
                                   : "expected a number or an object with expected, min or max");
        std::optional<double> rel, abs;
        for (const auto& [k, x] : v.items()) {
            const std::string sub = key + "." + k;
            if (k == "expected") {
                if (allow_equals && (x.is_string() || x.is_boolean())) e.equals = x;
                else e.expected = number(x, sub);
            } else if (k == "rel") {
                rel = non_negative(x, sub);
            } else if (k == "abs") {
                abs = non_negative(x, sub);
            } else if (k == "min") {
                e.min = number(x, sub);
            } else if (k == "max") {
                e.max = number(x, sub);
            } else if (k == "each_window" && each_window) {
                if (!x.is_boolean()) fail(sub, "expected true or false");
                *each_window = x.get<bool>();
            } else {
                fail(sub, "unknown key (known: " + join_words(expectation_keys) + (each_window ? ", each_window)" : ")"));
            }
        }
        if (!e.expected && !e.min && !e.max && e.equals.is_null()) fail(key, "give expected, min or max");
        if ((rel || abs) && !e.expected) fail(key + (rel ? ".rel" : ".abs"), "a tolerance needs an expected value");
        if (!e.equals.is_null() && (e.min || e.max)) fail(key, "min and max apply to numbers, not to a text or true/false");
        if (e.min && e.max && *e.min > *e.max) fail(key + ".min", "is greater than max");
        if (rel || abs) e.tolerance = Tolerance{rel.value_or(0.0), abs.value_or(0.0)};
        return e;
    }

    // "estimation": {METRIC: check, OUTPUT: {METRIC: check}}.
    void split_block(const ordered_json& v, const std::string& split, const Tolerance& defaults,
                     std::vector<MetricCheck>& out) const {
        if (!v.is_object()) fail(split, "expected an object of metrics (e.g. q_index_percent) or outputs");
        for (const auto& item : v.items()) {
            const std::string& k = item.key();
            const ordered_json& x = item.value();  // not a structured binding: clang 14 cannot capture those
            if (is_one_of(k, reference_metric_names())) {
                out.push_back(metric(x, split, "", k, defaults));
                continue;
            }
            // Not a metric: an output name holding metrics, unless it looks like a misspelled metric.
            const bool looks_like_check =
                x.is_number() || (x.is_object() && std::any_of(expectation_keys.begin(), expectation_keys.end(),
                                                                [&x](const std::string& e) { return x.contains(e); }));
            if (looks_like_check || !x.is_object())
                fail(split + "." + k, "unknown metric (metrics: " + join_words(reference_metric_names()) +
                                          "; or an output name holding metrics)");
            for (const auto& [m, check] : x.items()) {
                if (!is_one_of(m, reference_metric_names()))
                    fail(split + "." + k + "." + m, "unknown metric (metrics: " + join_words(reference_metric_names()) + ")");
                out.push_back(metric(check, split, k, m, defaults));
            }
        }
    }

private:
    MetricCheck metric(const ordered_json& v, const std::string& split, const std::string& output,
                       const std::string& name, const Tolerance& defaults) const {
        MetricCheck m;
        m.split = split;
        m.output = output;
        m.metric = name;
        const std::string key = split + "." + (output.empty() ? "" : output + ".") + name;
        m.expectation = expectation(v, key, defaults, false, &m.each_window);
        return m;
    }

    std::string file_;
};

// The tiny slack keeps a value exactly on the decimal boundary (1.01 against 1 ± 1 %)
// passing despite binary rounding.
double rounding_slack(double x, double y) {
    return 4 * std::numeric_limits<double>::epsilon() * std::max(std::abs(x), std::abs(y));
}

std::string metric_key(const std::string& split, const std::string& output, const std::string& metric) {
    return split + "." + output + "." + metric;
}

// The value at `path` in `j`; throws InputError naming `file` and the dotted key.
const json& field(const json& j, const std::string& file, const std::vector<std::string>& path) {
    const json* v = &j;
    std::string key;
    for (const std::string& p : path) {
        key += (key.empty() ? "" : ".") + p;
        if (!v->is_object() || !v->contains(p)) throw InputError(file, 0, key, "missing: not a tvid fit report");
        v = &(*v)[p];
    }
    return *v;
}

// A metric of one output's block (`path` leads to the block). The largest residual ratio is
// reported in percent (`max_abs_residual_ratio_percent`); a reference or a report from before
// that holds the fraction (`max_abs_residual_ratio`) is converted, so either checks either.
json metric_value(const json& j, const std::string& file, std::vector<std::string> path, const std::string& metric) {
    const json& block = field(j, file, path);
    constexpr const char* kPercent = "max_abs_residual_ratio_percent";
    constexpr const char* kFraction = "max_abs_residual_ratio";
    const bool percent_for_fraction = metric == kFraction && !block.contains(kFraction) && block.contains(kPercent);
    const bool fraction_for_percent = metric == kPercent && !block.contains(kPercent) && block.contains(kFraction);
    if (percent_for_fraction || fraction_for_percent) {
        const json& v = block[percent_for_fraction ? kPercent : kFraction];
        if (!v.is_number()) return v;
        return percent_for_fraction ? v.get<double>() / 100.0 : v.get<double>() * 100.0;
    }
    path.push_back(metric);
    return field(j, file, path);
}

CheckRow make_row(std::string quantity, const Expectation& e, json actual, std::string note = "") {
    CheckRow row;
    row.quantity = std::move(quantity);
    row.expectation = e;
    if (actual.is_number() && !std::isfinite(actual.get<double>())) actual = nullptr;
    row.pass = note.empty() && e.holds(actual);
    row.deviation = e.deviation(actual);
    if (note.empty() && actual.is_null()) note = "not finite";
    row.actual = std::move(actual);
    row.note = std::move(note);
    return row;
}

}  // namespace

const std::vector<std::string>& reference_metric_names() {
    static const std::vector<std::string> names = {"q_index_percent", "fit_percent", "rmse",   "cost_l1",
                                                   "cost_l2",         "e0",          "max_abs_residual_ratio_percent",
                                                   "max_abs_residual_ratio"};
    return names;
}

bool Expectation::holds(const json& actual) const {
    if (!equals.is_null()) return actual == equals;
    if (!actual.is_number()) return false;
    const double x = actual.get<double>();
    if (!std::isfinite(x)) return false;
    if (expected && !(std::abs(x - *expected) <= tolerance.allowed(*expected) + rounding_slack(x, *expected)))
        return false;
    if (min && x < *min) return false;
    if (max && x > *max) return false;
    return true;
}

std::optional<double> Expectation::reference_value(const json& actual) const {
    if (!equals.is_null() || !actual.is_number()) return std::nullopt;
    const double x = actual.get<double>();
    if (expected || !std::isfinite(x)) return expected;
    // The bound that fails, else the nearer one.
    if (min && (x < *min || !max || std::abs(x - *min) <= std::abs(x - *max))) return min;
    return max;
}

std::optional<double> Expectation::deviation(const json& actual) const {
    const std::optional<double> r = reference_value(actual);
    if (!r || *r == 0 || !std::isfinite(actual.get<double>())) return std::nullopt;
    return (actual.get<double>() - *r) / std::abs(*r);
}

Reference parse_reference(const ordered_json& j, const std::string& file) {
    const ReferenceReader reader(file);
    if (!j.is_object()) reader.fail("", "expected a JSON object with \"tvid_reference\": 1");
    if (!j.contains("tvid_reference"))
        reader.fail("tvid_reference", "missing: not a tvid reference file (it starts with \"tvid_reference\": 1)");
    const ordered_json& version = j["tvid_reference"];
    if (!version.is_number_integer() || version.get<int>() != reference_version)
        reader.fail("tvid_reference", "version " + json_text(version, -1) + " is not supported (this tvid reads version 1)");
    for (const auto& [k, v] : j.items())
        if (!is_one_of(k, top_level_keys)) reader.fail(k, "unknown key (known: " + join_words(top_level_keys) + ")");

    Reference r;
    r.file = file;
    if (j.contains("description")) {
        if (!j["description"].is_string()) reader.fail("description", "expected a text");
        r.description = j["description"].get<std::string>();
    }
    if (j.contains("defaults")) r.defaults = reader.tolerance(j["defaults"], "defaults");

    if (j.contains("experiment")) {
        if (!j["experiment"].is_string()) reader.fail("experiment", "expected the experiment name");
        r.fields.push_back({"experiment", "/experiment", reader.expectation(j["experiment"], "experiment", {}, true)});
    }
    if (j.contains("parameters")) {
        if (!j["parameters"].is_object()) reader.fail("parameters", "expected an object {name: check}");
        for (const auto& [name, v] : j["parameters"].items())
            r.parameters.push_back({name, reader.expectation(v, "parameters." + name, r.defaults, false)});
    }
    if (j.contains("combinations")) {
        if (!j["combinations"].is_object()) reader.fail("combinations", "expected an object {\"rho1*k_plus\": check}");
        for (const auto& [text, v] : j["combinations"].items()) {
            try {
                ParameterExpression{text};
            } catch (const std::invalid_argument& e) {
                reader.fail("combinations." + text, e.what());
            }
            r.combinations.push_back({text, reader.expectation(v, "combinations." + text, r.defaults, false)});
        }
    }
    if (j.contains("cost")) r.cost = reader.expectation(j["cost"], "cost", r.defaults, false);
    for (const char* split : {"estimation", "validation"})
        if (j.contains(split)) reader.split_block(j[split], split, r.defaults, r.metrics);
    if (j.contains("status")) {
        if (!j["status"].is_string()) reader.fail("status", "expected \"ok\" or \"failed\"");
        r.fields.push_back({"status", "/status", reader.expectation(j["status"], "status", {}, true)});
    }
    if (j.contains("converged")) {
        if (!j["converged"].is_boolean()) reader.fail("converged", "expected true or false");
        r.fields.push_back({"converged", "/optimizer/converged", reader.expectation(j["converged"], "converged", {}, true)});
    }
    if (j.contains("fields")) {
        if (!j["fields"].is_object()) reader.fail("fields", "expected an object {\"/json/pointer\": check}");
        for (const auto& [pointer, v] : j["fields"].items()) {
            const std::string key = "fields." + pointer;
            try {
                if (pointer.empty()) throw std::invalid_argument("empty");
                json::json_pointer{pointer};
            } catch (const std::exception&) {
                reader.fail(key, "not a JSON pointer into summary.json (e.g. /optimizer/iterations)");
            }
            r.fields.push_back({pointer, pointer, reader.expectation(v, key, r.defaults, true)});
        }
    }
    return r;
}

Reference read_reference(const std::filesystem::path& file) {
    const std::string name = file.string();
    return parse_reference(read_json_file<ordered_json>(file, "reference file"), name);
}

std::size_t CheckResult::failures() const {
    return static_cast<std::size_t>(std::count_if(rows.begin(), rows.end(), [](const CheckRow& r) { return !r.pass; }));
}

CheckResult check_report(const FitReportFiles& report, const Reference& reference) {
    CheckResult result;
    result.report_dir = report.dir.string();
    result.reference_file = reference.file;
    const json& summary = report.summary;
    const std::string summary_file = report.summary_file();

    std::map<std::string, json> values;
    std::vector<std::string> names;
    for (const json& p : field(report.params, report.params_file(), {"parameters"})) {
        values[p["name"].get<std::string>()] = p["value"];
        names.push_back(p["name"].get<std::string>());
    }
    auto parameter = [&](const std::string& name, const std::string& key) -> const json& {
        const auto it = values.find(name);
        if (it == values.end())
            throw InputError(reference.file, 0, key,
                             "no parameter " + name + " in " + report.params_file() + " (parameters: " + join_words(names) + ")");
        return it->second;
    };

    for (const ParameterCheck& c : reference.parameters) {
        const std::string key = "parameters." + c.name;
        result.rows.push_back(make_row(key, c.expectation, parameter(c.name, key)));
    }
    for (const ParameterCheck& c : reference.combinations) {
        const std::string key = "combinations." + c.name;
        const ParameterExpression expression(c.name);
        const double v = expression.evaluate([&](const std::string& n) { return as_double(parameter(n, key)); });
        result.rows.push_back(make_row(key, c.expectation, finite_or_null(v)));
    }
    if (reference.cost) {
        const json& kind = field(summary, summary_file, {"cost", "kind"});
        const std::string label = kind.is_string() ? "cost (" + kind.get<std::string>() + ")" : "cost";
        result.rows.push_back(make_row(label, *reference.cost, field(summary, summary_file, {"cost", "value"})));
    }
    for (const MetricCheck& m : reference.metrics) {
        const json& pooled = field(summary, summary_file, {m.split, "pooled"});
        std::vector<std::string> outputs;
        for (const auto& [name, metrics] : pooled.items()) outputs.push_back(name);
        if (!m.output.empty() && !pooled.contains(m.output))
            throw InputError(reference.file, 0, m.split + "." + m.output,
                             "no output " + m.output + " in " + summary_file + " (outputs: " + join_words(outputs) + ")");
        for (const std::string& out : outputs) {
            if (!m.output.empty() && out != m.output) continue;
            const std::string key = metric_key(m.split, out, m.metric);
            if (!m.each_window) {
                const json& metrics = pooled[out];
                const bool empty = field(metrics, summary_file, {"samples"}) == 0;
                result.rows.push_back(make_row(key, m.expectation, metric_value(summary, summary_file, {m.split, "pooled", out}, m.metric),
                                               empty ? "no samples in " + m.split : ""));
                continue;
            }
            const json& windows = field(summary, summary_file, {m.split, "windows"});
            if (windows.empty()) result.rows.push_back(make_row(key, m.expectation, nullptr, "no " + m.split + " windows"));
            for (const json& w : windows) {
                const std::string label = w.value("window", "?");
                result.rows.push_back(make_row(key + " [" + label + "]", m.expectation,
                                               metric_value(w, summary_file, {"outputs", out}, m.metric)));
            }
        }
    }
    for (const FieldCheck& f : reference.fields) {
        const json::json_pointer pointer(f.pointer);
        if (!summary.contains(pointer))
            throw InputError(reference.file, 0, f.label == f.pointer ? "fields." + f.pointer : f.label,
                             "no field " + f.pointer + " in " + summary_file);
        result.rows.push_back(make_row(f.label, f.expectation, summary.at(pointer)));
    }
    return result;
}

json check_result_json(const CheckResult& result) {
    json rows = json::array();
    for (const CheckRow& r : result.rows) {
        const Expectation& e = r.expectation;
        json row{{"quantity", r.quantity}, {"actual", r.actual}, {"pass", r.pass}, {"note", r.note}};
        row["expected"] = !e.equals.is_null() ? e.equals : e.expected ? json(*e.expected) : json(nullptr);
        row["rel"] = e.expected ? json(e.tolerance.rel) : json(nullptr);
        row["abs"] = e.expected ? json(e.tolerance.abs) : json(nullptr);
        row["allowed"] = e.expected ? json(e.tolerance.allowed(*e.expected)) : json(nullptr);
        row["min"] = e.min ? json(*e.min) : json(nullptr);
        row["max"] = e.max ? json(*e.max) : json(nullptr);
        row["deviation"] = r.deviation ? json(*r.deviation) : json(nullptr);
        rows.push_back(row);
    }
    return json{{"report", result.report_dir}, {"reference", result.reference_file}, {"passed", result.passed()},
                {"checks", result.rows.size()}, {"failed", result.failures()}, {"rows", rows}};
}

namespace {

// The effective number of independent residuals of one output's split: N/(1 + 2 Σ_k ρ_k²)
// from summary.json's residual_analysis (its autocorrelation at lags 1 … M); 0 when the
// report has none (written before it, or no samples).
double effective_samples(const json& s, const std::string& split, const std::string& output) {
    if (!s.contains("residual_analysis") || !s["residual_analysis"].is_object()) return 0.0;
    const json& block = s["residual_analysis"].value(split, json());
    if (!block.is_object() || !block.contains("outputs") || !block["outputs"].is_object()) return 0.0;
    const json& a = block["outputs"].value(output, json());
    if (!a.is_object() || !a.value("samples", json()).is_number() || !a.value("acf", json()).is_array()) return 0.0;
    double sum = 0.0;
    const json& acf = a["acf"];
    for (std::size_t k = 1; k < acf.size(); ++k)
        if (acf[k].is_number()) sum += acf[k].get<double>() * acf[k].get<double>();
    return a["samples"].get<double>() / (1.0 + 2.0 * sum);
}

// The relative spread (standard deviation over the mean) of a cost over N_eff residuals of
// Gaussian noise: Σe² is σ²χ²(N), sqrt(2/N); the mean |e| sqrt(π/2 − 1)/sqrt(N). 0 when
// N_eff is unknown.
double cost_spread(bool l2, double effective) {
    if (!(effective > 0.0)) return 0.0;
    return (l2 ? std::sqrt(2.0) : std::sqrt(std::acos(-1.0) / 2.0 - 1.0)) / std::sqrt(effective);
}

}  // namespace

ordered_json reference_from_report(const FitReportFiles& report, double rel, double sigmas) {
    const json& s = report.summary;
    if (s["status"] != "ok")
        throw InputError(report.summary_file(), 0, "status",
                         "is " + json_text(s["status"], -1) + ": a failed fit cannot be a reference");
    std::vector<std::string> undetermined;
    const json& identifiability = s.value("identifiability", json::object());
    if (identifiability.value("available", false))
        for (const json& n : identifiability.value("undetermined", json::array())) undetermined.push_back(n.get<std::string>());

    // Each parameter within `sigmas` standard errors, and never closer than rel of its value.
    ordered_json parameters = ordered_json::object();
    int from_errors = 0;
    for (const json& p : report.params["parameters"]) {
        const std::string name = p["name"].get<std::string>();
        if (p.value("fixed", false) || is_one_of(name, undetermined) || !p["value"].is_number()) continue;
        const double v = p["value"].get<double>();
        const json se = p.value("std_error", json());
        const double by_error = se.is_number() ? sigmas * se.get<double>() : 0.0;
        if (v != 0 && !(by_error > rel * std::abs(v))) {
            parameters[name] = v;
            continue;
        }
        // 0 has no relative tolerance: rel of the bound span (or of 1) as an absolute one.
        const double span = p["min"].is_number() && p["max"].is_number() ? as_double(p["max"]) - as_double(p["min"]) : 1.0;
        const double floor = v != 0 ? rel * std::abs(v) : rel * span;
        from_errors += by_error > floor ? 1 : 0;
        parameters[name] = {{"expected", v}, {"abs", std::max(by_error, floor)}};
    }

    // The cost and the metrics may grow by what a new noise realisation moves them: `sigmas`
    // times their relative spread, and at least by rel.
    const bool l2 = s["cost"].value("kind", "") == "l2";
    double cost_growth = rel;
    for (const auto& [out, m] : s["estimation"]["pooled"].items()) {
        (void)m;
        cost_growth = std::max(cost_growth, sigmas * cost_spread(l2, effective_samples(s, "estimation", out)));
    }

    std::string description = "written by tvid check --write-reference from " + report.dir.string();
    if (s.contains("command") && s["command"].is_string()) description += " (" + s["command"].get<std::string>() + ")";
    char rule[400];
    std::snprintf(rule, sizeof rule,
                  "; tolerances: each parameter %g standard errors (%d of them; rel %g of its value where that is "
                  "more), the cost and 100 - Q %g times their spread over the noise (at least %g), the max residual "
                  "ratio %g times the noise over the smallest |y| it counts",
                  sigmas, from_errors, rel, sigmas, rel, sigmas);
    description += rule;
    if (!undetermined.empty())
        description += "; left out the undetermined parameters " + join_words(undetermined) + ": check combinations";

    ordered_json r;
    r["tvid_reference"] = reference_version;
    r["description"] = description;
    if (s.contains("experiment")) r["experiment"] = s["experiment"];
    r["defaults"] = {{"rel", rel}, {"abs", 0.0}};
    r["parameters"] = parameters;
    if (s["cost"].contains("value") && s["cost"]["value"].is_number())
        r["cost"] = {{"max", s["cost"]["value"].get<double>() * (1.0 + cost_growth)}};
    for (const char* split : {"estimation", "validation"}) {
        ordered_json block = ordered_json::object();
        for (const auto& [out, m] : s[split]["pooled"].items()) {
            if (m.value("samples", 0) == 0) continue;
            ordered_json checks = ordered_json::object();
            // 100 − Q is the mean |e| over E0: its spread is the l1 cost's.
            const double q_growth = std::max(rel, sigmas * cost_spread(false, effective_samples(s, split, out)));
            if (m.contains("q_index_percent") && m["q_index_percent"].is_number())
                checks["q_index_percent"] = {{"min", 100.0 - (100.0 - m["q_index_percent"].get<double>()) * (1.0 + q_growth)}};
            const json ratio = m.contains("max_abs_residual_ratio_percent") || m.contains("max_abs_residual_ratio")
                                   ? metric_value(m, report.summary_file(), {}, "max_abs_residual_ratio_percent")
                                   : json();
            if (ratio.is_number()) {
                // The largest ratio is set by a few samples of small |y|: a new noise
                // realisation moves it by about the noise over the smallest |y| counted.
                double noise = 0.0;
                const json& smallest = m.value("residual_ratio_min_abs_y", json());
                const json& w = s.value("residuals", json::object()).value(split, json::object()).value(out, json::object());
                if (smallest.is_number() && smallest.get<double>() > 0 && w.value("noise_rms", json()).is_number())
                    noise = 100.0 * sigmas * w["noise_rms"].get<double>() / smallest.get<double>();
                checks["max_abs_residual_ratio_percent"] = {{"max", ratio.get<double>() * (1.0 + rel) + noise}};
            }
            if (!checks.empty()) block[out] = checks;
        }
        if (!block.empty()) r[split] = block;
    }
    r["status"] = "ok";
    if (s["optimizer"].value("converged", false)) r["converged"] = true;
    return r;
}

}  // namespace tvid
