// ForwardSensitivity::simulate_packed for blocks of up to 16 directions, every even state
// size of the fixed-size RK4.
#include "tvid/estimation/forward_sensitivity_packed.hpp"

namespace tvid {

template SimulationStatus ForwardSensitivity::simulate_packed<2, 16>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<16>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<4, 16>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<16>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<6, 16>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<16>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<8, 16>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<16>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<10, 16>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<16>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<12, 16>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<16>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<14, 16>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<16>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<16, 16>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<16>, const SolvedStart*) const;

}  // namespace tvid
