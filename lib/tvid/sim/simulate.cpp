#include "tvid/sim/simulate.hpp"

namespace tvid {

const char* to_string(SimulationStatus s) {
    switch (s) {
        case SimulationStatus::ok: return "ok";
        case SimulationStatus::not_finite: return "not finite";
        case SimulationStatus::diverged: return "diverged";
        case SimulationStatus::step_budget_exceeded: return "step budget exceeded";
        case SimulationStatus::stopped_by_observer: return "stopped";
        case SimulationStatus::stopped_by_request: return "stopped by a stop request";
    }
    return "unknown";
}

}  // namespace tvid
