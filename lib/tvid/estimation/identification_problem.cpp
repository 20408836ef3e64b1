#include "tvid/estimation/identification_problem.hpp"

#include <cmath>

#include "tvid/model/equilibrium.hpp"

namespace tvid {

namespace {
std::vector<double> scaled(const std::vector<double>& v, double scale) {
    std::vector<double> out(v);
    if (scale != 1.0)
        for (double& x : out) x *= scale;
    return out;
}
}  // namespace

IdentificationProblem::IdentificationProblem(const Experiment& experiment) : experiment_(&experiment) {
    const CsvTable& data = experiment.data;
    std::vector<std::vector<double>> input_values, angle_values;
    for (const ChannelBinding& in : experiment.inputs)
        (in.by_angle ? angle_values : input_values).push_back(scaled(data.column(in.column), in.scale));
    inputs_ = InputChannels(data.column(experiment.time_column), std::move(input_values));
    if (!angle_values.empty()) angle_inputs_ = CrankAngleChannels(experiment.crank_angle, std::move(angle_values));
    for (const ChannelBinding& out : experiment.outputs)
        measured_.push_back(scaled(data.column(out.column), out.scale));

    fixed_values_.resize(experiment.parameters.size());
    for (std::size_t i = 0; i < experiment.parameters.size(); ++i) {
        const ParameterSetting& p = experiment.parameters[i];
        fixed_values_[i] = p.init;
        if (p.fixed) continue;
        free_.push_back(i);
        free_names_.push_back(p.name);
        lower_.push_back(p.min);
        upper_.push_back(p.max);
        range_lo_.push_back(p.range ? p.range->first : p.min);
        range_hi_.push_back(p.range ? p.range->second : p.max);
        init_.push_back(p.init);
    }
}

std::unique_ptr<ProblemWorkspace> IdentificationProblem::make_workspace() const {
    auto ws = std::make_unique<ProblemWorkspace>(experiment_->network);
    ws->model.set_crank_angle_inputs(&angle_inputs_);
    ws->params = fixed_values_;
    ws->x.resize(ws->model.state_size());
    ws->u0.resize(inputs_.count());
    ws->buffers.u.resize(inputs_.count());
    return ws;
}

void IdentificationProblem::full_parameters(const double* free, std::vector<double>& out) const {
    out = fixed_values_;
    for (std::size_t j = 0; j < free_.size(); ++j) out[free_[j]] = free[j];
}

std::vector<double> IdentificationProblem::full_parameters(const std::vector<double>& free) const {
    std::vector<double> out;
    full_parameters(free.data(), out);
    return out;
}

bool IdentificationProblem::initial_state(std::size_t start, ProblemWorkspace& ws, std::string* problem) const {
    const std::size_t n = ws.model.node_count();
    std::size_t hint = start;
    inputs_.at(inputs_.time()[start], hint, ws.u0.data());
    std::fill(ws.x.begin(), ws.x.end(), 0.0);
    switch (experiment_->initial_state) {
        case InitialStateKind::rest: return true;
        case InitialStateKind::measured: {
            // Every node at the measured crank angle (no twist), turning at the measured speed.
            const double speed = measured_[static_cast<std::size_t>(experiment_->initial_speed_output)][start];
            for (std::size_t i = 0; i < n; ++i) {
                ws.x[i] = experiment_->crank_angle[start];
                ws.x[n + i] = speed;
            }
            return true;
        }
        case InitialStateKind::equilibrium: {
            // Seed 001 eq. 18: θ(t1) = θ̄ with F(θ̄, 0) balancing the input at t1, θ'(t1) = 0.
            EquilibriumResult eq = solve_equilibrium(ws.model, ws.u0.data());
            if (!eq.found) {
                if (problem) *problem = "no static equilibrium: " + eq.problem;
                return false;
            }
            for (std::size_t i = 0; i < n; ++i) ws.x[i] = eq.theta[i];
            return true;
        }
    }
    return false;
}

double IdentificationProblem::cost(const double* free, ProblemWorkspace& ws) const {
    for (std::size_t j = 0; j < free_.size(); ++j) {
        if (!std::isfinite(free[j])) return std::numeric_limits<double>::infinity();
        ws.params[free_[j]] = free[j];
    }
    ws.model.set_parameters(ws.params.data());
    const bool l1 = experiment_->estimation_settings.cost == CostKind::l1;
    const std::size_t n_out = experiment_->outputs.size();
    double total = 0.0;
    for (const Window& w : experiment_->estimation) {
        if (!initial_state(w.start, ws, nullptr)) return std::numeric_limits<double>::infinity();
        double window_sum = 0.0;
        std::size_t scored = 0;
        auto score = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
            if (i < w.first) return true;  // warm-up: simulated, not scored
            for (std::size_t k = 0; k < n_out; ++k) {
                const double e = ws.model.output(experiment_->output_indices[k], x.data(), u.data()) - measured_[k][i];
                window_sum += l1 ? std::abs(e) : e * e;
            }
            ++scored;
            return true;
        };
        const SimulationStatus status =
            simulate_samples(ws.model, inputs_, w.start, w.last, ws.x, experiment_->simulation, ws.buffers, score);
        if (status != SimulationStatus::ok) return std::numeric_limits<double>::infinity();
        total += l1 ? window_sum / static_cast<double>(scored) : window_sum;  // l1: mean per window
    }
    return std::isfinite(total) ? total : std::numeric_limits<double>::infinity();
}

bool IdentificationProblem::residuals(const double* free, ProblemWorkspace& ws, std::vector<double>& out) const {
    out.clear();
    for (std::size_t j = 0; j < free_.size(); ++j) {
        if (!std::isfinite(free[j])) return false;
        ws.params[free_[j]] = free[j];
    }
    ws.model.set_parameters(ws.params.data());
    const std::size_t n_out = experiment_->outputs.size();
    for (const Window& w : experiment_->estimation) {
        if (!initial_state(w.start, ws, nullptr)) return false;
        auto record = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
            if (i < w.first) return true;
            for (std::size_t k = 0; k < n_out; ++k)
                out.push_back(ws.model.output(experiment_->output_indices[k], x.data(), u.data()) - measured_[k][i]);
            return true;
        };
        if (simulate_samples(ws.model, inputs_, w.start, w.last, ws.x, experiment_->simulation, ws.buffers, record) !=
            SimulationStatus::ok)
            return false;
    }
    return true;
}

WindowTrace IdentificationProblem::trace(const std::vector<double>& params, const Window& window,
                                         ProblemWorkspace& ws) const {
    WindowTrace tr;
    tr.window = &window;
    const std::size_t n_out = experiment_->outputs.size();
    tr.measured.assign(n_out, {});
    tr.simulated.assign(n_out, {});
    ws.params = params;
    ws.model.set_parameters(ws.params.data());
    std::string problem;
    if (!initial_state(window.start, ws, &problem)) {
        tr.status = SimulationStatus::not_finite;
        tr.problem = problem;
        return tr;
    }
    auto record = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
        if (i < window.first) return true;
        tr.samples.push_back(i);
        tr.time.push_back(inputs_.time()[i]);
        for (std::size_t k = 0; k < n_out; ++k) {
            tr.measured[k].push_back(measured_[k][i]);
            tr.simulated[k].push_back(ws.model.output(experiment_->output_indices[k], x.data(), u.data()));
        }
        return true;
    };
    tr.status = simulate_samples(ws.model, inputs_, window.start, window.last, ws.x,
                                 experiment_->simulation, ws.buffers, record);
    if (tr.status != SimulationStatus::ok) tr.problem = std::string("simulation ") + to_string(tr.status);
    return tr;
}

}  // namespace tvid
