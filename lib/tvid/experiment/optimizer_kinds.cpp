#include "tvid/experiment/optimizer_kinds.hpp"

#include <stdexcept>
#include <string>

#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

namespace {

// A kind's check of the parameters beyond its traits, when it declares one.
template <class Kind>
constexpr auto parameter_check() {
    using Check = void (*)(const YamlMap&, const std::vector<ParameterSetting>&, const EstimationSettings&);
    if constexpr (requires { &Kind::template check_parameters<YamlMap, ParameterSetting, EstimationSettings>; })
        return Check{&Kind::template check_parameters<YamlMap, ParameterSetting, EstimationSettings>};
    else
        return Check{nullptr};
}

}  // namespace

const std::vector<OptimizerKindRow>& optimizer_kinds() {
    static const std::vector<OptimizerKindRow> rows{
#define TVID_OPTIMIZER_KIND_ROW(kind, Kind) \
    {OptimizerKind::kind, Kind::name, Kind::summary, Kind::traits, parameter_check<Kind>()},
        TVID_OPTIMIZER_KINDS(TVID_OPTIMIZER_KIND_ROW)
#undef TVID_OPTIMIZER_KIND_ROW
    };
    return rows;
}

const OptimizerKindRow& optimizer_kind_row(OptimizerKind kind) {
    for (const OptimizerKindRow& row : optimizer_kinds())
        if (row.kind == kind) return row;
    throw std::logic_error("no optimizer row for kind " + std::to_string(static_cast<int>(kind)));
}

const OptimizerKindRow* find_optimizer_kind(std::string_view name) {
    for (const OptimizerKindRow& row : optimizer_kinds())
        if (name == row.name) return &row;
    return nullptr;
}

const char* optimizer_name(OptimizerKind kind) { return optimizer_kind_row(kind).name; }

}  // namespace tvid
