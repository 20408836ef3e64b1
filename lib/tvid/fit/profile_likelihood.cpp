#include "tvid/fit/profile_likelihood.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "tvid/analysis/uncertainty.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/parallel_region.hpp"

namespace tvid {

namespace {

constexpr double kDefaultSpan = 4.0;  // standard errors either side of θ̂

// The experiment with every free parameter starting at `free` (the problem's order), and
// parameter `held` (a model index, or none) fixed at `value`.
Experiment restarted(const Experiment& ex, const IdentificationProblem& problem, const std::vector<double>& free,
                     std::optional<std::size_t> held, double value) {
    Experiment copy = ex;
    for (std::size_t j = 0; j < free.size(); ++j) copy.parameters[problem.free_indices()[j]].init = free[j];
    if (held) {
        copy.parameters[*held].fixed = true;
        copy.parameters[*held].init = value;
    }
    return copy;
}

struct LeastSquaresFit {
    std::vector<double> best;
    double best_cost = std::numeric_limits<double>::infinity();
    std::string termination;
    bool converged = false;
    Eigen::MatrixXd jacobian_at_best;  ///< in the parameters' own coordinates
    std::size_t residuals = 0;
};

// Levenberg–Marquardt as `tvid fit` runs it: the optimizer table's lm row (in the
// parameters' scales, within their bounds), from the problem's init.
LeastSquaresFit fit_least_squares(const IdentificationProblem& problem, int threads, const std::atomic<bool>* stop) {
    LeastSquaresFit f;
    const ProblemDefinition& d = problem.definition();
    f.residuals = estimation_residual_count(d.estimation, d.measured.size());
    if (problem.dimension() == 0) {
        // The profiled parameter was the only free one: nothing is left to fit, and the
        // point's cost is the simulation's at the held value.
        ResidualEvaluator least_squares(problem, EvaluatorOptions(threads).with_stop(stop));
        std::vector<double> r(f.residuals);
        const double none = 0.0;  // no parameter: a valid pointer to nothing used
        const bool ok = least_squares.residuals(&none, r.data());
        const double half = 0.5 * Eigen::Map<const Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size())).squaredNorm();
        f.best_cost = ok && std::isfinite(half) ? 2.0 * half : std::numeric_limits<double>::infinity();
        f.converged = std::isfinite(f.best_cost);
        f.termination = f.converged ? "nothing else to fit"
                                    : (least_squares.stopped() ? "stopped" : "simulation failed: " + least_squares.failure(&none));
        return f;
    }
    FitOptions options;
    options.threads = threads;
    options.stop = stop;
    options.progress = [stop](const HistoryRow&) { return !(stop && stop->load()); };
    FitResult scratch;
    OptimizerRun run = optimizer_entry(OptimizerKind::lm).run(problem, options, scratch);
    f.best = std::move(run.best);
    f.best_cost = run.best_cost;
    f.termination = std::move(run.termination);
    f.converged = run.termination_type == TerminationType::converged;
    f.jacobian_at_best = std::move(run.jacobian_at_best);
    return f;
}

// Where Δχ² crosses the threshold between grid points a and b: linear interpolation of
// √Δχ², which is linear in the value when the model is linear in its parameters (the exact
// crossing then) and close to linear near any smooth optimum.
double crossing(const ProfilePoint& a, const ProfilePoint& b, double threshold) {
    const double ra = std::sqrt(std::max(a.delta_chi2, 0.0)), rb = std::sqrt(std::max(b.delta_chi2, 0.0));
    // A failed point: the interval reaches to it, and no further.
    if (!std::isfinite(ra)) return a.value;
    if (!std::isfinite(rb)) return b.value;
    const double t = (std::sqrt(threshold) - ra) / (rb - ra);
    return a.value + t * (b.value - a.value);
}

}  // namespace

void check_profile_request(const Experiment& ex, const ProfileOptions& options) {
    if (ex.estimation_settings.cost != CostKind::l2)
        throw InputError(ex.file.string(), 0, "estimation.cost",
                         "the profile likelihood compares sums of squares: set cost: l2");
    const auto named = std::find_if(ex.parameters.begin(), ex.parameters.end(),
                                    [&](const ParameterSetting& p) { return p.name == options.parameter; });
    if (named == ex.parameters.end())
        throw InputError("--param", 0, options.parameter, "is not a parameter of the model");
    if (named->fixed)
        throw InputError("--param", 0, options.parameter, "is fixed in the experiment: only a free parameter has a profile");
    if (options.points < 3) throw InputError("--points", 0, "points", "a profile needs at least 3 points");
}

ProfileResult profile_likelihood(const Experiment& ex, const std::vector<double>& start, const ProfileOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    check_profile_request(ex, options);
    const auto named = std::find_if(ex.parameters.begin(), ex.parameters.end(),
                                    [&](const ParameterSetting& p) { return p.name == options.parameter; });
    const auto held = static_cast<std::size_t>(named - ex.parameters.begin());

    ProfileResult r;
    r.parameter = options.parameter;
    r.unit = parameter_units(ex.network)[held];
    r.threads = resolve_thread_count(options.threads);

    // θ̂: Levenberg–Marquardt from the start, on every thread.
    Experiment at_start = ex;
    for (std::size_t i = 0; i < ex.parameters.size(); ++i)
        if (!ex.parameters[i].fixed) at_start.parameters[i].init = start[i];
    const IdentificationProblem problem(at_start);
    const LeastSquaresFit best = fit_least_squares(problem, r.threads, options.stop);
    if (!std::isfinite(best.best_cost))
        throw std::runtime_error("the fit to the optimum failed (" + best.termination + "): there is nothing to profile");
    r.optimum = best.best;
    r.best_cost = best.best_cost;
    r.optimum_termination = best.termination;
    r.residuals = best.residuals;
    const std::size_t m = problem.dimension();
    const std::size_t j_held = static_cast<std::size_t>(
        std::find(problem.free_indices().begin(), problem.free_indices().end(), held) - problem.free_indices().begin());
    r.best_value = r.optimum[j_held];
    for (std::size_t j = 0; j < m; ++j)
        if (j != j_held) r.others.push_back(problem.free_names()[j]);
    r.s2 = r.best_cost / (static_cast<double>(r.residuals) - static_cast<double>(m));
    // The standard error from the Jacobian LM ended on (the one evaluator's).
    const ParameterUncertainty u =
        estimate_uncertainty(problem, r.optimum, {&best.jacobian_at_best, best.best_cost}, EvaluatorOptions(r.threads));
    r.std_error = u.available ? u.std_error[j_held] : std::numeric_limits<double>::quiet_NaN();

    // The grid: θ̂ ∓ 4 standard errors (or ∓ 50 % without one), within the bounds.
    const double lo_bound = problem.lower()[j_held], hi_bound = problem.upper()[j_held];
    const double half = std::isfinite(r.std_error) && r.std_error > 0 ? kDefaultSpan * r.std_error
                                                                       : 0.5 * std::max(std::abs(r.best_value), 1e-12);
    const double from = options.from.value_or(std::max(lo_bound, r.best_value - half));
    const double to = options.to.value_or(std::min(hi_bound, r.best_value + half));
    if (!(from < to)) throw InputError("--from", 0, "from", "the profile's grid is empty: --from must be below --to");
    if (from < lo_bound || to > hi_bound)
        throw InputError(options.from && from < lo_bound ? "--from" : "--to", 0, options.parameter,
                         "the profile's grid reaches beyond the parameter's bounds");
    r.points.resize(static_cast<std::size_t>(options.points));
    for (std::size_t k = 0; k < r.points.size(); ++k)
        r.points[k].value = from + (to - from) * static_cast<double>(k) / static_cast<double>(r.points.size() - 1);

    // Each point: the others refitted from θ̂ with the parameter held, one thread each.
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t k = next++; k < r.points.size(); k = next++) {
            ProfilePoint& p = r.points[k];
            const Experiment held_here = restarted(ex, problem, r.optimum, held, p.value);
            const IdentificationProblem sub(held_here);
            const LeastSquaresFit f = fit_least_squares(sub, 1, options.stop);
            p.cost = f.best_cost;
            p.others = f.best;
            p.termination = f.termination;
            p.converged = f.converged;
            p.delta_chi2 = std::isfinite(p.cost) ? (p.cost - r.best_cost) / r.s2 : std::numeric_limits<double>::infinity();
        }
    };
    run_on_threads(std::min(r.threads, options.points), work);

    // The interval: every value whose Δχ² is below the threshold, θ̂ included (Δχ² = 0).
    // Its ends are the outermost crossings; a grid end still below the threshold leaves
    // that side open. A point above the threshold inside it means a second valley.
    for (const ProfilePoint& p : r.points)
        if (p.cost < r.best_cost * (1.0 - 1e-9)) r.better_point_found = true;
    std::vector<ProfilePoint> curve = r.points;
    ProfilePoint optimum;
    optimum.value = r.best_value;
    curve.push_back(optimum);
    std::stable_sort(curve.begin(), curve.end(), [](const ProfilePoint& a, const ProfilePoint& b) { return a.value < b.value; });
    const auto below = [](const ProfilePoint& p) { return p.delta_chi2 < kProfileThreshold95; };
    const std::size_t first = static_cast<std::size_t>(std::find_if(curve.begin(), curve.end(), below) - curve.begin());
    const std::size_t last = curve.size() - 1 -
        static_cast<std::size_t>(std::find_if(curve.rbegin(), curve.rend(), below) - curve.rbegin());
    if (first > 0) r.low = crossing(curve[first - 1], curve[first], kProfileThreshold95);
    if (last + 1 < curve.size()) r.high = crossing(curve[last], curve[last + 1], kProfileThreshold95);
    for (std::size_t k = first; k <= last; ++k)
        if (!below(curve[k])) r.disconnected = true;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace tvid
