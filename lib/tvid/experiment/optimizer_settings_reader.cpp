#include "tvid/experiment/optimizer_settings_reader.hpp"

#include "tvid/experiment/experiment.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

OptimizerKind read_optimizer_kind(const YamlMap& estimation) {
    const std::string name = estimation.text("optimizer");
    std::vector<std::string> names;
    for (const OptimizerKindRow& row : optimizer_kinds()) {
        if (name == row.name) return row.kind;
        names.emplace_back(row.name);
    }
    estimation.fail("optimizer", "'" + name + "' is not one of: " + join_words(names));
}

std::vector<std::string> optimizer_section_keys() {
    return {
#define TVID_OPTIMIZER_SECTION_KEY(section, Kind) #section,
        TVID_OPTIMIZER_SECTIONS(TVID_OPTIMIZER_SECTION_KEY)
#undef TVID_OPTIMIZER_SECTION_KEY
    };
}

void read_optimizer_sections(const YamlMap& estimation, EstimationSettings& settings) {
#define TVID_OPTIMIZER_SECTION_READ(section, Kind)                                  \
    if (estimation.has(#section)) {                                                 \
        const YamlMap m = estimation.map(#section);                                 \
        m.allow_only(std::vector<std::string>(std::begin(Kind::keys), std::end(Kind::keys))); \
        Kind::read(m, settings);                                                    \
    }
    TVID_OPTIMIZER_SECTIONS(TVID_OPTIMIZER_SECTION_READ)
#undef TVID_OPTIMIZER_SECTION_READ
}

void check_search_box(const YamlMap& parameters, const std::vector<ParameterSetting>& settings,
                      const EstimationSettings& estimation) {
    const OptimizerKindRow& optimizer = optimizer_kind_row(estimation.optimizer);
    if (optimizer.check_parameters) optimizer.check_parameters(parameters, settings, estimation);
    if (!optimizer.traits.samples_box) return;
    for (const ParameterSetting& p : settings)
        if (!p.fixed && !p.range && !(p.has_min && p.has_max))
            parameters.fail(p.name, std::string(optimizer.name) +
                                        " samples its starts in the search box: give range: [a, b] or both min and max");
}

}  // namespace tvid
