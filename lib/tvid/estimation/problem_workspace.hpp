#pragma once
// Per-thread scratch space of an IdentificationProblem: a model instance and integrator
// buffers, built once (IdentificationProblem::make_workspace).

#include <array>
#include <atomic>
#include <cstddef>
#include <vector>

#include "tvid/channels/input_channels.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/model/state_jacobian.hpp"
#include "tvid/sim/simulate.hpp"
#include "tvid/util/cache_line.hpp"

namespace tvid {

/// ∂(the encoder's miss at the warm-up's mid, at its first scored sample)/∂(offset, speed).
using MissJacobian = std::array<std::array<double, 2>, 2>;

/// A warm-up shooting's solution (common angle offset a, common speed s) at other parameters,
/// as the first guess of the shooting of the window with the same start and first samples.
struct ShootingGuess {
    std::size_t start = 0, first = 0;
    double offset = 0.0, speed = 0.0;
    MissJacobian miss_jacobian{};  ///< at that solution
};

/// On cache lines of its own (kCacheLine): each thread writes to its workspace only.
struct alignas(kCacheLine) ProblemWorkspace {
    explicit ProblemWorkspace(const NetworkSpec& spec) : model(spec), tangent_model(spec) {}
    NetworkModel<double> model;
    /// The model with the warm-up shooting's two directions (angle offset, speed) carried
    /// along the state, for Newton's method with the exact Jacobian.
    NetworkModel<PackedDual<2>> tangent_model;
    std::vector<PackedDual<2>> tangent_params;
    SimulationBuffers buffers;
    std::vector<double> params;  ///< full model parameter vector
    std::vector<double> x;       ///< state
    std::vector<double> u0;      ///< inputs at the window start
    std::vector<double> x0;      ///< initial state of a warm-up being shot
    std::vector<double> x_start; ///< the state at the window start a simulation set out from
    std::vector<double> window_residuals;  ///< a window's residuals, filtered before they are scored
    /// Substeps per experiment step of the window being simulated (estimation/stable_step.hpp):
    /// set by its start, 1 unless the candidate is stiff at the experiment's step.
    std::size_t substeps = 1;
    /// The window takes sdirk3's steps instead: a candidate too stiff for the substeps (the same file).
    bool implicit_steps = false;
    StateJacobian state_jacobian;          ///< the linearisation that decides them
    std::vector<double> jacobian_values;
    /// Set by an optimizer that can be interrupted: once the flag is up, a simulation on this
    /// workspace (warm-up shooting included) ends at its next sample as stopped_by_observer.
    const std::atomic<bool>* stop = nullptr;
    bool stop_requested() const { return stop && stop->load(std::memory_order_relaxed); }
    /// Set by a least-squares solver between its evaluations: the shootings of the point it
    /// last took a Jacobian at, where the next trial point is near (empty: none).
    std::vector<ShootingGuess> shooting_guesses;

    /// The channels as this workspace's parameters read them: the problem's own, or, for
    /// a channel whose delay is a parameter, a copy shifted by the candidate's delay
    /// (IdentificationProblem::apply_channel_delays). Set by make_workspace.
    const InputChannels* inputs = nullptr;
    std::vector<const std::vector<double>*> measured;  ///< [output] → its samples
    InputChannels shifted_inputs;
    std::vector<std::vector<double>> shifted_measured;  ///< [output]; empty unless delayed by a parameter
    std::vector<double> applied_delays;  ///< per delayed channel (inputs, then outputs): its copy's delay
    std::vector<double> shift_scratch;   ///< one shifted input channel
};

}  // namespace tvid
