#include "tvid/fit/optimizer_table.hpp"

#include <stdexcept>
#include <string>

namespace tvid {

// Each optimizer kind's row (experiment/optimizer_kinds/table.hpp), defined in
// lib/tvid/fit/optimizers/<kind>_run.cpp.
#define TVID_OPTIMIZER_ENTRY_DECLARATION(kind, Kind) OptimizerEntry kind##_optimizer();
TVID_OPTIMIZER_KINDS(TVID_OPTIMIZER_ENTRY_DECLARATION)
#undef TVID_OPTIMIZER_ENTRY_DECLARATION

const std::vector<OptimizerEntry>& optimizer_table() {
    static const std::vector<OptimizerEntry> table{
#define TVID_OPTIMIZER_ENTRY(kind, Kind) kind##_optimizer(),
        TVID_OPTIMIZER_KINDS(TVID_OPTIMIZER_ENTRY)
#undef TVID_OPTIMIZER_ENTRY
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
