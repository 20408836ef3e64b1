#include "tvid/fit/optimizer_table.hpp"

#include <stdexcept>
#include <string>

namespace tvid {

// Each optimizer's row, defined in lib/tvid/fit/optimizers/<name>_run.cpp.
OptimizerEntry pso_optimizer();
OptimizerEntry lm_optimizer();
OptimizerEntry nlopt_optimizer();
OptimizerEntry pso_lm_optimizer();
OptimizerEntry multistart_optimizer();

const std::vector<OptimizerEntry>& optimizer_table() {
    static const std::vector<OptimizerEntry> table{
        pso_optimizer(), lm_optimizer(), nlopt_optimizer(), pso_lm_optimizer(), multistart_optimizer(),
    };
    return table;
}

const OptimizerEntry& optimizer_entry(OptimizerKind kind) {
    for (const OptimizerEntry& entry : optimizer_table())
        if (entry.kind == kind) return entry;
    throw std::logic_error("the optimizer table has no row for optimizer kind " +
                           std::to_string(static_cast<int>(kind)));
}

const OptimizerEntry* find_optimizer(std::string_view name) {
    for (const OptimizerEntry& entry : optimizer_table())
        if (name == entry.name()) return &entry;
    return nullptr;
}

}  // namespace tvid
