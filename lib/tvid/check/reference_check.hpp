#pragma once
// `tvid check`: a fit report (summary.json, params.json) against a reference file of
// expected values, tolerances and bounds (docs/reference-checks.md, "tvid_reference": 1).
// Every check becomes one row, PASS or FAIL, so CI shows what moved and by how much.

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tvid/check/fit_report_reader.hpp"

namespace tvid {

/// A value passes when |actual − expected| ≤ abs + rel·|expected|.
struct Tolerance {
    double rel = 0.0;
    double abs = 0.0;
    double allowed(double expected) const { return abs + rel * std::abs(expected); }
};

/// What one number must satisfy: `expected` within `tolerance`, and/or min ≤ actual ≤ max.
struct Expectation {
    std::optional<double> expected;
    Tolerance tolerance;
    std::optional<double> min, max;
    /// For a value of the report that is not a number (status, converged): equality.
    nlohmann::json equals;

    bool holds(const nlohmann::json& actual) const;
    /// What a number is compared with: `expected`, else the failing or nearer bound.
    std::optional<double> reference_value(const nlohmann::json& actual) const;
    /// (actual − r)/|r| with r = reference_value(actual); empty when r is 0 or missing,
    /// or the value is not a finite number.
    std::optional<double> deviation(const nlohmann::json& actual) const;
};

/// A parameter of params.json, or a combination of parameters such as "rho1*k_plus".
struct ParameterCheck {
    std::string name;
    Expectation expectation;
};

/// A fit metric of summary.json (`q_index_percent`, `max_abs_residual_ratio_percent`, …).
struct MetricCheck {
    std::string split;         ///< "estimation" or "validation"
    std::string output;        ///< an output name; "" for every output of the report
    std::string metric;
    bool each_window = false;  ///< every window of the split instead of the pooled value
    Expectation expectation;
};

/// Any field of summary.json by JSON pointer, e.g. "/optimizer/converged".
struct FieldCheck {
    std::string label;         ///< the row's name: the reference key
    std::string pointer;
    Expectation expectation;
};

struct Reference {
    std::string file;          ///< for messages
    std::string description;
    Tolerance defaults;
    std::vector<ParameterCheck> parameters;
    std::vector<ParameterCheck> combinations;
    std::optional<Expectation> cost;
    std::vector<MetricCheck> metrics;
    std::vector<FieldCheck> fields;  ///< experiment, status, converged, then `fields`
};

/// The metric names a reference may bound: the fields of summary.json's metrics.
const std::vector<std::string>& reference_metric_names();

/// Throws InputError (file, key, what is wrong) for a malformed reference.
Reference parse_reference(const nlohmann::ordered_json& j, const std::string& file);
Reference read_reference(const std::filesystem::path& file);

struct CheckRow {
    std::string quantity;      ///< e.g. "parameters.J1", "validation.omega_dw.q_index_percent [cycle 3]"
    Expectation expectation;
    nlohmann::json actual;     ///< number, string or bool; null when not finite
    std::optional<double> deviation;
    bool pass = false;
    std::string note;          ///< e.g. "not finite", "no samples"
};

struct CheckResult {
    std::string report_dir;
    std::string reference_file;
    std::vector<CheckRow> rows;  ///< in reference order

    std::size_t failures() const;
    bool passed() const { return failures() == 0; }
};

/// Evaluates every check of `reference` on the report. Throws InputError when the
/// reference names a parameter, output or field the report does not have.
CheckResult check_report(const FitReportFiles& report, const Reference& reference);

/// `tvid check --json`: the rows with numbers, and the verdict.
nlohmann::json check_result_json(const CheckResult& result);

/// --write-reference: a parameter's tolerance in standard errors (params.json's std_error).
/// A refit on a new noise realisation differs from this fit by about √2 standard errors per
/// parameter, so 5 leaves each parameter 3.5 of those: one refit in about 2500 fails a given
/// parameter by chance.
constexpr double kReferenceStandardErrors = 5.0;

/// A reference from a known-good report (`--write-reference`, docs/reference-checks.md):
/// every free parameter the report does not list as undetermined, expected at its value
/// within `sigmas` standard errors (at least `rel` of its value); the cost and 100 − Q of
/// each split and output may grow by `sigmas` times their relative spread over the noise,
/// sqrt(2/N_eff) for Σe² and sqrt(π/2 − 1)/sqrt(N_eff) for a mean |e| with
/// N_eff = N/(1 + 2 Σ_k ρ_k²) from the residual's autocorrelation (at least by `rel`); the max
/// residual ratio by `rel`, plus `sigmas` times the noise over the smallest |y| it counts; the status must stay
/// ok and, if it converged, the optimizer must converge.
nlohmann::ordered_json reference_from_report(const FitReportFiles& report, double rel,
                                             double sigmas = kReferenceStandardErrors);

}  // namespace tvid
