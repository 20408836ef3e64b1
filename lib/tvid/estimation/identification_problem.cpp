#include "tvid/estimation/identification_problem.hpp"

#include "tvid/estimation/residual_filter.hpp"
#include "tvid/channels/channel_delay.hpp"
#include "tvid/estimation/difference_step.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tvid/estimation/stable_step.hpp"
#include "tvid/estimation/window_score.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

IdentificationProblem::IdentificationProblem(const Experiment& experiment)
    : experiment_(&experiment), definition_(problem_definition(experiment)) {
    const std::vector<ParameterSetting>& parameters = definition_.parameters;
    fixed_values_.resize(parameters.size());
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        const ParameterSetting& p = parameters[i];
        fixed_values_[i] = p.init;
        if (p.fixed) continue;
        free_.push_back(i);
        free_names_.push_back(p.name);
        lower_.push_back(p.min);
        upper_.push_back(p.max);
        range_lo_.push_back(p.range ? p.range->first : p.min);
        range_hi_.push_back(p.range ? p.range->second : p.max);
        init_.push_back(p.init);
        scales_.push_back(p.scale);
    }
    const std::vector<int>& delays = definition_.network.delay_parameters;
    for (std::size_t index : free_)
        delay_column_.push_back(std::find(delays.begin(), delays.end(), static_cast<int>(index)) != delays.end());
    for (const ProblemDefinition::DelayedChannel& c : definition_.delayed_inputs)
        if (const long j = free_column(c.parameter); j >= 0 &&
            std::find(input_delay_columns_.begin(), input_delay_columns_.end(), static_cast<std::size_t>(j)) ==
                input_delay_columns_.end())
            input_delay_columns_.push_back(static_cast<std::size_t>(j));
    if (definition_.estimated.on) seed_estimated_starts();
}

void IdentificationProblem::seed_estimated_starts() {
    const std::unique_ptr<ProblemWorkspace> ws = make_workspace();
    use_parameters(fixed_values_, *ws);  // every parameter at its init, the corrections at 0
    definition_.estimated.seed.clear();
    for (const Window& w : definition_.estimation) {
        std::string problem;
        if (!starts_.recipe_state(w, *ws, &problem)) {
            const SourceLocation& at = experiment_->estimated_start.where;
            throw InputError(at.file, at.line, at.key,
                             "the seed of the estimated start of window '" + w.label +
                                 "' cannot be computed at the parameters' init (" + problem +
                                 "); seed it from another recipe (from: rest, measured or steady)");
        }
        definition_.estimated.seed.push_back(ws->x);
    }
}

double IdentificationProblem::start_scale(std::size_t j) const {
    const NetworkSpec::StartCoordinate* c = start_coordinate(definition_.network, free_[j]);
    if (!c) return 0.0;
    const std::vector<std::vector<double>>& seed = definition_.estimated.seed;
    const double from = c->window < seed.size() ? std::abs(seed[c->window][c->state]) : 0.0;
    return std::max(from, 0.5 * (range_hi_[j] - range_lo_[j]));
}

long IdentificationProblem::free_column(int parameter) const {
    const auto it = std::find(free_.begin(), free_.end(), static_cast<std::size_t>(parameter));
    return parameter >= 0 && it != free_.end() ? static_cast<long>(it - free_.begin()) : -1;
}

std::unique_ptr<ProblemWorkspace> IdentificationProblem::make_workspace() const {
    auto ws = std::make_unique<ProblemWorkspace>(definition_.network);
    ws->model.set_crank_angle_inputs(&definition_.angle_inputs);
    ws->tangent_model.set_crank_angle_inputs(&definition_.angle_inputs);
    ws->tangent_params.resize(definition_.network.parameter_names.size());
    ws->params = fixed_values_;
    ws->x.resize(ws->model.state_size());
    ws->u0.resize(inputs().count());
    ws->buffers.u.resize(inputs().count());
    ws->inputs = &definition_.inputs;
    for (const std::vector<double>& m : definition_.measured) ws->measured.push_back(&m);
    if (!has_delay_parameters()) return ws;
    // Copies of the delayed channels, shifted as the definition holds them: by the inits.
    if (!definition_.delayed_inputs.empty()) {
        ws->shifted_inputs = definition_.inputs;
        ws->inputs = &ws->shifted_inputs;
    }
    ws->shifted_measured.resize(definition_.measured.size());
    for (const ProblemDefinition::DelayedChannel& c : definition_.delayed_inputs)
        ws->applied_delays.push_back(definition_.parameters[static_cast<std::size_t>(c.parameter)].init);
    for (const ProblemDefinition::DelayedChannel& c : definition_.delayed_outputs) {
        ws->shifted_measured[c.channel] = definition_.measured[c.channel];
        ws->measured[c.channel] = &ws->shifted_measured[c.channel];
        ws->applied_delays.push_back(definition_.parameters[static_cast<std::size_t>(c.parameter)].init);
    }
    return ws;
}

double IdentificationProblem::difference_step(std::size_t j, double x) const {
    const std::vector<double>& time = inputs().time();
    if (time.size() > 1 && delay_column_[j])
        return delay_difference_step(mean_sample_interval(time, definition_.recordings));
    return tvid::difference_step(x, lower_[j], upper_[j]);
}

std::pair<double, double> IdentificationProblem::difference_points(std::size_t j, double x) const {
    const double h = difference_step(j, x);
    return {std::min(x + h, upper_[j]), std::max(x - h, lower_[j])};
}

void IdentificationProblem::use_parameters(const std::vector<double>& params, ProblemWorkspace& ws) const {
    ws.params = params;
    ws.model.set_parameters(ws.params.data());
    apply_channel_delays(ws);
}

void IdentificationProblem::apply_channel_delays(ProblemWorkspace& ws) const {
    if (!has_delay_parameters()) return;
    const std::vector<double>& time = inputs().time();
    std::size_t q = 0;
    for (const ProblemDefinition::DelayedChannel& c : definition_.delayed_inputs) {
        const double delay = ws.params[static_cast<std::size_t>(c.parameter)];
        if (ws.applied_delays[q] != delay) {
            delay_channel(c.signal(time), definition_.recordings, delay, ws.shift_scratch);
            ws.shifted_inputs.set_channel(c.channel, ws.shift_scratch);
            ws.applied_delays[q] = delay;
        }
        ++q;
    }
    for (const ProblemDefinition::DelayedChannel& c : definition_.delayed_outputs) {
        const double delay = ws.params[static_cast<std::size_t>(c.parameter)];
        if (ws.applied_delays[q] != delay) {
            delay_channel(c.signal(time), definition_.recordings, delay, ws.shifted_measured[c.channel]);
            ws.applied_delays[q] = delay;
        }
        ++q;
    }
}

void IdentificationProblem::full_parameters(const double* free, std::vector<double>& out) const {
    out = fixed_values_;
    for (std::size_t j = 0; j < free_.size(); ++j) out[free_[j]] = free[j];
    resolve_parameter_formulas(definition_.network.parameter_formulas, out.data());  // `expr:` parameters
}

std::vector<double> IdentificationProblem::full_parameters(const std::vector<double>& free) const {
    std::vector<double> out;
    full_parameters(free.data(), out);
    return out;
}

bool IdentificationProblem::set_free_parameters(const double* free, ProblemWorkspace& ws) const {
    for (std::size_t j = 0; j < free_.size(); ++j) {
        if (!std::isfinite(free[j])) return false;
        ws.params[free_[j]] = free[j];
    }
    ws.model.set_parameters(ws.params.data());
    apply_channel_delays(ws);
    return true;
}

template <class Observer>
SimulationStatus IdentificationProblem::simulate_window(const Window& w, ProblemWorkspace& ws, std::string* problem,
                                                        Observer&& on_scored, SolvedStart* solved,
                                                        const SolvedStart* given) const {
    const bool restored = given && given->x_start.size() == ws.x.size();
    const WindowStart start = restored ? restore_start(*given, ws) : start_window(w, ws, problem);
    if (start.status != SimulationStatus::ok) return start.status;
    if (solved) {  // assigned member by member: the vectors keep their storage
        solved->start = start;
        solved->x_start = ws.x_start;
        solved->x = ws.x;
        solved->u0 = ws.u0;
    }
    std::size_t from = w.start;
    if (warms_up(w)) {
        from = w.first;
        // After a warm-up the first sample is a prediction too: score it.
        std::size_t hint = w.first;
        ws.inputs->at(inputs().time()[w.first], hint, ws.buffers.u.data());
        if (!on_scored(w.first, ws.x, ws.buffers.u)) return SimulationStatus::stopped_by_observer;
    }
    std::size_t reached = from;  // the last sample the simulation reached sane
    const std::size_t n = definition_.network.nodes.size();
    const std::vector<double>& limit = definition_.speed_limits;
    int beyond = -1;  // a node whose speed left the physical range
    const auto scored = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
        for (std::size_t j = 0; j < n && j < limit.size(); ++j)
            if (std::abs(x[n + j]) > limit[j]) {
                beyond = static_cast<int>(j);
                return false;
            }
        reached = i;
        if (ws.stop_requested()) return false;
        return i < w.first ? true : on_scored(i, x, u);  // warm-up: simulated, not scored
    };
    SimulationStatus status =
        simulate_samples(ws.model, *ws.inputs, from, w.last, ws.x, window_settings(definition_, w, ws), ws.buffers, scored);
    if (beyond >= 0) {
        status = SimulationStatus::diverged;
        if (problem) *problem = speed_account(static_cast<std::size_t>(beyond), reached, ws.x);
        return status;
    }
    if (status != SimulationStatus::ok && problem) *problem = failure_account(status, reached, ws.x);
    return status;
}

std::string IdentificationProblem::speed_account(std::size_t node, std::size_t reached,
                                                 const std::vector<double>& x) const {
    const std::vector<double>& time = inputs().time();
    const std::size_t n = definition_.network.nodes.size();
    const NodeSpec& spec = definition_.network.nodes[node];
    const std::string unit = spec.linear ? " m/s" : " rad/s";
    std::string text = "simulation diverged: node " + spec.name + "'s speed reached " + number_text(x[n + node]) + unit +
                       ", beyond " + number_text(kSpeedLimitFactor) +
                       " times the largest measured speed it is tied to, through the gear ratios (" +
                       number_text(definition_.speed_limits[node]) + unit + " allowed), after t = " +
                       number_text(time[reached]) + " s";
    if (reached + 1 < time.size()) text += " (by t = " + number_text(time[reached + 1]) + " s)";
    return text + "; check the start (initial_state) and the gear ratios, or a stiff candidate's step";
}

std::string IdentificationProblem::failure_account(SimulationStatus status, std::size_t reached,
                                                   const std::vector<double>& x) const {
    std::string text = std::string("simulation ") + to_string(status);
    if (status != SimulationStatus::not_finite && status != SimulationStatus::diverged) return text;
    // The state the march stopped at (left in x): the first value that is not finite or
    // beyond the divergence limit names the node, between the last sane sample and the next.
    const std::vector<double>& time = inputs().time();
    const std::size_t n = definition_.network.nodes.size();
    for (std::size_t i = 0; i < x.size() && i < 2 * n; ++i) {
        if (std::isfinite(x[i]) && std::abs(x[i]) <= kDivergenceLimit) continue;
        const NodeSpec& node = definition_.network.nodes[i % n];
        text += ": node " + node.name + "'s " + (i < n ? "angle" : "speed") + " reached " + number_text(x[i]) + " " +
                output_kind_unit(i < n ? OutputKind::angle : OutputKind::speed, node.linear);
        break;
    }
    text += " after t = " + number_text(time[reached]) + " s";
    if (reached + 1 < time.size()) text += " (by t = " + number_text(time[reached + 1]) + " s)";
    text += integration_method_row(definition_.simulation.method).failure_hint;
    return text;
}

std::string IdentificationProblem::failure(const double* free, ProblemWorkspace& ws) const {
    for (std::size_t j = 0; j < free_.size(); ++j)
        if (!std::isfinite(free[j])) return "parameter " + free_names_[j] + " is " + number_text(free[j]);
    set_free_parameters(free, ws);
    for (const Window& w : definition_.estimation) {
        std::string problem;
        const auto ignore = [](std::size_t, const std::vector<double>&, const std::vector<double>&) { return true; };
        const SimulationStatus status = simulate_window(w, ws, &problem, ignore);
        if (status == SimulationStatus::stopped_by_request) return {};
        if (status != SimulationStatus::ok)
            return "estimation window " + w.label + ": " + (problem.empty() ? to_string(status) : problem);
    }
    return {};
}

double IdentificationProblem::cost(const double* free, ProblemWorkspace& ws) const {
    return cost(free, ws, std::numeric_limits<double>::infinity());
}

double IdentificationProblem::cost(const double* free, ProblemWorkspace& ws, double bound) const {
    return window_cost(free, ws, bound, nullptr);
}

double IdentificationProblem::cost(const double* free, ProblemWorkspace& ws, const std::vector<SolvedStart>& starts) const {
    return window_cost(free, ws, std::numeric_limits<double>::infinity(), &starts);
}

double IdentificationProblem::window_cost(const double* free, ProblemWorkspace& ws, double bound,
                                          const std::vector<SolvedStart>* starts) const {
    if (!set_free_parameters(free, ws)) return std::numeric_limits<double>::infinity();
    if (starts && starts->size() != definition_.estimation.size()) starts = nullptr;
    const std::size_t n_out = definition_.measured.size();
    const bool bounded = bound < std::numeric_limits<double>::infinity();
    double total = 0.0;
    for (std::size_t wi = 0; wi < definition_.estimation.size(); ++wi) {
        const Window& w = definition_.estimation[wi];
        WindowScore<double> score(definition_.cost, scored_sample_count(w));
        double cut_at = 0.0;
        bool cut = false;
        ws.window_residuals.clear();
        auto add_sample = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
            for (std::size_t k = 0; k < n_out; ++k) {
                const double e = output_residual(definition_.output_scale[k],
                                                 ws.model.output(definition_.output_indices[k], x.data(), u.data()),
                                                 (*ws.measured[k])[i]);
                if (definition_.filtered)
                    ws.window_residuals.push_back(e);  // scored once the window is complete
                else
                    score.add(e);
            }
            if (!bounded || definition_.filtered) return true;
            cut_at = score.partial_cost(total);
            cut = WindowScore<double>::reached(cut_at, bound);
            return !cut;
        };
        const SimulationStatus status =
            simulate_window(w, ws, nullptr, add_sample, nullptr, starts ? &(*starts)[wi] : nullptr);
        if (cut) return cut_at;
        if (status != SimulationStatus::ok) return std::numeric_limits<double>::infinity();
        if (definition_.filtered) {
            filter_window_residuals(w, ws.window_residuals.data(), 1, 0);
            for (double e : ws.window_residuals) score.add(e);
        }
        total = score.partial_cost(total);
    }
    return finished_cost(total);
}

bool IdentificationProblem::residuals(const double* free, ProblemWorkspace& ws, std::vector<double>& out,
                                      std::vector<SolvedStart>* starts) const {
    out.clear();
    if (starts) starts->resize(definition_.estimation.size());
    if (!set_free_parameters(free, ws)) return false;
    const std::size_t n_out = definition_.measured.size();
    for (std::size_t wi = 0; wi < definition_.estimation.size(); ++wi) {
        auto record = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
            for (std::size_t k = 0; k < n_out; ++k)
                out.push_back(output_residual(definition_.output_scale[k],
                                              ws.model.output(definition_.output_indices[k], x.data(), u.data()),
                                              (*ws.measured[k])[i]));
            return true;
        };
        const std::size_t at = out.size();
        if (simulate_window(definition_.estimation[wi], ws, nullptr, record, starts ? &(*starts)[wi] : nullptr) !=
            SimulationStatus::ok)
            return false;
        filter_window_residuals(definition_.estimation[wi], out.data() + at, 1, 0);
    }
    return true;
}

void IdentificationProblem::filter_window_residuals(const Window& w, double* r, std::size_t columns,
                                                    std::size_t column) const {
    if (!definition_.filtered) return;
    // Window w's block: scored sample s, output k at row s·n_out + k (times `columns`, plus `column`).
    const std::size_t n_out = definition_.measured.size(), n = scored_sample_count(w);
    const double* t = inputs().time().data() + std::max(w.start + 1, w.first);
    for (std::size_t k = 0; k < n_out; ++k)
        filter_residuals(definition_.output_filter[k], t, r + k * columns + column, n, n_out * columns);
}

WindowTrace IdentificationProblem::trace(const std::vector<double>& params, const Window& window,
                                         ProblemWorkspace& ws, SolvedStart* solved, const SolvedStart* given) const {
    WindowTrace tr;
    tr.window = &window;
    const std::size_t n_out = definition_.measured.size();
    tr.measured.assign(n_out, {});
    tr.simulated.assign(n_out, {});
    use_parameters(params, ws);
    auto record = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
        tr.samples.push_back(i);
        tr.time.push_back(inputs().time()[i]);
        for (std::size_t k = 0; k < n_out; ++k) {
            tr.measured[k].push_back((*ws.measured[k])[i]);
            tr.simulated[k].push_back(ws.model.output(definition_.output_indices[k], x.data(), u.data()));
        }
        return true;
    };
    tr.status = simulate_window(window, ws, &tr.problem, record, solved, given);
    return tr;
}

}  // namespace tvid
