#include "tvid/fit/fit_verdict.hpp"

#include <memory>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "tvid/analysis/determined_combinations.hpp"
#include "tvid/analysis/input_noise.hpp"
#include "tvid/channels/recording_spans.hpp"
#include "tvid/estimation/stable_step.hpp"
#include "tvid/experiment/smoothing_speeds.hpp"
#include "tvid/analysis/identifiability.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

namespace {

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}


// ---- the figures ----------------------------------------------------------------------

// Per output, the residual (measured − simulated) of each simulated window of a split;
// against the noise model of the declared input noise where it is given.
std::vector<ResidualWhiteness> split_whiteness(const SplitEvaluation& split, std::size_t outputs,
                                               const PropagatedInputNoise& noise) {
    std::vector<ResidualWhiteness> out(outputs);
    for (std::size_t k = 0; k < outputs; ++k) {
        std::vector<std::vector<double>> segments;
        for (const WindowEvaluation& w : split.windows) {
            if (w.trace.status != SimulationStatus::ok || k >= w.trace.measured.size()) continue;
            std::vector<double> e(w.trace.measured[k].size());
            for (std::size_t i = 0; i < e.size(); ++i) e[i] = w.trace.measured[k][i] - w.trace.simulated[k][i];
            segments.push_back(std::move(e));
        }
        out[k] = noise.available && k < noise.covariance.size() ? assess_whiteness_against(segments, noise.covariance[k][k])
                                                                : assess_whiteness(segments);
    }
    return out;
}

// The declared input noise carried to the outputs of a split's simulated windows at the
// optimum (analysis/input_noise.hpp): its covariances between outputs, and its cross-
// covariances with each input's noise; unavailable when no input declares noise.
struct SplitInputNoise {
    PropagatedInputNoise propagated;
    std::vector<std::vector<std::vector<double>>> cross;  ///< InputNoiseResponses::input_cross
};

// `known`: the responses of the split's windows taken before (the fit's, of the estimation
// windows, for its standard errors), used when every window simulated.
SplitInputNoise split_input_noise(const IdentificationProblem& problem, const SplitEvaluation& split,
                                  const std::vector<double>& params, int threads, const InputNoiseResponses* known = nullptr) {
    SplitInputNoise out;
    if (!declares_input_noise(problem.definition())) return out;
    std::vector<const Window*> windows;
    for (const WindowEvaluation& w : split.windows)
        if (w.trace.status == SimulationStatus::ok) windows.push_back(w.trace.window);
    if (windows.empty()) return out;
    const bool taken = known && !known->delta.empty() && known->delta.front().size() == windows.size() &&
                       windows.size() == split.windows.size();
    InputNoiseResponses computed;
    if (!taken) computed = input_noise_responses(problem, params, windows, kInputNoiseDraws, threads);
    const InputNoiseResponses& responses = taken ? *known : computed;
    out.propagated = propagated_covariance(responses, problem.experiment().outputs.size(), std::numeric_limits<int>::max());
    out.cross = responses.input_cross;
    return out;
}

// The residual analysis of a split: each output's residual and each input read by time, at
// the scored samples of every simulated window; the inputs as the parameters read them (a
// delay parameter's channel shifted by its fitted delay).
ResidualCorrelation split_correlation(const IdentificationProblem& problem, const SplitEvaluation& split,
                                      const std::vector<double>& params, const SplitInputNoise& noise) {
    const Experiment& ex = problem.experiment();
    const std::unique_ptr<ProblemWorkspace> ws = problem.make_workspace();
    problem.use_parameters(params, *ws);
    const std::vector<std::size_t> inputs = correlated_inputs(ex);
    std::vector<std::vector<std::vector<double>>> residuals(ex.outputs.size()), input_values(inputs.size());
    for (const WindowEvaluation& w : split.windows) {
        if (w.trace.status != SimulationStatus::ok) continue;
        for (std::size_t k = 0; k < ex.outputs.size() && k < w.trace.measured.size(); ++k) {
            std::vector<double> e(w.trace.measured[k].size());
            for (std::size_t i = 0; i < e.size(); ++i) e[i] = w.trace.measured[k][i] - w.trace.simulated[k][i];
            residuals[k].push_back(std::move(e));
        }
        // The time inputs come first in the channels, in the order of experiment.inputs.
        for (std::size_t q = 0; q < inputs.size(); ++q) {
            std::vector<double> u(w.trace.samples.size());
            for (std::size_t i = 0; i < u.size(); ++i) u[i] = ws->inputs->value(q, w.trace.samples[i]);
            input_values[q].push_back(std::move(u));
        }
    }
    // The time inputs are the first channels, so input q's declared noise is channel q's.
    std::vector<std::vector<std::vector<double>>> noise_covariance(inputs.size());
    for (std::size_t q = 0; q < inputs.size() && q < noise.cross.size(); ++q) noise_covariance[q] = noise.cross[q];
    // And the cross-correlations' bands over a quarter of the window: the carried noise's
    // memory can be as long (a vehicle's speed wanders with its torque's noise).
    std::vector<int> band_lags(ex.outputs.size(), noise.propagated.available ? std::numeric_limits<int>::max() : 0);
    return analyse_residual_correlation(residuals, input_values, kCorrelationLags, noise_covariance, band_lags);
}

// The N × n_y prediction errors of the estimation windows.
InformationCriteria estimation_criteria(const SplitEvaluation& split, std::size_t outputs, int parameters) {
    Eigen::Index rows = 0;
    for (const WindowEvaluation& w : split.windows)
        if (w.trace.status == SimulationStatus::ok) rows += static_cast<Eigen::Index>(w.trace.time.size());
    Eigen::MatrixXd e(rows, static_cast<Eigen::Index>(outputs));
    Eigen::Index row = 0;
    for (const WindowEvaluation& w : split.windows) {
        if (w.trace.status != SimulationStatus::ok) continue;
        for (std::size_t i = 0; i < w.trace.time.size(); ++i, ++row)
            for (std::size_t k = 0; k < outputs; ++k)
                e(row, static_cast<Eigen::Index>(k)) = w.trace.measured[k][i] - w.trace.simulated[k][i];
    }
    return information_criteria(e, parameters);
}

// Which bound a value sits on: -1 lower, +1 upper, 0 neither. On it: the optimizers clamp
// to a bound exactly, so within kNearBound of the box width, and (for a wide box) within
// 1 % of the value's own size.
int on_bound(double value, double lower, double upper) {
    const bool has_lower = lower > -1e299, has_upper = upper < 1e299;
    const double width = has_lower && has_upper ? upper - lower : std::max(std::abs(value), 1e-300);
    auto near = [&](double bound) {
        const double gap = std::abs(value - bound);
        return gap <= kNearBound * width && gap <= 0.01 * std::max(std::abs(value), std::abs(bound));
    };
    if (has_lower && near(lower)) return -1;
    if (has_upper && near(upper)) return 1;
    return 0;
}

// Intervals that reach beyond the box are cut at it; a parameter on a bound gets the
// one-sided interval from the bound inwards.
void bound_intervals(const IdentificationProblem& problem, const std::vector<double>& best, ParameterUncertainty& u) {
    if (!u.available) return;
    for (std::size_t j = 0; j < best.size() && j < u.ci_low.size(); ++j) {
        if (!std::isfinite(u.ci_low[j])) continue;
        const double lo = problem.lower()[j], hi = problem.upper()[j];
        const int side = on_bound(best[j], lo, hi);
        if (side != 0) {
            u.interval[j] = "one-sided";
            if (side < 0) u.ci_low[j] = lo;
            else u.ci_high[j] = hi;
        }
        if (u.ci_low[j] < lo) { u.ci_low[j] = lo; if (side == 0) u.interval[j] = "clipped"; }
        if (u.ci_high[j] > hi) { u.ci_high[j] = hi; if (side == 0) u.interval[j] = "clipped"; }
    }
}

// ---- the findings ---------------------------------------------------------------------

void judge_run(const FitResult& fit, Verdict& v) {
    if (!fit.success) {
        v.add({"no_result", Severity::error, "", "no candidate simulated: no parameters were identified",
               "simulate the init values (tvid simulate) and read why the first window fails"});
        return;
    }
    if (fit.interrupted)
        v.add({"interrupted", Severity::warning, "", "stopped before the optimizer finished: the best parameters so far",
               "run again to the end"});
    else if (!fit.run.converged)
        v.add({"not_converged", Severity::warning, "", fit.run.name + " stopped on its budget (" + fit.run.termination + "), not a tolerance",
               "raise the optimizer's iteration or evaluation limit, or start closer (init, range)"});
    if (fit.run.evaluations > 0 && fit.run.failed_evaluations > 0) {
        const double share = static_cast<double>(fit.run.failed_evaluations) / static_cast<double>(fit.run.evaluations);
        v.add({"failed_simulations", share >= kFailedShareWarning ? Severity::warning : Severity::info, "",
               std::to_string(fit.run.failed_evaluations) + " of " + std::to_string(fit.run.evaluations) +
                   " candidate simulations failed (" + whole_percent(share) + ")" +
                   (fit.run.first_failure.empty() ? "" : "; the first: " + fit.run.first_failure),
               "narrow the search box, or a smaller simulation.step or integrator rosenbrock4 for stiff candidates"});
    }
    int failed_starts = 0, redrawn = 0, draws = 0;
    for (const StartResult& s : fit.run.starts) {
        failed_starts += std::isfinite(s.best_cost) ? 0 : 1;
        redrawn += s.draws > 1 ? 1 : 0;
        draws += s.draws;
    }
    if (failed_starts > 0)
        v.add({"failed_starts", Severity::warning, "",
               std::to_string(failed_starts) + " of " + std::to_string(fit.run.starts.size()) +
                   " multistart starts failed to simulate at every point drawn for them (" + std::to_string(draws) +
                   " points drawn in all)",
               "narrow range to where the model simulates, or a stiffer-safe integrator (rosenbrock4)"});
    else if (redrawn > 0)
        v.add({"redrawn_starts", Severity::info, "",
               std::to_string(redrawn) + " of " + std::to_string(fit.run.starts.size()) +
                   " multistart starts were drawn again because their first point could not be simulated (" +
                   std::to_string(draws) + " points drawn for " + std::to_string(fit.run.starts.size()) + " starts)",
               "the box reaches candidates the integrator cannot simulate: narrow range, or a smaller simulation.step"});
}

// A swarm that stopped still improving or still spread: its best is not yet an optimum.
// After pso alone a warning; where least squares polished the swarm's best (pso+lm) a note,
// since the polish goes on from there.
void judge_swarm(const IdentificationProblem& problem, const FitResult& fit, Verdict& v) {
    if (!fit.run.swarm || fit.interrupted) return;
    const PsoConvergence& c = *fit.run.swarm;
    const bool improving = c.recent_improvement > kSwarmStillImproving;
    const bool spread = c.max_spread > kSwarmStillSpread;
    if (!improving && !spread) return;
    std::string widest;
    for (std::size_t j = 0; j < c.spread.size() && j < problem.dimension(); ++j)
        if (c.spread[j] == c.max_spread) widest = problem.free_names()[j];
    std::string what;
    if (improving)
        what = "its best cost still fell " + readable_percent(c.recent_improvement) + " over its last " + std::to_string(c.window) +
               " iterations";
    if (spread)
        what += (what.empty() ? "" : ", and ") + std::string("its particles' best points still span ") +
                whole_percent(c.max_spread) + " of the box in " + widest;
    const bool polished = optimizer_traits(problem.experiment().estimation_settings.optimizer).least_squares;
    v.add({"swarm_not_converged", polished ? Severity::info : Severity::warning, "",
           "the swarm stopped before it converged: " + what +
               (polished ? "; the least-squares polish went on from its best" : ": its best need not be the optimum"),
           polished ? "if the polish ended far from the swarm's best, give the swarm more iterations (estimation.pso.iterations)"
                    : "run pso+lm (least squares from the swarm's best) or multistart, or more iterations "
                      "(estimation.pso.iterations); scale: log for parameters whose box spans decades"});
}

// After an optimizer that does not solve least squares itself (the swarm, NLopt) on an l2
// cost: a Gauss–Newton step from its best that would still cut the cost by more than 1 %,
// and by more than the noise can tell (one σ² of the residuals), says its best is no minimum.
void judge_minimum(const IdentificationProblem& problem, const FitResult& fit, Verdict& v) {
    const Experiment& ex = problem.experiment();
    const ParameterUncertainty& u = fit.uncertainty;
    if (ex.estimation_settings.cost != CostKind::l2 || !u.available || !std::isfinite(u.gauss_newton_decrease)) return;
    if (u.residuals <= problem.dimension() || !(u.sum_of_squares > 0)) return;
    const double sigma2 = u.sum_of_squares / static_cast<double>(u.residuals - problem.dimension());
    const double share = u.gauss_newton_decrease / u.sum_of_squares;
    if (!(share > kNotAtMinimumShare) || !(u.gauss_newton_decrease > sigma2)) return;
    const bool swarm = optimizer_traits(ex.estimation_settings.optimizer).swarm;
    v.add({"not_at_minimum", Severity::warning, "",
           std::string("the ") + optimizer_name(ex.estimation_settings.optimizer) +
               " optimizer's best is not a minimum of the cost: one least-squares step from it would lower the "
               "sum of squares by about " + whole_percent(share) + " (linearised)",
           swarm ? "run pso+lm (least squares from the swarm's best) or multistart, or more iterations "
                   "(estimation.pso.iterations)"
                 : "run lm or multistart from its best (--set parameters.NAME.init=...), or tighten the optimizer's "
                   "tolerances"});
}

void judge_windows(const Experiment& ex, const Evaluation& ev, Verdict& v) {
    const std::string failed = first_failed_window(ev);
    if (!failed.empty())
        v.add({"window_failed", Severity::error, "", "at the optimum the " + failed,
               "the optimum is not usable on every window: check that window's data, or fix the parameter that drives it unstable"});
    for (const SplitEvaluation* split : {&ev.estimation, &ev.validation}) {
        for (const WindowEvaluation& w : split->windows) {
            if (w.trace.status != SimulationStatus::ok) continue;
            for (std::size_t k = 0; k < ex.outputs.size() && k < w.metrics.size(); ++k) {
                const double f = w.metrics[k].fit_percent, pooled = split->pooled[k].fit_percent;
                if (!std::isfinite(f) || !std::isfinite(pooled) || split->windows.size() < 2) continue;
                if (f >= 0.0 && f >= pooled - kPoorWindowPoints) continue;
                // A window of little motion has a low fit % at the noise floor: only a
                // systematic misfit makes it poor.
                std::vector<double> e(w.trace.measured[k].size());
                for (std::size_t i = 0; i < e.size(); ++i) e[i] = w.trace.measured[k][i] - w.trace.simulated[k][i];
                if (assess_whiteness({e}).systematic_share < kSystematicShareError) continue;
                v.add({"poor_window", Severity::warning, w.trace.window->label,
                       split->split + " window " + w.trace.window->label + ": fit " + num(f) + " % on " +
                           ex.outputs[k].model_name + " while the pooled fit is " + num(pooled) + " %",
                       "look at that window in the report's traces (its misfit is systematic); the pooled figure hides it"});
            }
        }
    }
}

// A residual at the numerical level (noise-free data fitted exactly): its structure is the
// integrator's, not a misfit.
bool exact_fit(const SplitEvaluation& split, std::size_t k) {
    return k < split.pooled.size() && split.pooled[k].fit_percent >= kExactFitPercent;
}

// The residual analysis of the estimation windows: an input whose cross-correlation with a
// residual leaves its band at more lags τ ≥ 0 than chance, and a residual whose
// autocorrelation does while the whiteness test above raised nothing.
void judge_correlations(const Experiment& ex, const FitResult& fit, Verdict& v) {
    const ResidualCorrelation& c = fit.correlation_estimation;
    const std::vector<std::size_t> inputs = correlated_inputs(ex);
    for (std::size_t k = 0; k < ex.outputs.size() && k < c.autocorrelation.size(); ++k) {
        if (exact_fit(fit.evaluation.estimation, k)) continue;
        const std::string& output = ex.outputs[k].model_name;
        for (std::size_t q = 0; q < inputs.size() && q < c.cross_correlation.size(); ++q) {
            const CorrelationTest& t = c.cross_correlation[q][k];
            const int outside = t.outside_from(0), tested = t.tested(0);
            if (!t.available || !correlation_beyond_chance(outside, tested)) continue;
            // The largest |r − expected| at τ ≥ 0 (the lags run from −M, so τ = 0 is at index M).
            const auto departure = [&](std::size_t i) {
                return std::abs(t.values[i] - (i < t.expected.size() ? t.expected[i] : 0.0));
            };
            std::size_t largest = static_cast<std::size_t>(c.lags);
            for (std::size_t i = largest; i < t.values.size(); ++i)
                if (departure(i) > departure(largest)) largest = i;
            const std::string& input = ex.inputs[inputs[q]].model_name;
            const std::string beyond =
                t.expected.empty() ? "" : " (beyond " + num(t.values[largest] - departure(largest) *
                                              (t.values[largest] >= t.expected[largest] ? 1.0 : -1.0)) +
                                              ", what the declared noise of " + input + " leaves)";
            v.add({"missing_input_dynamic", Severity::warning, input,
                   output + "'s residual follows input " + input + ": their cross-correlation lies outside its 99 % band "
                       "at " + std::to_string(outside) + " of the " + std::to_string(tested) + " lags tau = 0 to " +
                       std::to_string(c.lags) + " samples (largest " + num(t.values[largest]) + beyond + " at tau = " +
                       std::to_string(t.lags[largest]) + ", band +-" + num(t.band) + "): a dynamic from " + input +
                       " is missing from the model",
                   "model how " + input + " reaches " + output + ": a missing element or mode on its path, a wrong "
                       "stiffness or damping there, or a delay on " + input + " (delay:); residual_analysis.png shows "
                       "the lags"});
        }
        const CorrelationTest& a = c.autocorrelation[k];
        if (!a.available || !correlation_beyond_chance(a.outside_from(1), a.tested(1))) continue;
        // A declared input noise colours the residual: its whiteness was judged against it.
        if (k < fit.whiteness_estimation.size() && fit.whiteness_estimation[k].propagated_noise_rms > 0) continue;
        const bool said = std::any_of(v.findings.begin(), v.findings.end(), [&](const Finding& f) {
            return f.code == "residuals_not_white" && f.subject == output;
        });
        if (said) continue;
        v.add({"residual_autocorrelation", Severity::info, output,
               output + ": the residual's autocorrelation lies outside its 99 % band at " +
                   std::to_string(a.outside_from(1)) + " of " + std::to_string(a.tested(1)) +
                   " lags (not white), though only " + whole_percent(k < fit.whiteness_estimation.size()
                                                               ? fit.whiteness_estimation[k].systematic_share : 0.0) +
                   " of its variance is systematic",
               "a small misfit or coloured noise: read residual_analysis.png and the residual spectrum"});
    }
}

// What to try when validation is worse. An estimated start whose validation windows start
// from the recipe: their start is the one thing the fit did not estimate for them.
std::string validation_worse_hint(const Experiment& ex) {
    if (ex.estimated_start.on && !ex.estimated_start.validation)
        return "the estimation windows' starts were estimated and the validation windows' were not: give "
               "initial_state.validation: estimated, so that each validation window's start is estimated too with the "
               "model held; else estimate on more windows or fix weakly determined parameters";
    return "estimate on more windows or cycles, or fix weakly determined parameters; and check that each "
           "validation window starts as the recording does (initial_state, warm-up)";
}

void judge_residuals(const Experiment& ex, const FitResult& fit, Verdict& v) {
    for (std::size_t k = 0; k < ex.outputs.size() && k < fit.whiteness_estimation.size(); ++k) {
        const ResidualWhiteness& w = fit.whiteness_estimation[k];
        const std::string& name = ex.outputs[k].model_name;
        if (w.samples == 0 || exact_fit(fit.evaluation.estimation, k)) continue;
        const bool error = w.systematic_share >= kSystematicShareError;
        if (!error && !(w.systematic_share >= kSystematicShareWarning && w.p_value < kWhitenessP)) continue;
        char p[32];
        std::snprintf(p, sizeof p, w.p_value < 1e-16 ? "< 1e-16" : "%.2g", w.p_value);
        const std::string beyond =
            w.propagated_noise_rms > 0 ? " beyond the declared input noise (RMSE " + num(w.rms) + ", of which the input "
                                             "noise carried to it is " + num(w.propagated_noise_rms) + "; Ljung-Box p "
                                       : " (RMSE " + num(w.rms) + " against an unpredictable part (noise) of " +
                                             num(w.noise_rms) + "; Ljung-Box p ";
        v.add({"residuals_not_white", error ? Severity::error : Severity::warning, name,
               name + ": " + whole_percent(w.systematic_share) + " of the residual variance is systematic" + beyond + p + ")",
               "the model misses what the data hold: another start or optimizer, wider bounds, scale: log on wide "
               "boxes, or a model element (a delay, a mode); a logged input's noise is declared with noise: under "
               "inputs"});
    }
    judge_correlations(ex, fit, v);
    for (std::size_t k = 0; k < ex.outputs.size() && k < fit.whiteness_validation.size(); ++k) {
        const ResidualWhiteness& e = fit.whiteness_estimation[k];
        const ResidualWhiteness& val = fit.whiteness_validation[k];
        if (e.samples == 0 || val.samples == 0 || !(e.rms > 0)) continue;
        if (exact_fit(fit.evaluation.estimation, k) && exact_fit(fit.evaluation.validation, k)) continue;
        // Residuals that are mostly noise: each RMSE over its own noise, so that windows of
        // more noise do not count as worse fits. Otherwise the RMSEs themselves.
        const bool noise = e.noise_rms > 0 && val.noise_rms > 0 && e.systematic_share < kSystematicShareError &&
                           val.systematic_share < kSystematicShareError;
        const double ratio = noise ? (val.rms / val.noise_rms) / (e.rms / e.noise_rms) : val.rms / e.rms;
        if (!(ratio > kValidationWorseWarning)) continue;
        const std::string& name = ex.outputs[k].model_name;
        v.add({"validation_worse", ratio > kValidationWorseError ? Severity::error : Severity::warning, name,
               name + ": validation RMSE " + num(val.rms) + " against " + num(e.rms) + " in estimation (" +
                   num(ratio) + " times worse" + (noise ? ", each over its noise)" : ")"),
               validation_worse_hint(ex)});
    }
}

void judge_parameters(const IdentificationProblem& problem, const FitResult& fit, Verdict& v) {
    const auto& names = problem.free_names();
    for (std::size_t j = 0; j < names.size() && j < fit.best_free.size(); ++j) {
        const double lo = problem.lower()[j], hi = problem.upper()[j], p = fit.best_free[j];
        const int side = on_bound(p, lo, hi);
        if (side == 0) continue;
        v.add({"at_bound", Severity::warning, names[j],
               names[j] + " = " + num(p) + " is on its " + (side < 0 ? "lower" : "upper") + " bound " +
                   num(side < 0 ? lo : hi) + ": the optimum may lie beyond it",
               "widen the bound if the physics allows; if the bound is the physical value, fix " + names[j] + " there"});
    }
    const IdentifiabilityReport id = assess_identifiability(problem, fit.uncertainty, fit.best_free);
    if (!id.available) return;
    if (!id.null_directions.empty()) {
        std::string text = "the data determine only " + std::to_string(id.rank) + " of " + std::to_string(id.of) +
                           " parameter directions: ";
        for (std::size_t i = 0; i < id.null_directions.size(); ++i) text += (i ? "; " : "") + id.null_directions[i].text;
        const auto& lead = id.null_directions.front().members;
        v.add({"undetermined", Severity::warning, lead.empty() ? "" : lead.front(), text,
               id.null_directions.size() == 1
                   ? "fix one of these parameters at a known value, or add an output that separates them"
                   : "fix one parameter of each combination at a known value, or add outputs that separate them"});
    }
    // Weak parameters that trade against each other, whose combination the data do pin:
    // one finding for the group, naming that combination, instead of one per member.
    std::vector<bool> in_group(names.size(), false);
    for (const DeterminedCombination& c : determined_combinations(fit.uncertainty, id, fit.best_free, kCorrelatedGroup)) {
        if (!(c.std_error <= kWeakRelativeError * std::abs(c.value))) continue;
        std::string members, combination;
        for (std::size_t k = 0; k < c.members.size(); ++k) {
            const std::string& n = names[c.members[k]];
            in_group[c.members[k]] = true;
            members += (k == 0 ? "" : k + 1 == c.members.size() ? " and " : ", ") + n;
            const double w = c.weights[k];
            combination += (k == 0 ? (w < 0 ? "-" : "") : (w < 0 ? " - " : " + ")) +
                           (std::abs(std::abs(w) - 1.0) < 5e-4 ? std::string() : num(std::abs(w)) + "·") + n;
        }
        v.add({"weak_apart", Severity::warning, names[c.members.front()],
               members + " are weakly determined one by one (standard errors " + whole_percent(c.smallest_member_error) + " to " +
                   whole_percent(c.largest_member_error) + "), trading against each other (|correlation| >= " +
                   num(c.weakest_correlation) + "); the data determine their combination " + combination + " = " +
                   num(c.value) + " ± " + num(c.std_error) + " (" + num(100.0 * c.std_error / std::abs(c.value)) + " %)",
               "fix all but one of them at known values (e.g. from a run-down or a component test), or estimate over "
               "more windows or cycles (windows.estimation), where they separate"});
    }
    for (const ParameterIdentifiability& q : id.parameters) {
        if (q.flag != IdentifiabilityFlag::weak) continue;
        const auto j = static_cast<std::size_t>(&q - id.parameters.data());
        if (j < in_group.size() && in_group[j]) continue;
        v.add({"weakly_determined", Severity::warning, q.name,
               q.name + " is weakly determined: standard error " + whole_percent(q.judged_std_error) + " of " + q.judged_against,
               "fix it, excite it more (another window or cycle), or read its profile"});
    }
}

// Another multistart start that ended as low, elsewhere (a start the race stopped has not
// converged: where it stopped is no optimum).
void judge_starts(const IdentificationProblem& problem, const FitResult& fit, Verdict& v) {
    const std::vector<StartResult>& starts = fit.run.starts;
    if (fit.run.best_start < 1 || starts.size() < 2) return;
    const StartResult& best = starts[static_cast<std::size_t>(fit.run.best_start - 1)];
    const auto& names = problem.free_names();
    for (const StartResult& s : starts) {
        if (s.start == best.start || !std::isfinite(s.best_cost) || s.best.size() != best.best.size() ||
            s.termination_type == TerminationType::raced_out)
            continue;
        if (s.best_cost - best.best_cost > kNearEqualCost * best.best_cost) continue;
        std::size_t widest = names.size();
        double widest_gap = 0.0;
        for (std::size_t j = 0; j < s.best.size(); ++j) {
            const double gap = std::abs(s.best[j] - best.best[j]);
            // Within 3 standard errors: the sandwich's where correlated residuals make it the larger.
            double se = j < fit.uncertainty.std_error.size() ? fit.uncertainty.std_error[j] : 0.0;
            if (j < fit.uncertainty.robust_std_error.size() && fit.uncertainty.robust_std_error[j] > se)
                se = fit.uncertainty.robust_std_error[j];
            const double scale = std::max(std::abs(best.best[j]), 1e-300);
            if (gap <= kDistinctRelative * scale || (std::isfinite(se) && gap <= 3.0 * se)) continue;
            if (gap / scale > widest_gap) { widest_gap = gap / scale; widest = j; }
        }
        if (widest == names.size()) continue;
        v.add({"non_unique_optimum", Severity::warning, names[widest],
               "start " + std::to_string(s.start) + " ends at cost " + num(s.best_cost) + " (best " + num(best.best_cost) +
                   ", start " + std::to_string(best.start) + ") with " + names[widest] + " = " + num(s.best[widest]) +
                   " against " + num(best.best[widest]),
               "the data do not single out one optimum: fix a parameter, add data, or compare the starts in starts.csv"});
        return;  // one is enough to say it
    }
}

// A box the optimizer samples linearly over several decades: almost every particle or
// start lands in its top decade.
void judge_search_boxes(const Experiment& ex, Verdict& v) {
    if (optimizer_traits(ex.estimation_settings.optimizer).starts_at_init) return;  // the box is only a bound
    for (const ParameterSetting& p : ex.parameters) {
        if (!spans_decades(p, kWideBoxDecades)) continue;
        const auto box = search_interval(p);
        const double decades = std::log10(box->second / box->first);
        const double top_decade = (box->second - box->second / 10) / (box->second - box->first);  // share of uniform samples
        v.add({"wide_linear_box", Severity::warning, p.name,
               p.name + "'s search box [" + num(box->first) + ", " + num(box->second) + "] spans " + num(decades) +
                   " decades on a linear scale: " + whole_percent(top_decade) + " of the samples fall in its top decade",
               "scale: log on " + p.name + " spreads the " + std::string(optimizer_name(ex.estimation_settings.optimizer)) +
                   " samples evenly per decade (or give it a narrower range)"});
    }
}

// Each smoothed sign's width, when the data chose it, and a warning where many samples sit
// within a few widths of zero: there the dry friction is a viscous damper of slope F/v_s,
// and the fit trades the one against the other.
void judge_smoothing(const Experiment& ex, Verdict& v) {
    for (const SmoothingChoice& c : ex.smoothing) {
        if (!c.given)
            v.add({"smoothing_speed", Severity::info, c.element,
                   c.element + "'s sign is smoothed over " + num(c.speed) + " " + c.unit + ": " + c.basis,
                   "give smoothing_speed: to choose it (smaller is closer to dry friction, and stiffer)"});
        if (c.share_within >= kSmoothedShareWarning)
            v.add({"smoothed_friction", Severity::warning, c.element,
                   whole_percent(c.share_within) + " of the samples in motion have a speed across " + c.element + " within " +
                       num(kSmoothingShareSpeeds) + " smoothing speeds (" + num(kSmoothingShareSpeeds * c.speed) + " " +
                       c.unit + ") of zero, where its smoothed sign acts as a viscous term: the fit trades its dry "
                       "part against the viscous one",
                   "a smaller smoothing_speed (a stiffer law: the simulation may take substeps)"});
    }
}

void judge_stability(const StepStability& s, Verdict& v) {
    if (s.assessed && s.implicit) {
        v.add({"implicit_steps", Severity::info, s.window,
               "window " + s.window + ": at the fitted parameters a mode is too fast for " +
                   std::to_string(kMaxStableSubsteps) + " RK4 substeps of the experiment's step; the window is "
                   "simulated by sdirk3's implicit steps at that step",
               "method: sdirk3 for every candidate, or a model without the stiff mode (a rigid ideal_gear for a stiff mesh)"});
        return;
    }
    if (!s.assessed || s.margin < kStepMarginWarning) return;
    // Divided into substeps, the window is simulated within RK4's limit whatever the
    // candidate's stiffness (estimation/stable_step.hpp): no candidate blows up for it, it
    // only costs time.
    if (s.substeps > 1) {
        v.add({"substeps", Severity::info, s.window,
               "window " + s.window + ": a mode of " + num(s.frequency_hz) + " Hz (|lambda| " + num(s.rate) +
                   " 1/s) needs " + std::to_string(s.substeps) + " substeps of the experiment's step, each " +
                   num(s.step) + " s: each simulation takes " + std::to_string(s.substeps) + " times as long",
               "a smaller simulation.step saves nothing; integrator rosenbrock4 takes such a mode in long steps"});
        return;
    }
    v.add({"near_instability", Severity::warning, s.window,
           "window " + s.window + ": a mode of " + num(s.frequency_hz) + " Hz (damping ratio " + num(s.damping_ratio) +
               ", |lambda| " + num(s.rate) + " 1/s) is at " + whole_percent(s.margin) + " of RK4's stability limit for the step " +
               num(s.step) + " s",
           "a smaller simulation.step, or integrator rosenbrock4; a slightly stiffer candidate would blow up"});
}

}  // namespace

// A delay parameter that ended near half way between samples: there the delayed channel
// is read between two samples, which damps its content near the Nyquist frequency. If the
// cost one sample on is as low again (the gain recurs every sample) while the nearest
// whole-sample delay is worse, the fit was buying that smoothing, not a delay.
void judge_delays(const IdentificationProblem& problem, const FitResult& fit, Verdict& v) {
    const std::vector<double>& time = problem.inputs().time();
    if (time.size() < 2) return;
    const double dt = mean_sample_interval(time, problem.definition().recordings);
    std::unique_ptr<ProblemWorkspace> ws;
    for (std::size_t j = 0; j < problem.dimension(); ++j) {
        if (!problem.is_delay_column(j)) continue;
        const double d = fit.best_free[j], samples = d / dt, past = samples - std::floor(samples);
        if (std::abs(past - 0.5) > kHalfSampleBand) continue;
        if (!ws) ws = problem.make_workspace();
        const auto cost_at = [&](double delay) {
            std::vector<double> x = fit.best_free;
            x[j] = std::clamp(delay, problem.lower()[j], problem.upper()[j]);
            return problem.cost(x.data(), *ws);
        };
        const double best = cost_at(d), whole = cost_at((std::floor(samples) + (past < 0.5 ? 0.0 : 1.0)) * dt);
        const double on = std::min(cost_at(d + dt), cost_at(d - dt));
        if (!(whole > best) || !(on - best < kHalfSampleRecurrence * (whole - best))) continue;
        const std::string& name = problem.free_names()[j];
        v.add({"delay_smoothing", Severity::warning, name,
               name + " = " + num(d) + " s ends " + num(samples) + " samples on, half way between samples, "
                   "where the channel is interpolated and its content near the Nyquist frequency damped; the cost "
                   "there is " + num(best) + ", " + num(on) + " one sample on, and " + num(whole) +
                   " at the nearest whole sample: the gain recurs every sample, as smoothing does and a delay does not",
               "fix " + name + " at a whole number of samples, or low-pass the data; a real delay keeps its gain off "
               "the half sample"});
    }
}

bool correlation_beyond_chance(int outside, int tested) {
    return static_cast<double>(outside) > kCorrelationChanceShare * tested + kCorrelationLagMargin;
}

bool residual_is_white(const ResidualWhiteness& w) { return w.samples > 0 && w.p_value >= kWhitenessP; }

std::vector<std::size_t> correlated_inputs(const Experiment& experiment) {
    std::vector<std::size_t> out;
    for (std::size_t q = 0; q < experiment.inputs.size(); ++q)
        if (!experiment.inputs[q].by_angle) out.push_back(q);
    return out;
}

void judge_fit(const IdentificationProblem& problem, FitResult& fit, int threads) {
    const Experiment& ex = problem.experiment();
    const std::size_t outputs = ex.outputs.size();
    Verdict v;
    judge_run(fit, v);
    if (fit.success) judge_swarm(problem, fit, v);
    if (fit.success) {
        const SplitInputNoise noise_estimation = split_input_noise(problem, fit.evaluation.estimation, fit.best_params,
                                                                   threads, &fit.input_noise);
        const SplitInputNoise noise_validation = split_input_noise(problem, fit.evaluation.validation, fit.best_params, threads);
        fit.whiteness_estimation = split_whiteness(fit.evaluation.estimation, outputs, noise_estimation.propagated);
        fit.whiteness_validation = split_whiteness(fit.evaluation.validation, outputs, noise_validation.propagated);
        fit.correlation_estimation = split_correlation(problem, fit.evaluation.estimation, fit.best_params, noise_estimation);
        fit.correlation_validation = split_correlation(problem, fit.evaluation.validation, fit.best_params, noise_validation);
        fit.criteria = estimation_criteria(fit.evaluation.estimation, outputs, static_cast<int>(problem.dimension()));
        if (!fit.interrupted)
            fit.stability = assess_step_stability(
                problem, fit.best_params,
                fit.evaluation.params == fit.best_params ? &fit.evaluation.estimation_starts : nullptr);
        bound_intervals(problem, fit.best_free, fit.uncertainty);
        judge_windows(ex, fit.evaluation, v);
        judge_residuals(ex, fit, v);
        judge_parameters(problem, fit, v);
        judge_minimum(problem, fit, v);
        judge_starts(problem, fit, v);
        judge_stability(fit.stability, v);
        judge_search_boxes(ex, v);
        judge_smoothing(ex, v);
        if (!fit.interrupted) judge_delays(problem, fit, v);
    }
    fit.verdict = std::move(v);
}

}  // namespace tvid
