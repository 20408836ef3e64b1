#include "tvid/analysis/verdict.hpp"

#include <algorithm>
#include <array>

#include "tvid/util/kind_table.hpp"

namespace tvid {

const char* to_string(Severity severity) {
    using enum Severity;
    static constexpr std::array<EnumName<Severity>, 3> names{{{info, "note"}, {warning, "warning"}, {error, "error"}}};
    static_assert(rows_in_enumerator_order(names, 3));
    return name_in(names, severity);
}

void Verdict::add(Finding finding) {
    // Stable: after every finding at least as severe.
    const auto at = std::find_if(findings.begin(), findings.end(),
                                 [&](const Finding& f) { return f.severity < finding.severity; });
    findings.insert(at, std::move(finding));
}

int Verdict::count(Severity severity) const {
    return static_cast<int>(std::count_if(findings.begin(), findings.end(),
                                          [&](const Finding& f) { return f.severity == severity; }));
}

std::string Verdict::summary() const {
    const int errors = count(Severity::error), warnings = count(Severity::warning);
    if (errors == 0 && warnings == 0) return "clean";
    std::string s;
    if (errors > 0) s = std::to_string(errors) + (errors == 1 ? " error" : " errors");
    if (warnings > 0) s += (s.empty() ? "" : ", ") + std::to_string(warnings) + (warnings == 1 ? " warning" : " warnings");
    return s;
}

}  // namespace tvid
