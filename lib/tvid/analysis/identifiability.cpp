#include "tvid/analysis/identifiability.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numbers>

#include "tvid/channels/recording_spans.hpp"
#include "tvid/util/kind_table.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

namespace {

constexpr int kMaxDenominator = 4;          // exponents read as n/1 … n/4
constexpr double kFractionTolerance = 0.02;  // how close an exponent must be to n/d

// n/d with d <= kMaxDenominator within kFractionTolerance of a, or d = 0 when none is.
void nearby_fraction(double a, int& n, int& d) {
    if (!(std::abs(a) < 1e6)) {  // no small fraction, and lround would overflow
        n = d = 0;
        return;
    }
    for (d = 1; d <= kMaxDenominator; ++d) {
        n = static_cast<int>(std::lround(a * d));
        if (std::abs(a - static_cast<double>(n) / d) <= kFractionTolerance) return;
    }
    d = 0;
}

double rounded_exponent(double a) {
    int n = 0, d = 0;
    nearby_fraction(a, n, d);
    return d > 0 ? static_cast<double>(n) / d : a;
}

// The factor s^a as text: "s", "1/s", "s^2", "1/s^(1/2)", "s^0.37".
std::string power_of_s(double a) {
    const bool inverse = a < 0;
    const double e = std::abs(a);
    int n = 0, d = 0;
    nearby_fraction(e, n, d);
    char buf[32];
    if (d == 1 && n == 1) std::snprintf(buf, sizeof buf, "s");
    else if (d == 1) std::snprintf(buf, sizeof buf, "s^%d", n);
    else if (d > 1) std::snprintf(buf, sizeof buf, "s^(%d/%d)", n, d);
    else std::snprintf(buf, sizeof buf, "s^%.2g", e);
    return (inverse ? "1/" : "") + std::string(buf);
}

// "a", "a and b", "a, b and c".
std::string and_list(const std::vector<std::string>& words) {
    std::string s;
    for (std::size_t i = 0; i < words.size(); ++i) {
        if (i > 0) s += i + 1 == words.size() ? " and " : ", ";
        s += words[i];
    }
    return s;
}

std::string percent_text(double fraction) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g %%", 100.0 * fraction);
    return buf;
}

}  // namespace

const char* to_string(IdentifiabilityFlag flag) {
    using enum IdentifiabilityFlag;
    static constexpr std::array<EnumName<IdentifiabilityFlag>, 3> names{{{ok, "ok"}, {weak, "weak"}, {undetermined, "undetermined"}}};
    static_assert(rows_in_enumerator_order(names, 3));
    return name_in(names, flag);
}

ParameterCombination describe_null_direction(const std::vector<double>& direction,
                                             const std::vector<std::string>& names, const std::vector<double>& values,
                                             const std::vector<ParameterScaleRule>& rules,
                                             const std::vector<double>& column_scales) {
    ParameterCombination c;
    c.vector = direction;
    c.exponents.assign(direction.size(), 0.0);
    std::vector<std::size_t> members;
    for (std::size_t j = 0; j < direction.size(); ++j)
        if (std::abs(direction[j]) > kNullDirectionComponent) {
            members.push_back(j);
            c.members.push_back(names[j]);
        }
    if (members.empty()) return c;
    if (members.size() == 1) {
        c.text = names[members[0]] + " has no effect on the output";
        return c;
    }
    // A member with a meaningful zero (a start's correction, a delay, an offset, a phase) or
    // at 0 changes by an amount: the component times its column's scale. The others scale.
    const auto additive = [&](std::size_t j) { return (j < rules.size() && rules[j].scale > 0) || values[j] == 0.0; };
    const auto amount = [&](std::size_t j) {
        const double scale = j < column_scales.size() ? column_scales[j] : values[j] != 0.0 ? std::abs(values[j]) : 1.0;
        return direction[j] * scale;
    };
    std::vector<std::size_t> scaled, shifted;
    for (std::size_t j : members) (additive(j) ? shifted : scaled).push_back(j);
    c.multiplicative = shifted.empty();
    if (scaled.empty()) {
        // Amounts only: their proportions, as a unit vector.
        double norm = 0.0;
        for (std::size_t j : shifted) norm += amount(j) * amount(j);
        norm = std::sqrt(norm);
        std::vector<std::string> parts;
        for (std::size_t j : shifted) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%+.2g", amount(j) / norm);
            parts.push_back(names[j] + " by " + buf);
        }
        c.text = "changing " + and_list(parts) + " together (absolute changes, or any multiple of them) leaves the output unchanged";
        return c;
    }
    // The leading scaled member (the first of at least half the largest) gets s^1.
    double largest = 0.0;
    for (std::size_t j : scaled) largest = std::max(largest, std::abs(direction[j]));
    std::size_t lead = scaled.front();
    for (std::size_t j : scaled)
        if (std::abs(direction[j]) >= 0.5 * largest) {
            lead = j;
            break;
        }
    // Along the direction, ln p_j changes by t·v_j: p_j → p_j·s^(v_j/v_lead) with s = e^(t·v_lead).
    for (std::size_t j : scaled) c.exponents[j] = rounded_exponent(direction[j] / direction[lead]);
    // Group the scaled members by their power of s, in order of first appearance.
    std::vector<std::pair<double, std::vector<std::string>>> groups;
    for (std::size_t j : scaled) {
        bool placed = false;
        for (auto& g : groups)
            if (std::abs(g.first - c.exponents[j]) <= 1e-12) {
                g.second.push_back(names[j]);
                placed = true;
            }
        if (!placed) groups.push_back({c.exponents[j], {names[j]}});
    }
    std::vector<std::string> phrases;
    for (const auto& g : groups) phrases.push_back(and_list(g.second) + " by " + power_of_s(g.first));
    c.text = "scaling " + and_list(phrases);
    if (!shifted.empty()) {
        // ... and the others by amounts in ln s: δq = t·v_q·scale_q = (v_q·scale_q / v_lead)·ln s.
        std::vector<std::string> parts;
        for (std::size_t j : shifted) {
            char buf[48];
            std::snprintf(buf, sizeof buf, "%+.2g·ln(s)", amount(j) / direction[lead]);
            parts.push_back(names[j] + " by " + buf);
        }
        c.text += " while changing " + and_list(parts) + " (absolute changes)";
    }
    c.text += " leaves the output unchanged";
    return c;
}

std::vector<ParameterScaleRule> parameter_scale_rules(const IdentificationProblem& problem) {
    const NetworkSpec& network = problem.definition().network;
    enum class Zero { none, delay, offset, phase };
    std::vector<Zero> kind(network.parameter_names.size(), Zero::none);
    const auto mark = [&](const Field& f, Zero z) {
        if (f.is_parameter() && kind[static_cast<std::size_t>(f.parameter)] == Zero::none)
            kind[static_cast<std::size_t>(f.parameter)] = z;
    };
    for (int p : network.delay_parameters) mark(Field::param(p), Zero::delay);
    for (const OutputSpec& o : network.outputs) mark(o.offset, Zero::offset);
    for_each_element_field(network, [&](const FieldInfo& info, const Field& field) {
        if (std::strcmp(info.name, "offset") == 0) mark(field, Zero::offset);
        else if (std::strcmp(info.name, "phase") == 0) mark(field, Zero::phase);
    });
    const std::vector<double>& time = problem.inputs().time();
    const double period = mean_sample_interval(time, problem.definition().recordings);
    std::vector<ParameterScaleRule> rules;
    for (std::size_t j = 0; j < problem.dimension(); ++j) {
        ParameterScaleRule r;
        const double width = problem.range_upper()[j] - problem.range_lower()[j];
        switch (kind[problem.free_indices()[j]]) {
            case Zero::none: break;
            case Zero::delay:
                r.scale = period;
                r.what = "a sample period (" + number_text(period) + " s)";
                break;
            case Zero::offset:
                r.scale = width;
                r.what = "its range (" + number_text(width) + ")";
                break;
            case Zero::phase:
                r.scale = std::min(width, 2 * std::numbers::pi);
                r.what = r.scale < width ? "one turn (2π rad)" : "its range (" + number_text(width) + " rad)";
                break;
        }
        if (const double s = problem.start_scale(j); s > 0) {
            r.scale = s;  // the start's coordinate, not the correction
            r.what = "its coordinate's scale (" + number_text(s) + ")";
        }
        if (!(r.scale > 0) || !std::isfinite(r.scale)) r = {};
        rules.push_back(r);
    }
    return rules;
}

IdentifiabilityReport assess_identifiability(const IdentificationProblem& problem, const ParameterUncertainty& u,
                                             const std::vector<double>& values) {
    return assess_identifiability(u, problem.free_names(), values, parameter_scale_rules(problem));
}

IdentifiabilityReport assess_identifiability(const ParameterUncertainty& u, const std::vector<std::string>& names,
                                             const std::vector<double>& values,
                                             const std::vector<ParameterScaleRule>& rules) {
    IdentifiabilityReport r;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    r.available = u.available;
    r.problem = u.problem;
    r.of = static_cast<int>(names.size());
    r.rank = u.rank;
    r.condition_number = u.condition_number;
    if (!u.available) return r;
    for (std::size_t j = 0; j < names.size(); ++j) {
        ParameterIdentifiability p;
        p.name = names[j];
        p.value = values[j];
        p.std_error = u.std_error[j];
        p.relative_std_error = u.determined[j] && values[j] != 0.0 ? u.std_error[j] / std::abs(values[j]) : nan;
        p.judged_std_error = p.relative_std_error;
        if (j < rules.size() && rules[j].scale > 0) {
            // A meaningful zero: against the larger of the value and the natural scale.
            const double against = std::max(std::abs(values[j]), rules[j].scale);
            p.judged_std_error = u.determined[j] ? u.std_error[j] / against : nan;
            p.judged_against = against > rules[j].scale ? "its value" : rules[j].what;
        }
        if (!u.determined[j]) p.flag = IdentifiabilityFlag::undetermined;
        else if (p.judged_std_error > kWeakRelativeError) p.flag = IdentifiabilityFlag::weak;
        r.parameters.push_back(p);
    }
    for (std::size_t a = 0; a < names.size(); ++a)
        for (std::size_t b = a + 1; b < names.size(); ++b) {
            const double c = u.correlation[a][b];
            if (std::isfinite(c) && std::abs(c) > kStrongCorrelation) r.correlated_pairs.push_back({names[a], names[b], c});
        }
    for (const auto& dir : u.null_directions)
        r.null_directions.push_back(describe_null_direction(dir, names, values, rules, u.column_scale));
    return r;
}

std::string IdentifiabilityReport::warning() const {
    if (!available) return "";
    std::string line;
    if (rank < of) {
        line = "the data determine only " + std::to_string(rank) + " of " + std::to_string(of) + " parameter directions: ";
        for (std::size_t i = 0; i < null_directions.size(); ++i) line += (i ? "; " : "") + null_directions[i].text;
        line += null_directions.size() == 1 ? " (fix one of these parameters)" : " (fix one parameter of each)";
    }
    std::vector<std::string> weak;
    for (const ParameterIdentifiability& p : parameters)
        if (p.flag == IdentifiabilityFlag::weak)
            weak.push_back(p.name + " " + percent_text(p.judged_std_error) +
                           (p.judged_against == "its value" ? "" : " of " + p.judged_against));
    if (!weak.empty()) {
        if (!line.empty()) line += "; ";
        line += "weakly determined (relative std error > " + percent_text(kWeakRelativeError) + "): ";
        for (std::size_t i = 0; i < weak.size(); ++i) line += (i ? ", " : "") + weak[i];
    }
    return line;
}

}  // namespace tvid
