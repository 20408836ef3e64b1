#pragma once
// What the data determine, read from the uncertainty estimate at the optimum: the rank
// and condition number of the scaled JᵀJ, each parameter's relative standard error with
// a flag, strongly correlated pairs, and each near-null direction written as the
// parameter combination an engineer can act on. For the CVT preset with all nine
// parameters free (Yoshida & Takamatsu eqs. 15–21) the null direction is the exact scaling
//   ρ1 → sρ1, μ → sμ, k± → k±/s, c± → c±/s, σ → σ/s,
// which leaves Tds unchanged, and is reported as
//   "scaling rho1 and mu by s and k_minus, k_plus, c_minus, c_plus and sigma by 1/s
//    leaves the output unchanged".

#include <string>
#include <vector>

#include "tvid/analysis/uncertainty.hpp"

namespace tvid {

/// A parameter whose standard error exceeds this fraction of its value is weak.
constexpr double kWeakRelativeError = 0.5;
/// Pairs of parameters whose |correlation| exceeds this are reported (summary.json's
/// correlated_pairs, and the terminal's summary).
constexpr double kStrongCorrelation = 0.9;

enum class IdentifiabilityFlag { ok, weak, undetermined };
const char* to_string(IdentifiabilityFlag flag);

/// What a parameter's standard error is judged against. Most parameters scale: their
/// error counts relative to their value. A delay, an offset or a phase has a meaningful
/// zero instead (a delay of 5 µs ± 12 µs is well determined at 1 kHz): its error counts
/// against the larger of its value and a natural scale of its own.
struct ParameterScaleRule {
    double scale = 0.0;        ///< the natural scale; 0: relative to the value
    std::string what;          ///< e.g. "a sample period (0.001 s)", "its range (5)"
};

struct ParameterIdentifiability {
    std::string name;
    double value = 0.0;
    double std_error = 0.0;             ///< NaN when undetermined
    double relative_std_error = 0.0;    ///< std_error / |value|; NaN when undetermined or value = 0
    /// std_error over what it is judged against (|value|, or for a parameter with a
    /// natural scale the larger of |value| and that scale); the flag reads this.
    double judged_std_error = 0.0;
    std::string judged_against = "its value";  ///< what judged_std_error divides by
    IdentifiabilityFlag flag = IdentifiabilityFlag::ok;
};

struct CorrelatedPair {
    std::string first, second;          ///< in parameter order
    double correlation = 0.0;
};

/// A direction of relative parameter changes that leaves the output unchanged.
struct ParameterCombination {
    std::vector<double> vector;         ///< the unit vector, one entry per free parameter
    std::vector<std::string> members;   ///< the parameters taking part (component > kNullDirectionComponent)
    /// Per free parameter, the power of s in p_j → p_j·s^a_j along the direction (0 for
    /// non-members), relative to the leading member; rounded to a fraction with a
    /// denominator up to 4 when within 0.02 of one.
    std::vector<double> exponents;
    bool multiplicative = true;         ///< false when a member changes by an amount (at 0, or its rule has a scale)
    std::string text;                   ///< e.g. "scaling rho1 and mu by s and ... by 1/s leaves the output unchanged"
};

struct IdentifiabilityReport {
    bool available = false;
    std::string problem;                ///< why not available
    int rank = 0;
    int of = 0;                         ///< free parameters
    double condition_number = 0.0;      ///< inf when rank < of
    std::vector<ParameterIdentifiability> parameters;
    std::vector<CorrelatedPair> correlated_pairs;
    std::vector<ParameterCombination> null_directions;

    /// One line for the terminal ("" when everything is determined well): rank deficiency
    /// with the combinations, and the weak parameters.
    std::string warning() const;
};

/// `names` and `values`: the free parameters at the optimum, in the order of `uncertainty`;
/// `rules`: how each is judged (empty, or a rule with scale 0: relative to its value).
IdentifiabilityReport assess_identifiability(const ParameterUncertainty& uncertainty,
                                             const std::vector<std::string>& names, const std::vector<double>& values,
                                             const std::vector<ParameterScaleRule>& rules = {});

/// The rule of each free parameter of `problem`: a channel's delay against one (mean)
/// sample period; an offset (of an output or an element) or a phase against the width of
/// its search range (`range:`, else its bounds; a phase at most one turn); every other
/// parameter relative to its value.
std::vector<ParameterScaleRule> parameter_scale_rules(const IdentificationProblem& problem);

/// assess_identifiability for `problem`'s free parameters at `values`, each by its rule.
IdentifiabilityReport assess_identifiability(const IdentificationProblem& problem, const ParameterUncertainty& uncertainty,
                                             const std::vector<double>& values);

/// The combination a null direction describes (members, exponents, text). `rules`: a
/// member whose rule has a scale (a start's correction, a delay, an offset, a phase) has a
/// meaningful zero, so its change is written as an amount, not a factor; `column_scales`
/// (ParameterUncertainty::column_scale) turn the direction's components into those
/// amounts (empty: |value|, or 1 at 0).
ParameterCombination describe_null_direction(const std::vector<double>& direction,
                                             const std::vector<std::string>& names, const std::vector<double>& values,
                                             const std::vector<ParameterScaleRule>& rules = {},
                                             const std::vector<double>& column_scales = {});

}  // namespace tvid
