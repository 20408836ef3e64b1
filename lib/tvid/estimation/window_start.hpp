#pragma once
// How a window's simulation starts (Yoshida & Takamatsu eq. 18's static equilibrium, at rest, or
// the methodology paper's measured state made consistent with the encoder by a warm-up shooting), for
// the parameters already set in a workspace's model.

#include <atomic>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "tvid/estimation/problem_definition.hpp"
#include "tvid/estimation/problem_workspace.hpp"

namespace tvid {

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
    std::size_t substeps = 1;  ///< substeps per step of this window's simulations (stable_step.hpp)
    bool implicit_steps = false;  ///< sdirk3's steps instead: too stiff for the substeps (stable_step.hpp)
};

/// A window's start as a simulation solved it, to set out from again without solving it
/// again (the sensitivities at the point whose residuals were just computed): what
/// start_window returned, and the workspace's state at w.start (x_start), where the march
/// begins (x: at w.first after a warm-up) and the inputs at w.start (u0).
struct SolvedStart {
    WindowStart start;
    std::vector<double> x_start, x, u0;
};

/// How fast node i of the state x (n nodes) turns relative to node `node`: the gear
/// ratios a measured start gave its speeds (1 where they cannot tell: a node at rest).
/// A shot warm-up moves every node's angle and speed in these ratios.
double speed_ratio(const std::vector<double>& x, std::size_t n, std::size_t node, std::size_t i);

/// The starts of the windows of one problem definition.
class WindowStarts {
public:
    /// `subdivided` and `implicit` (may be null) count the starts that needed substeps, and
    /// those too stiff for them that take sdirk3's steps (stable_step.hpp).
    explicit WindowStarts(const ProblemDefinition& definition, std::atomic<long long>* subdivided = nullptr,
                          std::atomic<long long>* implicit = nullptr)
        : d_(&definition), subdivided_(subdivided), implicit_(implicit) {}

    /// Whether window w is simulated from a measured start through a warm-up (then its
    /// march begins at w.first, whose sample is scored too).
    bool warms_up(const Window& w) const {
        return initial_state_row(d_->initial_state).reads_measured_speed && !d_->crank_angle.empty() && w.start < w.first;
    }

    /// Prepares window w with the parameters already set in ws.model: ws.x_start gets the
    /// state at w.start and, after a warm-up, ws.x the state at w.first.
    WindowStart start(const Window& w, ProblemWorkspace& ws, std::string* problem) const;

    /// start's effect on ws from a start solved before for the same parameters.
    static WindowStart restore(const SolvedStart& solved, ProblemWorkspace& ws);

    /// The index of w among the estimation windows (the same samples and recording), or
    /// kNotEstimation: an estimated start holds parameters for those windows alone.
    static constexpr std::size_t kNotEstimation = static_cast<std::size_t>(-1);
    std::size_t estimation_index(const Window& w) const;

    /// ws.x set to the initial_state recipe's state at w's start, for ws.model's
    /// parameters (an estimated start's seed); false (with a reason) if impossible.
    bool recipe_state(const Window& w, ProblemWorkspace& ws, std::string* problem) const;

    /// The samples (from, to] a validation window's estimated start is fitted on
    /// (`validation: estimated`): those before its first scored sample, its warm-up or the
    /// lead-in the loader gave it (a tenth of it, at least two samples per coordinate).
    std::pair<std::size_t, std::size_t> estimated_start_samples(const Window& w) const;

private:
    // Sets ws.x to the initial state at window w's start; false (with a reason) if impossible.
    bool initial_state(const Window& w, ProblemWorkspace& ws, std::string* problem) const;
    // A validation window's estimated start: the recipe's state in ws.x, corrected by
    // Levenberg–Marquardt so that the outputs meet the measured ones on
    // estimated_start_samples(w) with the model held (window_start_estimate.cpp).
    bool estimate_start(const Window& w, ProblemWorkspace& ws, std::string* problem) const;
    // Measured initial state with a warm-up: leaves ws.x at the window's first sample.
    SimulationStatus shoot_warmup(const Window& w, ProblemWorkspace& ws, WindowStart& start) const;
    // With fixed-step RK4 it solves by Newton's method with the exact Jacobian
    // (estimation/warmup_newton.hpp); otherwise by chord Newton with the Jacobian from
    // differences (any integrator):
    SimulationStatus shoot_warmup_by_differences(const Window& w, ProblemWorkspace& ws, WindowStart& start) const;

    const ProblemDefinition* d_;
    std::atomic<long long>* subdivided_ = nullptr;
    std::atomic<long long>* implicit_ = nullptr;
};

}  // namespace tvid
