#pragma once
// The optimizers an experiment can name, one row each, on the floor the experiment reader
// stands on: each kind's name and the traits the reader and the verdict ask about, made
// from the kinds' own files (experiment/optimizer_kinds/table.hpp). The fit floor's table
// (fit/optimizer_table.hpp) holds how each one runs and what it reports. Nothing else
// switches on an optimizer's kind.

#include <span>
#include <string_view>
#include <vector>

#include "tvid/experiment/optimizer_kinds/table.hpp"

namespace tvid {

class YamlMap;
struct ParameterSetting;
struct EstimationSettings;

enum class OptimizerKind {
#define TVID_OPTIMIZER_KIND_ENUMERATOR(kind, Kind) kind,
    TVID_OPTIMIZER_KINDS(TVID_OPTIMIZER_KIND_ENUMERATOR)
#undef TVID_OPTIMIZER_KIND_ENUMERATOR
};
struct OptimizerKindRow {
    OptimizerKind kind;
    const char* name;             ///< in experiment files, on the command line and in reports
    const char* summary;          ///< one line for `tvid models` and the docs
    OptimizerTraits traits;
    /// Fails at the first free parameter it cannot search, beyond the traits' own rule
    /// (a global NLopt algorithm needs both bounds); null when there is none.
    void (*check_parameters)(const YamlMap& parameters, const std::vector<ParameterSetting>& settings,
                             const EstimationSettings& estimation) = nullptr;
};

/// Every optimizer, in the order of OptimizerKind.
const std::vector<OptimizerKindRow>& optimizer_kinds();

/// The row of `kind`.
const OptimizerKindRow& optimizer_kind_row(OptimizerKind kind);

/// The row named `name`, or null.
const OptimizerKindRow* find_optimizer_kind(std::string_view name);

/// The optimizer's name ("pso", "pso+lm", …).
const char* optimizer_name(OptimizerKind kind);

/// Its traits.
inline const OptimizerTraits& optimizer_traits(OptimizerKind kind) { return optimizer_kind_row(kind).traits; }

}  // namespace tvid
