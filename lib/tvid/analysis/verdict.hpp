#pragma once
// Whether a result can be trusted, said by the tool itself: a list of findings, each with a
// code a script can match, a severity, one line on what was found and one on what to try.
// A fit without findings has the verdict "clean". `--strict` turns an error into exit 1.

#include <string>
#include <vector>

namespace tvid {

enum class Severity { info, warning, error };
const char* to_string(Severity severity);

struct Finding {
    std::string code;       ///< e.g. "residuals_not_white" (docs/report-format.md lists them)
    Severity severity = Severity::warning;
    std::string subject;    ///< the parameter, output or window it concerns; empty for the fit
    std::string message;    ///< what was found, with the figures
    std::string advice;     ///< what to try next
};

struct Verdict {
    std::vector<Finding> findings;  ///< errors first, then warnings, then notes; in order found within each

    void add(Finding finding);
    int count(Severity severity) const;
    bool has_errors() const { return count(Severity::error) > 0; }
    /// "clean", or e.g. "1 error, 2 warnings" (notes are not counted).
    std::string summary() const;
};

}  // namespace tvid
