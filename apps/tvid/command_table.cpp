#include "command_table.hpp"

namespace tvid::cli {

const std::vector<CommandRow>& command_table() {
    static const std::vector<CommandRow> rows{
        fit_command_row(),
        simulate_command_row(),
        validate_command_row(),
        sensitivity_command_row(),
        design_command_row(),
        profile_command_row(),
        check_command_row(),
        batch_command_row(),
        modes_command_row(),
        frf_command_row(),
        models_command_row(),
    };
    return rows;
}

}  // namespace tvid::cli
