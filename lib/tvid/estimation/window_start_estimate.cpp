// A validation window's estimated start (`initial_state: { kind: estimated, validation:
// estimated }`): with the model's parameters held, the start coordinates that the
// estimation windows identify are fitted on the window's first samples, as nlgreyest's
// compare(…, 'InitialCondition', 'estimate') does, and the window is then simulated from
// that start. Levenberg–Marquardt (optim/levenberg_marquardt.hpp) with the Jacobian from
// forward differences: a few coordinates over a short stretch.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "tvid/estimation/stable_step.hpp"
#include "tvid/estimation/window_score.hpp"
#include "tvid/estimation/window_start.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"

namespace tvid {

namespace {

// The outputs' scaled residuals f·(y − y*) on samples (from, to] from the recipe's state
// corrected by δ on the estimated coordinates.
class StartCorrection final : public LeastSquaresProblem {
public:
    StartCorrection(const ProblemDefinition& d, const Window& w, ProblemWorkspace& ws, std::size_t from, std::size_t to)
        : d_(d), ws_(ws), from_(from), to_(to), recipe_(ws.x), settings_(window_settings(d, w, ws)) {}

    std::size_t residual_count() const override { return (to_ - from_) * d_.measured.size(); }

    bool residuals(const double* delta, double* r) override {
        ws_.x = recipe_;
        const std::vector<std::size_t>& states = d_.estimated.states;
        for (std::size_t j = 0; j < states.size(); ++j) ws_.x[states[j]] += delta[j];
        ws_.model.project_onto_ties(ws_.x.data());
        std::size_t row = 0;
        const std::size_t count = residual_count();
        const auto observe = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
            for (std::size_t k = 0; k < d_.measured.size() && row < count; ++k) {
                const double y = ws_.model.output(static_cast<std::size_t>(d_.output_indices[k]), x.data(), u.data());
                r[row++] = output_residual(d_.output_scale[k], y, (*ws_.measured[k])[i]);
            }
            return !ws_.stop_requested();
        };
        std::vector<double> x = ws_.x;
        const SimulationStatus status =
            simulate_samples(ws_.model, *ws_.inputs, from_, to_, x, settings_, ws_.buffers, observe);
        if (status != SimulationStatus::ok || row != count) return false;
        for (std::size_t i = 0; i < count; ++i)
            if (!std::isfinite(r[i])) return false;
        return true;
    }

    bool jacobian(const double* delta, double* r, Eigen::MatrixXd& J) override {
        const std::size_t m = d_.estimated.states.size(), count = residual_count();
        if (!residuals(delta, r)) return false;
        std::vector<double> point(delta, delta + m), shifted(count);
        for (std::size_t j = 0; j < m; ++j) {
            const double h = 1e-6 * std::max(1.0, std::abs(delta[j]));
            point[j] = delta[j] + h;
            if (!residuals(point.data(), shifted.data())) return false;
            point[j] = delta[j];
            for (std::size_t i = 0; i < count; ++i)
                J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = (shifted[i] - r[i]) / h;
        }
        return true;
    }

    bool stopped() const override { return ws_.stop_requested(); }
    const std::vector<double>& recipe() const { return recipe_; }

private:
    const ProblemDefinition& d_;
    ProblemWorkspace& ws_;
    std::size_t from_, to_;
    std::vector<double> recipe_;
    SimulationSettings settings_;
};

}  // namespace

bool WindowStarts::estimate_start(const Window& w, ProblemWorkspace& ws, std::string* problem) const {
    const std::vector<std::size_t>& states = d_->estimated.states;
    const auto [from, to] = estimated_start_samples(w);
    if (states.empty() || to <= from) return true;
    StartCorrection correction(*d_, w, ws, from, to);
    LmSettings settings;
    settings.max_iterations = 60;
    settings.stol = 0.0;  // the start to the bit the data give, not to a standard error
    const std::vector<double> unbounded_low(states.size(), -1e300), unbounded_high(states.size(), 1e300);
    const LmSummary fit = run_levenberg_marquardt(settings, std::vector<double>(states.size(), 0.0), unbounded_low,
                                                  unbounded_high, correction);
    ws.x = correction.recipe();
    if (!std::isfinite(fit.best_cost) || fit.best.size() != states.size()) {
        if (problem) *problem = "the validation window's start could not be estimated: " + fit.termination;
        return false;
    }
    for (std::size_t j = 0; j < states.size(); ++j) ws.x[states[j]] += fit.best[j];
    ws.model.project_onto_ties(ws.x.data());
    return true;
}

}  // namespace tvid
