#pragma once
// The identification problem of an experiment: maps the free parameters to the model
// parameter vector, simulates every window from its initial state and scores the
// simulated outputs against the measured ones. Independent of any optimizer.

#include <array>
#include <atomic>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "tvid/experiment/experiment.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/channels/input_channels.hpp"
#include "tvid/sim/simulate.hpp"

namespace tvid {

/// Per-thread scratch space: a model instance and integrator buffers, built once.
/// ∂(the encoder's miss at the warm-up's mid, at its first scored sample)/∂(offset, speed).
using MissJacobian = std::array<std::array<double, 2>, 2>;

/// A warm-up shooting's solution (common angle offset a, common speed s) at other parameters,
/// as the first guess of the shooting of the window with the same start and first samples.
struct ShootingGuess {
    std::size_t start = 0, first = 0;
    double offset = 0.0, speed = 0.0;
    MissJacobian miss_jacobian{};  ///< at that solution
};

struct ProblemWorkspace {
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
    /// Set by an optimizer that can be interrupted: once the flag is up, a simulation on this
    /// workspace (warm-up shooting included) ends at its next sample as stopped_by_observer.
    const std::atomic<bool>* stop = nullptr;
    bool stop_requested() const { return stop && stop->load(std::memory_order_relaxed); }
    /// Set by a least-squares solver between its evaluations: the shootings of the point it
    /// last took a Jacobian at, where the next trial point is near (empty: none).
    std::vector<ShootingGuess> shooting_guesses;
};

/// How a window's simulation starts: from ws.x_start at sample `start`, possibly through a
/// warm-up whose common angle offset and speed were solved for so that the encoder's node
/// meets the measured crank angle at samples `mid` and `first` (then the start depends on
/// the parameters through that solution).
struct WindowStart {
    SimulationStatus status = SimulationStatus::ok;
    bool shot = false;       ///< the warm-up shooting was solved
    double offset = 0.0;     ///< its solution: the common angle offset added to the measured angles
    double speed = 0.0;      ///< and the common speed
    /// The Jacobian of the miss that the shooting last computed (all 0 when it computed none).
    MissJacobian miss_jacobian{};
    std::size_t mid = 0;     ///< its first matching sample
    std::size_t node = 0;    ///< the encoder's node
};

/// A window's start as a simulation solved it, to set out from again without solving it
/// again (the sensitivities at the point whose residuals were just computed): what
/// start_window returned, and the workspace's state at w.start (x_start), where the march
/// begins (x: at w.first after a warm-up) and the inputs at w.start (u0).
struct SolvedStart {
    WindowStart start;
    std::vector<double> x_start, x, u0;
};

/// Measured and simulated outputs of one window at its scored samples.
struct WindowTrace {
    const Window* window = nullptr;
    SimulationStatus status = SimulationStatus::ok;
    std::string problem;                        ///< why the simulation failed, if it did
    std::vector<std::size_t> samples;           ///< scored sample indices
    std::vector<double> time;
    std::vector<std::vector<double>> measured;  ///< [output][k]
    std::vector<std::vector<double>> simulated; ///< [output][k]
};

class IdentificationProblem {
public:
    explicit IdentificationProblem(const Experiment& experiment);
    // Workspaces point at the problem's channels: it stays where it was built.
    IdentificationProblem(const IdentificationProblem&) = delete;
    IdentificationProblem& operator=(const IdentificationProblem&) = delete;

    const Experiment& experiment() const { return *experiment_; }
    std::size_t dimension() const { return free_.size(); }          ///< number of free parameters
    const std::vector<std::size_t>& free_indices() const { return free_; }
    const std::vector<std::string>& free_names() const { return free_names_; }
    const std::vector<double>& lower() const { return lower_; }      ///< bounds of the free parameters
    const std::vector<double>& upper() const { return upper_; }
    const std::vector<double>& range_lower() const { return range_lo_; }  ///< initial search box
    const std::vector<double>& range_upper() const { return range_hi_; }
    const std::vector<double>& initial() const { return init_; }     ///< init of the free parameters
    const InputChannels& inputs() const { return inputs_; }
    const CrankAngleChannels& crank_angle_inputs() const { return angle_inputs_; }
    /// Measured output k (unit-scaled) at every sample.
    const std::vector<double>& measured(std::size_t k) const { return measured_[k]; }

    std::unique_ptr<ProblemWorkspace> make_workspace() const;

    /// The model parameter vector for free parameter values `free` (fixed ones at their value).
    void full_parameters(const double* free, std::vector<double>& out) const;
    std::vector<double> full_parameters(const std::vector<double>& free) const;

    /// Cost over the estimation windows (l1: Σ_windows Σ_outputs mean|e| (Yoshida & Takamatsu eq. 19);
    /// l2: Σ e² (the methodology paper eq. 7)). +inf when a simulation fails. Never throws.
    double cost(const double* free, ProblemWorkspace& ws) const;

    /// The cost, or, once the partial sum of the non-negative terms already reaches `bound`,
    /// that partial sum (>= bound, <= the full cost) without simulating the rest: for an
    /// optimizer that only asks whether the candidate beats `bound`. bound = +inf: cost().
    double cost(const double* free, ProblemWorkspace& ws, double bound) const;

    /// Residuals y* − y of every scored sample of every estimation window and output
    /// (window by window, sample-major). False when a simulation fails. With `starts`,
    /// each estimation window's solved start is kept there (one per window).
    bool residuals(const double* free, ProblemWorkspace& ws, std::vector<double>& out,
                   std::vector<SolvedStart>* starts = nullptr) const;

    /// Simulates one window with the full parameter vector `params` and records every
    /// scored sample.
    WindowTrace trace(const std::vector<double>& params, const Window& window, ProblemWorkspace& ws) const;

    /// Prepares window w with the parameters already set in ws.model: ws.x_start gets the
    /// state at w.start and, after a warm-up, ws.x the state at w.first.
    WindowStart start_window(const Window& w, ProblemWorkspace& ws, std::string* problem) const;

    /// start_window's effect on ws from a start solved before for the same parameters.
    static WindowStart restore_start(const SolvedStart& solved, ProblemWorkspace& ws);

    /// The number of samples of window w that are scored.
    std::size_t scored_samples(const Window& w) const;

    /// Whether window w is simulated from a measured start through a warm-up (then its
    /// march begins at w.first, whose sample is scored too).
    bool warms_up(const Window& w) const {
        return experiment_->initial_state == InitialStateKind::measured && w.start < w.first;
    }

private:
    // Sets ws.x to the initial state at sample `start`; false (with a reason) if impossible.
    bool initial_state(std::size_t start, ProblemWorkspace& ws, std::string* problem) const;

    // Simulates window w from its initial state (through its warm-up) and calls
    // on_scored(i, x, u) at every scored sample.
    template <class Observer>
    SimulationStatus simulate_window(const Window& w, ProblemWorkspace& ws, std::string* problem,
                                     Observer&& on_scored, SolvedStart* solved = nullptr) const;

    // Measured initial state with a warm-up: leaves ws.x at the window's first sample.
    SimulationStatus shoot_warmup(const Window& w, ProblemWorkspace& ws, WindowStart& start) const;
    // The same by Newton's method with the Jacobian from the warm-up simulated with the
    // two directions (fixed-step RK4, state of N values).
    template <std::size_t N>
    SimulationStatus shoot_warmup_newton(const Window& w, ProblemWorkspace& ws, WindowStart& start) const;

    const Experiment* experiment_;
    InputChannels inputs_;
    CrankAngleChannels angle_inputs_;
    std::vector<std::vector<double>> measured_;  ///< [output][sample], unit-scaled
    std::vector<std::size_t> free_;
    std::vector<std::string> free_names_;
    std::vector<double> lower_, upper_, range_lo_, range_hi_, init_;
    std::vector<double> fixed_values_;  ///< full vector with every fixed parameter set
};

}  // namespace tvid
