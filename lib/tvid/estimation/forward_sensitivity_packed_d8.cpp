// ForwardSensitivity::simulate_packed for blocks of up to 8 directions, every even state
// size of the fixed-size RK4.
#include "tvid/estimation/forward_sensitivity_packed.hpp"

namespace tvid {

template SimulationStatus ForwardSensitivity::simulate_packed<2, 8>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<8>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<4, 8>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<8>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<6, 8>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<8>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<8, 8>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<8>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<10, 8>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<8>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<12, 8>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<8>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<14, 8>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<8>, const SolvedStart*) const;
template SimulationStatus ForwardSensitivity::simulate_packed<16, 8>(
    const double*, const Window&, std::size_t, std::size_t, SensitivityWorkspace&, std::string*,
    PackedObserver<8>, const SolvedStart*) const;

}  // namespace tvid
