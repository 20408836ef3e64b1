// `tvid check REPORT_DIR --reference REF.json`: a fit report against a reference of
// expected values and tolerances, as a table of PASS/FAIL rows (CI regression checks).
// `--write-reference REF.json` makes such a reference from a known-good report.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <memory>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/check/reference_check.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/text.hpp"
#include "tvid/io/json_file.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid::cli {

namespace {

std::string number(double v, int digits = 6) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

std::string value_text(const nlohmann::json& v) {
    if (v.is_null()) return "-";
    if (v.is_string()) return v.get<std::string>();
    if (v.is_number()) return number(v.get<double>());
    return json_text(v, -1);
}

// The actual value with enough digits to show how far it is from what it is compared
// with: 99.99989 against a minimum of 99.9999, not "99.9999".
std::string actual_text(const CheckRow& r) {
    if (!r.actual.is_number()) return value_text(r.actual);
    const double x = r.actual.get<double>();
    const std::optional<double> reference = r.expectation.reference_value(r.actual);
    int digits = 6;
    while (reference && digits < 12 && std::abs(std::stod(number(x, digits)) - x) > 0.01 * std::abs(x - *reference))
        ++digits;
    return number(x, digits);
}

std::string expected_text(const Expectation& e) {
    if (!e.equals.is_null()) return value_text(e.equals);
    std::string out = e.expected ? number(*e.expected) : "";
    if (!out.empty() && (e.min || e.max)) out += ", ";
    if (e.min && e.max) return out + "in [" + number(*e.min) + ", " + number(*e.max) + "]";
    if (e.min) return out + ">= " + number(*e.min);
    if (e.max) return out + "<= " + number(*e.max);
    return out;
}

std::string tolerance_text(const Expectation& e) {
    if (!e.expected) return "-";
    const Tolerance& t = e.tolerance;
    const std::string rel = number(100 * t.rel) + " %";
    if (t.abs > 0 && t.rel > 0) return number(t.abs) + " + " + rel;
    if (t.abs > 0) return number(t.abs);
    if (t.rel > 0) return rel;
    return "exact";
}

std::string deviation_text(const std::optional<double>& d) {
    if (!d) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%+.3g %%", 100 * *d);
    return buf;
}

std::string result_text(const CheckRow& r) { return (r.pass ? "PASS" : "FAIL") + (r.note.empty() ? "" : " (" + r.note + ")"); }

// The verdict: also the only line `--quiet` prints.
std::string final_line(const CheckResult& result) {
    const std::string where = " (" + result.report_dir + " against " + result.reference_file + ")";
    const std::size_t failed = result.failures();
    if (failed == 0) return "tvid check: PASS, all " + std::to_string(result.rows.size()) + " checks hold" + where;
    std::string names;
    std::size_t listed = 0;
    for (const CheckRow& r : result.rows) {
        if (r.pass) continue;
        if (listed++ == 5) {
            names += ", ...";
            break;
        }
        names += (names.empty() ? "" : ", ") + r.quantity;
    }
    return "tvid check: FAIL, " + std::to_string(failed) + " of " + std::to_string(result.rows.size()) +
           " checks failed: " + names + where;
}

// Every check as a row; the failing rows first.
std::string table_text(const CheckResult& result) {
    std::vector<const CheckRow*> order;
    for (const CheckRow& r : result.rows) order.push_back(&r);
    std::stable_partition(order.begin(), order.end(), [](const CheckRow* r) { return !r->pass; });

    std::vector<std::vector<std::string>> cells = {{"quantity", "expected", "tolerance", "actual", "deviation", "result"}};
    for (const CheckRow* r : order)
        cells.push_back({r->quantity, expected_text(r->expectation), tolerance_text(r->expectation),
                         actual_text(*r), deviation_text(r->deviation), result_text(*r)});
    std::vector<std::size_t> width(cells[0].size(), 0);
    for (const auto& row : cells)
        for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());

    std::ostringstream out;
    out << "tvid check " << result.report_dir << " against " << result.reference_file << ": " << result.rows.size()
        << " checks\n";
    for (const auto& row : cells) {
        std::string line = " ";
        for (std::size_t c = 0; c < row.size(); ++c) {
            line += ' ' + row[c];
            if (c + 1 < row.size()) line += std::string(width[c] - row[c].size() + 1, ' ');
        }
        out << line << '\n';
    }
    return out.str();
}

// Whether every number in `j` is finite (nlohmann would write an infinite one as null).
bool all_finite(const nlohmann::ordered_json& j) {
    if (j.is_number_float()) return std::isfinite(j.get<double>());
    if (j.is_structured())
        for (const auto& item : j)
            if (!all_finite(item)) return false;
    return true;
}

int write_reference(const CheckCommand& cmd) {
    const FitReportFiles report = read_fit_report(cmd.report_dir);
    // An interrupted fit's numbers are where the optimizer stood, not its result: the same
    // fit run to the end would fail a reference made from them.
    if (report.summary.value("interrupted", false))
        throw InputError((std::filesystem::path(cmd.report_dir) / "summary.json").string(), 0, "interrupted",
                         "the report is of an interrupted fit: a reference from it would fail the fit run to the end; "
                         "fit again to the end, then write the reference");
    // A reference file tvid did not write (a hand-kept one) is replaced only with --force;
    // after the report is read, so that a target among its files is named as such.
    check_replaceable(cmd.write_reference, cmd.force,
                      {WrittenFileMark::Form::json_string, "description", "written by tvid check --write-reference"},
                      "a reference");
    const nlohmann::ordered_json reference = reference_from_report(report, cmd.rel, cmd.sigmas);
    // A tolerance beyond a double (--sigmas 1e308 times a standard error) is the option's
    // fault, not the reference file's, which is never written.
    if (!all_finite(reference))
        throw InputError("", 0, "--sigmas",
                         "--sigmas " + number_text(cmd.sigmas) + " and --rel " + number_text(cmd.rel) +
                             " make a tolerance beyond the largest number (about 1.8e308): give smaller ones");
    // Checked before it is written: only a valid reference that this report passes reaches
    // the disk (its text parsed back, as a later tvid check reads it).
    const std::string text = json_text(reference) + "\n";
    const CheckResult result = check_report(
        report, parse_reference(parse_json_text<nlohmann::ordered_json>(text, cmd.write_reference), cmd.write_reference));
    if (!result.passed()) {
        std::cerr << "tvid check: the reference made from " << cmd.report_dir
                  << " fails on that report itself; nothing was written\n";
        return kExitNotSucceeded;
    }
    write_named_output_file(cmd.write_reference, text);
    // Tolerances from standard errors hold for a fit whose residual is noise; a fit the
    // verdict faults (a residual that is not white: a missing dynamic, or noise on an
    // input) moves by more than its standard errors on a new recording of the system.
    if (const nlohmann::json& verdict = report.summary.value("verdict", nlohmann::json::object());
        verdict.value("errors", 0) > 0) {
        std::string kinds;
        for (const nlohmann::json& f : verdict.value("findings", nlohmann::json::array()))
            if (f.value("severity", "") == "error" && kinds.find(f.value("code", "")) == std::string::npos)
                kinds += (kinds.empty() ? "" : ", ") + f.value("code", std::string());
        std::cerr << "tvid check: warning: the verdict of " << cmd.report_dir << " has " << verdict.value("errors", 0)
                  << " error(s) (" << kinds << "): its standard errors understate how far a refit on a new "
                  << "recording moves; widen the tolerances (--sigmas, or from a batch's spread) or fix the fit first\n";
    }
    if (const nlohmann::json& optimizer = report.summary.value("optimizer", nlohmann::json::object());
        optimizer.is_object() && !optimizer.value("converged", true))
        std::cerr << "tvid check: warning: the fit of " << cmd.report_dir << " did not converge ("
                  << optimizer.value("termination", std::string("no reason given"))
                  << "): a converged refit may move beyond the reference's tolerances; fit to convergence first\n";
    if (!cmd.quiet)
        std::cout << "tvid check: wrote " << cmd.write_reference << " with " << result.rows.size() << " checks from "
                  << cmd.report_dir << "\n  " << reference["description"].get<std::string>() << '\n';
    return kExitDone;
}

}  // namespace

int run_check_command(const CheckCommand& cmd) {
    if (!cmd.write_reference.empty()) return write_reference(cmd);
    if (cmd.reference.empty())
        throw InputError("", 0, "tvid check", "give --reference REF.json, or --write-reference REF.json to make one");
    const Reference reference = read_reference(cmd.reference);
    const FitReportFiles report = read_fit_report(cmd.report_dir);
    const CheckResult result = check_report(report, reference);
    if (cmd.json) {
        std::cout << json_text(check_result_json(result)) << std::endl;
    } else {
        if (!cmd.quiet) std::cout << table_text(result);
        std::cout << final_line(result) << std::endl;
    }
    return result.passed() ? 0 : 1;
}

CommandRow check_command_row() {
    return {"check", "compare a fit report with a reference of expected values (CI)", false,
            [](CLI::App& sub) -> CommandRunner {
                auto check = std::make_shared<CheckCommand>();
                sub.add_option("report", check->report_dir, "report directory written by tvid fit")->required();
                auto* reference = sub.add_option("--reference", check->reference, "reference file (JSON) to check against");
                auto* write = sub.add_option("--write-reference", check->write_reference,
                                             "write a reference from this known-good report instead");
                reference->excludes(write);
                sub.add_option("--rel", check->rel,
                               "relative tolerance written: the default, and the least a parameter, the cost and Q "
                               "get (default 0.01)")
                    ->needs(write)
                    ->check(kTolerance);
                sub.add_option("--sigmas", check->sigmas,
                               "tolerance written for each parameter in its standard errors, and for the cost, Q and "
                               "the residual ratio in their spread over the noise (default 5)")
                    ->needs(write)
                    ->check(kTolerance);
                sub.add_flag("--force", check->force, "replace a --write-reference file that tvid did not write")
                    ->needs(write);
                sub.add_flag("-q,--quiet", check->quiet, "print only the final line");
                sub.add_flag("--json", check->json, "print the checks as JSON");
                return [check](const CommandContext&) { return run_check_command(*check); };
            }};
}

}  // namespace tvid::cli
