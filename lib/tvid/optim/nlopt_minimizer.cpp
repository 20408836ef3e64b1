#include "tvid/optim/nlopt_minimizer.hpp"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>

#include "tvid/optim/nlopt_algorithms.hpp"

namespace tvid {

namespace {

constexpr double kNoBound = 1e300;  // the experiment's "no bound"

double nlopt_bound(double b) {
    if (b <= -kNoBound) return -HUGE_VAL;
    if (b >= kNoBound) return HUGE_VAL;
    return b;
}

NloptAlgorithm require_algorithm(const std::string& name, const char* role) {
    const auto a = find_nlopt_algorithm(name);
    if (!a) throw std::invalid_argument(std::string("NLopt: unknown ") + role + " '" + name + "'");
    return *a;
}

// What one run shares with the objective callback.
struct RunState {
    DifferentiableCost* cost = nullptr;
    const NloptProgress* progress = nullptr;
    nlopt::opt* opt = nullptr;
    NloptSummary* summary = nullptr;
    bool stopped = false;
    long long max_evaluations = 0;  ///< 0: none; else enforced here (some algorithms, e.g. GN_ORIG_DIRECT, overrun it)
    bool budget_spent = false;
    HistoryRow last;

    long long counted() const {
        const long long sims = cost->simulations();
        return sims >= 0 ? sims : summary->evaluations;
    }
};

double objective(unsigned n, const double* x, double* gradient, void* data) {
    RunState& run = *static_cast<RunState*>(data);
    NloptSummary& s = *run.summary;
    double f = gradient ? run.cost->value_and_gradient(x, gradient) : run.cost->value(x);
    const long long k = s.evaluations++;
    if (gradient) ++s.gradient_evaluations;
    if (!std::isfinite(f)) {
        ++s.failed_evaluations;
        f = HUGE_VAL;  // NLopt treats it as a very bad point and moves away
        if (gradient) std::fill(gradient, gradient + n, 0.0);
    }
    if (k == 0) s.initial_cost = f;
    run.last = HistoryRow{static_cast<int>(std::min<long long>(k, std::numeric_limits<int>::max())), run.counted(),
                          std::min(f, s.best_cost)};
    if (f < s.best_cost || k == 0) {
        if (f < s.best_cost) {
            s.best_cost = f;
            s.best.assign(x, x + n);
        }
        s.history.push_back(run.last);
    }
    if (*run.progress && !(*run.progress)(run.last)) {
        run.stopped = true;
        run.opt->force_stop();
    } else if (run.max_evaluations > 0 && s.evaluations >= run.max_evaluations) {
        run.budget_spent = true;
        run.opt->force_stop();
    }
    return f;
}

std::string termination_text(nlopt::result r) {
    switch (r) {
        case nlopt::SUCCESS: return "success";
        case nlopt::STOPVAL_REACHED: return "stop value reached";
        case nlopt::FTOL_REACHED: return "cost change below ftol_rel";
        case nlopt::XTOL_REACHED: return "step below xtol_rel";
        case nlopt::MAXEVAL_REACHED: return "evaluation limit";
        case nlopt::MAXTIME_REACHED: return "time limit";
        case nlopt::FORCED_STOP: return "stopped";
        case nlopt::ROUNDOFF_LIMITED: return "roundoff limited";
        case nlopt::OUT_OF_MEMORY: return "out of memory";
        case nlopt::INVALID_ARGS: return "invalid arguments";
        default: break;  // FAILURE
    }
    return "failure";
}

TerminationType termination_type(nlopt::result r) {
    switch (r) {
        case nlopt::SUCCESS:
        case nlopt::STOPVAL_REACHED:
        case nlopt::FTOL_REACHED:
        case nlopt::XTOL_REACHED: return TerminationType::converged;
        case nlopt::MAXEVAL_REACHED: return TerminationType::evaluation_limit;
        case nlopt::MAXTIME_REACHED: return TerminationType::time_limit;
        case nlopt::FORCED_STOP: return TerminationType::stopped;
        case nlopt::ROUNDOFF_LIMITED: return TerminationType::no_progress;
        default: break;  // FAILURE, OUT_OF_MEMORY, INVALID_ARGS
    }
    return TerminationType::failed;
}

void set_tolerances(nlopt::opt& opt, const NloptSettings& settings) {
    if (settings.xtol_rel > 0) opt.set_xtol_rel(settings.xtol_rel);
    if (settings.ftol_rel > 0) opt.set_ftol_rel(settings.ftol_rel);
}

}  // namespace

NloptSummary run_nlopt(const NloptSettings& settings, std::vector<double> x0, const std::vector<double>& lower,
                       const std::vector<double>& upper, DifferentiableCost& cost, const NloptProgress& progress) {
    const std::size_t m = x0.size();
    if (m == 0 || lower.size() != m || upper.size() != m) throw std::invalid_argument("NLopt: inconsistent sizes");
    const NloptAlgorithm algorithm = require_algorithm(settings.algorithm, "algorithm");
    std::vector<double> lo(m), hi(m);
    for (std::size_t j = 0; j < m; ++j) {
        if (!(lower[j] <= upper[j])) throw std::invalid_argument("NLopt: a lower bound above its upper bound");
        lo[j] = nlopt_bound(lower[j]);
        hi[j] = nlopt_bound(upper[j]);
        if (algorithm.global && !(std::isfinite(lo[j]) && std::isfinite(hi[j])))
            throw std::invalid_argument("NLopt: the global algorithm " + algorithm.name + " needs finite bounds");
        if (!std::isfinite(x0[j])) throw std::invalid_argument("NLopt: a non-finite start");
        x0[j] = std::clamp(x0[j], lo[j], hi[j]);
    }
    if (algorithm.needs_local && settings.local_algorithm.empty())
        throw std::invalid_argument("NLopt: " + algorithm.name + " needs a local algorithm");

    nlopt::opt opt(static_cast<nlopt::algorithm>(algorithm.code), static_cast<unsigned>(m));
    opt.set_lower_bounds(lo);
    opt.set_upper_bounds(hi);
    set_tolerances(opt, settings);
    if (settings.max_evaluations > 0)
        opt.set_maxeval(static_cast<int>(std::min<long long>(settings.max_evaluations, std::numeric_limits<int>::max())));
    if (settings.max_seconds > 0) opt.set_maxtime(settings.max_seconds);
    if (settings.population > 0) opt.set_population(static_cast<unsigned>(settings.population));

    NloptSummary s;
    s.algorithm = algorithm.name;
    s.best = x0;
    s.best_cost = std::numeric_limits<double>::infinity();
    if (!settings.local_algorithm.empty()) {
        if (!algorithm.takes_local)
            throw std::invalid_argument("NLopt: " + algorithm.name + " runs no local algorithm");
        const NloptAlgorithm local = require_algorithm(settings.local_algorithm, "local algorithm");
        if (local.global) throw std::invalid_argument("NLopt: the local algorithm " + local.name + " is global");
        nlopt::opt inner(static_cast<nlopt::algorithm>(local.code), static_cast<unsigned>(m));
        set_tolerances(inner, settings);
        opt.set_local_optimizer(inner);
        s.local_algorithm = local.name;
    }

    RunState run;
    run.cost = &cost;
    run.progress = &progress;
    run.opt = &opt;
    run.summary = &s;
    run.max_evaluations = settings.max_evaluations;
    opt.set_min_objective(objective, &run);
    nlopt::srand(static_cast<unsigned long>(settings.seed));  // randomized algorithms: one seed, one result

    std::vector<double> x = x0;
    double f = HUGE_VAL;
    nlopt::result result = nlopt::FAILURE;
    try {
        result = opt.optimize(x, f);
    } catch (const nlopt::forced_stop&) {
        result = nlopt::FORCED_STOP;
    } catch (const nlopt::roundoff_limited&) {
        result = nlopt::ROUNDOFF_LIMITED;
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::invalid_argument&) {
        result = opt.last_optimize_result();  // e.g. a start NLopt rejects: reported, not thrown
        if (result >= 0) result = nlopt::INVALID_ARGS;
    } catch (const std::runtime_error&) {
        result = nlopt::FAILURE;
    }
    if (run.budget_spent && !run.stopped && result == nlopt::FORCED_STOP) result = nlopt::MAXEVAL_REACHED;
    s.termination_type = run.stopped ? TerminationType::stopped : termination_type(result);
    s.termination = run.stopped ? "stopped" : termination_text(result);
    if (s.evaluations > 0 && s.history.back().iteration != run.last.iteration) s.history.push_back(run.last);
    s.iterations = static_cast<int>(s.evaluations);  // NLopt's iterations are its evaluations
    if (!std::isfinite(s.best_cost)) {
        if (s.evaluations > 0) {
            s.termination_type = TerminationType::all_failed;
            s.termination = "all evaluations failed";
        }
        s.success = false;
        return s;
    }
    // A global algorithm has no tolerance of its own: its budget is its stopping rule.
    const bool budget = s.termination_type == TerminationType::evaluation_limit ||
                        s.termination_type == TerminationType::time_limit;
    s.success = s.termination_type == TerminationType::converged || (algorithm.global && budget);
    return s;
}

}  // namespace tvid
