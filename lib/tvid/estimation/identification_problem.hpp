#pragma once
// The identification problem of an experiment: maps the free parameters to the model
// parameter vector, simulates every window from its initial state and scores the
// simulated outputs against the measured ones (estimation/window_score.hpp). Independent
// of any optimizer. It computes from its ProblemDefinition, what it needs of the
// experiment; the experiment itself stays reachable for the callers that describe the
// fit (reports, the terminal, the fit's settings).

#include <array>
#include <atomic>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tvid/estimation/problem_definition.hpp"
#include "tvid/estimation/problem_workspace.hpp"
#include "tvid/estimation/window_start.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/sim/simulate.hpp"

namespace tvid {

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
    /// The problem of problem_definition(experiment); `experiment` must outlive it.
    explicit IdentificationProblem(const Experiment& experiment);
    // Workspaces point at the problem's channels: it stays where it was built.
    IdentificationProblem(const IdentificationProblem&) = delete;
    IdentificationProblem& operator=(const IdentificationProblem&) = delete;

    /// The experiment the problem was built from, for callers outside estimation/ that
    /// report on it; the problem's own computations read only definition().
    const Experiment& experiment() const { return *experiment_; }
    const ProblemDefinition& definition() const { return definition_; }
    std::size_t dimension() const { return free_.size(); }          ///< number of free parameters
    const std::vector<std::size_t>& free_indices() const { return free_; }
    const std::vector<std::string>& free_names() const { return free_names_; }
    const std::vector<double>& lower() const { return lower_; }      ///< bounds of the free parameters
    const std::vector<double>& upper() const { return upper_; }
    const std::vector<double>& range_lower() const { return range_lo_; }  ///< initial search box
    const std::vector<double>& range_upper() const { return range_hi_; }
    const std::vector<double>& initial() const { return init_; }     ///< init of the free parameters
    /// How the optimizers search each free parameter (`scale:`; optim/parameter_scaling.hpp).
    const std::vector<ParameterScale>& scales() const { return scales_; }
    const InputChannels& inputs() const { return definition_.inputs; }
    const CrankAngleChannels& crank_angle_inputs() const { return definition_.angle_inputs; }
    /// Measured output k (unit-scaled) at every sample, shifted by its delay's init.
    const std::vector<double>& measured(std::size_t k) const { return definition_.measured[k]; }
    /// Whether a channel's delay is a parameter (ProblemDefinition::delayed_inputs, _outputs).
    bool has_delay_parameters() const {
        return !definition_.delayed_inputs.empty() || !definition_.delayed_outputs.empty();
    }
    /// The free column of model parameter `parameter`, or -1 when it is fixed.
    long free_column(int parameter) const;
    /// Whether free column j is a channel's delay.
    bool is_delay_column(std::size_t j) const { return delay_column_[j] != 0; }
    /// The free columns that delay an input, each once (an input and its rate share one).
    const std::vector<std::size_t>& input_delay_columns() const { return input_delay_columns_; }
    /// The central-difference step of free parameter j at value x (difference_step.hpp);
    /// for a delay, a thousandth of the mean sample interval, whatever its value (a step
    /// relative to a delay near 0 would vanish).
    double difference_step(std::size_t j, double x) const;
    /// The points of free column j's central difference at x: x ± difference_step, each
    /// kept within the bounds (one-sided when x is on or near one). {up, down}.
    std::pair<double, double> difference_points(std::size_t j, double x) const;
    /// Sets the full parameter vector `params` in ws: its model and its delayed channels.
    void use_parameters(const std::vector<double>& params, ProblemWorkspace& ws) const;
    /// Shifts ws's copies of the channels whose delay is a parameter to ws.params' delays
    /// (only those whose delay changed): every simulation and score on ws then reads
    /// ws.inputs and ws.measured.
    void apply_channel_delays(ProblemWorkspace& ws) const;

    std::unique_ptr<ProblemWorkspace> make_workspace() const;

    /// The model parameter vector for free parameter values `free` (fixed ones at their value).
    void full_parameters(const double* free, std::vector<double>& out) const;
    std::vector<double> full_parameters(const std::vector<double>& free) const;

    /// Cost over the estimation windows by the rule of window_score.hpp (l1: Σ_windows the
    /// mean over the samples of Σ_outputs |e| (Yoshida & Takamatsu eq. 19); l2: Σ e² (the methodology paper eq. 7)).
    /// +inf when a simulation fails. Never throws.
    double cost(const double* free, ProblemWorkspace& ws) const;

    /// The cost, or, once the partial sum of the non-negative terms already reaches `bound`,
    /// that partial sum (>= bound, <= the full cost) without simulating the rest: for an
    /// optimizer that only asks whether the candidate beats `bound`. bound = +inf: cost().
    double cost(const double* free, ProblemWorkspace& ws, double bound) const;

    /// The cost from the estimation windows' starts as a simulation at the same parameters
    /// solved them (trace's `solved`, one per window; an empty one is solved again): the
    /// same value as cost(), without solving the starts a second time.
    double cost(const double* free, ProblemWorkspace& ws, const std::vector<SolvedStart>& starts) const;

    /// Residuals f·(y − y*) (output_residual, window_score.hpp) of every scored sample of every
    /// estimation window and output
    /// (window by window, sample-major). False when a simulation fails. With `starts`,
    /// each estimation window's solved start is kept there (one per window).
    bool residuals(const double* free, ProblemWorkspace& ws, std::vector<double>& out,
                   std::vector<SolvedStart>* starts = nullptr) const;

    /// Why the estimation windows cannot be simulated at free parameter values `free`:
    /// the first failing window and its simulation's account (failure_account); empty
    /// when every window simulates.
    std::string failure(const double* free, ProblemWorkspace& ws) const;

    /// Simulates one window with the full parameter vector `params` and records every
    /// scored sample. With `solved`, the window's start is kept there; with `given` (a start
    /// solved before at the same parameters), it is set out from instead of solved again.
    WindowTrace trace(const std::vector<double>& params, const Window& window, ProblemWorkspace& ws,
                      SolvedStart* solved = nullptr, const SolvedStart* given = nullptr) const;

    /// Prepares window w with the parameters already set in ws.model: ws.x_start gets the
    /// state at w.start and, after a warm-up, ws.x the state at w.first (WindowStarts::start).
    WindowStart start_window(const Window& w, ProblemWorkspace& ws, std::string* problem) const {
        return starts_.start(w, ws, problem);
    }

    /// start_window's effect on ws from a start solved before for the same parameters.
    static WindowStart restore_start(const SolvedStart& solved, ProblemWorkspace& ws) {
        return WindowStarts::restore(solved, ws);
    }

    /// For free column j that corrects an estimated start (NetworkSpec::start_coordinates),
    /// the scale of its coordinate: the larger of the seed's magnitude and the half-width of
    /// its search box. A correction sits near 0 by design, so its effect and its error are
    /// judged against this, not against its value. 0 for a model parameter.
    double start_scale(std::size_t j) const;

    /// How many window starts so far needed a smaller step than the experiment's, a stiff
    /// candidate's (estimation/stable_step.hpp).
    long long subdivided_starts() const { return subdivided_.load(std::memory_order_relaxed); }
    /// How many of them were too stiff for the substeps and took sdirk3's implicit steps.
    long long implicit_starts() const { return implicit_.load(std::memory_order_relaxed); }

    /// The index of w among the estimation windows, or WindowStarts::kNotEstimation.
    std::size_t estimation_index(const Window& w) const { return starts_.estimation_index(w); }
    /// The samples a validation window's estimated start is fitted on (`validation: estimated`).
    std::pair<std::size_t, std::size_t> estimated_start_samples(const Window& w) const {
        return starts_.estimated_start_samples(w);
    }

    /// Whether window w is simulated from a measured start through a warm-up (then its
    /// march begins at w.first, whose sample is scored too).
    bool warms_up(const Window& w) const { return starts_.warms_up(w); }

    /// Applies each output's detrend and high-pass (ProblemDefinition::output_filter) to
    /// window w's block of residuals, or of one Jacobian column: in a row-major block of
    /// `columns` columns, column `column`. Nothing when no output is filtered.
    void filter_window_residuals(const Window& w, double* r, std::size_t columns, std::size_t column) const;

private:
    // Simulates window w from its initial state (through its warm-up) and calls
    // on_scored(i, x, u) at every scored sample.
    // With `given` (not empty), that start is set out from instead of solved.
    template <class Observer>
    SimulationStatus simulate_window(const Window& w, ProblemWorkspace& ws, std::string* problem,
                                     Observer&& on_scored, SolvedStart* solved = nullptr,
                                     const SolvedStart* given = nullptr) const;
    // cost() over the estimation windows, from `starts` where given.
    double window_cost(const double* free, ProblemWorkspace& ws, double bound, const std::vector<SolvedStart>* starts) const;
    // "simulation STATUS", and for a state that left the finite or sane range the node,
    // the value, the sample interval and what to try; x the state the march stopped at,
    // `reached` the last sample it passed.
    std::string failure_account(SimulationStatus status, std::size_t reached, const std::vector<double>& x) const;
    // The same for a speed beyond ProblemDefinition::speed_limits[node].
    std::string speed_account(std::size_t node, std::size_t reached, const std::vector<double>& x) const;
    // Sets the free parameters in ws's model; false if one is not finite.
    bool set_free_parameters(const double* free, ProblemWorkspace& ws) const;
    // An estimated start's seeds: each estimation window's recipe state at the parameters'
    // init (ProblemDefinition::EstimatedStarts). Throws InputError when one has none.
    void seed_estimated_starts();

    const Experiment* experiment_;
    ProblemDefinition definition_;
    mutable std::atomic<long long> subdivided_{0}, implicit_{0};
    WindowStarts starts_{definition_, &subdivided_, &implicit_};
    std::vector<std::size_t> free_;
    std::vector<std::string> free_names_;
    std::vector<double> lower_, upper_, range_lo_, range_hi_, init_;
    std::vector<ParameterScale> scales_;
    std::vector<char> delay_column_;               ///< per free column: a channel's delay
    std::vector<std::size_t> input_delay_columns_;
    std::vector<double> fixed_values_;  ///< full vector with every fixed parameter set
};

}  // namespace tvid
