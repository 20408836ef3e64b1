// The cases of docs/performance.md, one per process (so the peak memory is the case's own):
//
//   tvid_bench cvt-pso [--threads N] [--iterations K] [--unbounded] [--scalar]
//                                                       paper swarm (512 x 250) with the library
//                                                       (--unbounded: without the early stop;
//                                                       --scalar: one candidate at a time, no SIMD groups)
//   tvid_bench cvt-pso-nonsmooth [--threads N] [--iterations K]
//                                                       a swarm of the same size on the same window
//                                                       with the non-smooth clearance law (eq. 7),
//                                                       every candidate to the end: the cost of a
//                                                       right-hand side without the smoothed law
//   tvid_bench cvt-baseline [--iterations K]            the same swarm, straightforward code, 1 thread
//   tvid_bench cvt-check                                baseline cost = library cost at a few points
//   tvid_bench cvt-window --repeat R [--threads N]      one simulation of the window tiled R times
//   tvid_bench engine-lm [--threads N]                  10-parameter LM fit from x0.5 / x2 of the truth
//
// Each prints one `case=… wall_s=… sims_per_s=… ns_per_rhs=… threads=… peak_mb=…` line
// (bench_row.hpp); scripts/bench.sh repeats them and prints the medians. Figures only:
// nothing here passes or fails on time.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "baseline_cvt.hpp"
#include "bench_row.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/optim/pso.hpp"
#include "tvid/parallel/process_group.hpp"

using namespace tvid;
using namespace tvid::bench;

namespace {

const std::string kSource = TVID_SOURCE_DIR;

struct Args {
    std::string name;
    int threads = 0;
    int iterations = -1;  ///< -1: the experiment's
    int repeat = 1;
    bool unbounded = false;  ///< --unbounded: no early stop at the personal best
    bool scalar = false;     ///< --scalar: one candidate at a time instead of SIMD groups
};

Args parse(int argc, char** argv) {
    Args a;
    if (argc > 1) a.name = argv[1];
    for (int i = 2; i < argc; i += 2) {
        const std::string key = argv[i];
        if (key == "--unbounded" || key == "--scalar") {
            (key == "--unbounded" ? a.unbounded : a.scalar) = true;
            --i;
            continue;
        }
        if (i + 1 >= argc) break;
        const int value = std::atoi(argv[i + 1]);
        if (key == "--threads") a.threads = value;
        else if (key == "--iterations") a.iterations = value;
        else if (key == "--repeat") a.repeat = value;
    }
    return a;
}

std::vector<Override> iteration_override(const Args& a) {
    if (a.iterations < 0) return {};
    return {{"estimation.pso.iterations", std::to_string(a.iterations)}};
}

SearchBox search_box(const IdentificationProblem& problem) {
    return SearchBox{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
}

std::string cost_note(double cost) {
    char text[64];
    std::snprintf(text, sizeof text, "E=%.10g", cost);
    return text;
}

std::string seconds_text(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", s);
    return text;
}

// Hides evaluate_bounded: every candidate simulated to the end (the swarm without the bound).
class UnboundedEvaluator : public CandidateEvaluator {
public:
    explicit UnboundedEvaluator(CandidateEvaluator& inner) : inner_(&inner) {}
    void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) override {
        inner_->evaluate(candidates, count, dimension, costs);
    }

private:
    CandidateEvaluator* inner_;
};

// (a) The paper's swarm as `tvid fit` runs it: run_fit, the entry the command calls, with
// a process group of one; the wall time is the optimizer's (the report's scoring and the
// uncertainty after it are timed by scripts/bench.sh on the binary).
int cvt_pso_fit(const Args& a) {
    const Experiment ex = load_experiment(kSource + "/configs/cvt_tipin.yaml", iteration_override(a));
    const IdentificationProblem problem(ex);
    ProcessGroup alone;
    FitOptions options;
    options.threads = a.threads;
    options.processes = &alone;
    const FitResult fit = run_fit(problem, options);
    print_row({a.threads == 1 ? "cvt-pso-1thread" : "cvt-pso", fit.optimizer_seconds,
               static_cast<double>(fit.run.evaluations), static_cast<double>(fit.run.right_hand_sides), fit.threads,
               cost_note(fit.run.best_cost) + ",after_optimizer_s=" + seconds_text(fit.wall_seconds - fit.optimizer_seconds)});
    return 0;
}

// Variants of (a) through the evaluator itself, to compare: --unbounded (no stop at the
// personal best), --scalar (one candidate at a time), and with `nonsmooth` the same-sized
// swarm on the model with the non-smooth law (bench/cvt_tipin_nonsmooth.yaml).
int cvt_pso(const Args& a, bool nonsmooth) {
    if (!nonsmooth && !a.unbounded && !a.scalar) return cvt_pso_fit(a);
    const std::string config = nonsmooth ? "/bench/cvt_tipin_nonsmooth.yaml" : "/configs/cvt_tipin.yaml";
    const Experiment ex = load_experiment(kSource + config, iteration_override(a));
    const IdentificationProblem problem(ex);
    ParallelEvaluator evaluator(problem, EvaluatorOptions(a.threads));
    evaluator.set_batching(!a.scalar);
    UnboundedEvaluator unbounded(evaluator);
    // (The non-smooth swarm scores every candidate to the end: the same work whatever its path.)
    CandidateEvaluator& used = a.unbounded || nonsmooth ? static_cast<CandidateEvaluator&>(unbounded) : evaluator;
    const auto t0 = Clock::now();
    const PsoSummary s = run_pso(ex.estimation_settings.pso, search_box(problem), used);
    const double wall = seconds_since(t0);
    const std::string name = std::string(nonsmooth ? "cvt-pso-nonsmooth" : a.threads == 1 ? "cvt-pso-1thread" : "cvt-pso") +
                             (a.scalar ? "-scalar" : "");
    // In SIMD groups: the share of the lanes' right-hand sides that a candidate needed.
    std::string note = cost_note(s.best_cost);
    if (evaluator.batching()) {
        char use[32];
        std::snprintf(use, sizeof use, ",lanes_used=%.3f", evaluator.lanes_used());
        note += use;
    }
    print_row({name, wall, static_cast<double>(s.evaluations),
               static_cast<double>(evaluator.right_hand_sides()), evaluator.threads(), note});
    return 0;
}

BaselineCvt make_baseline(const Experiment& ex, const IdentificationProblem& problem) {
    const Window& w = ex.estimation.at(0);
    return BaselineCvt(problem.inputs().time(), ex.data.column("Ttm"), ex.data.column("Tds"), w.start, w.last);
}

// Scores candidates one after the other with the straightforward code.
class BaselineEvaluator : public CandidateEvaluator {
public:
    explicit BaselineEvaluator(BaselineCvt& cvt) : cvt_(&cvt) {}
    void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) override {
        for (std::size_t i = 0; i < count; ++i) costs[i] = cvt_->cost(candidates + i * dimension);
    }

private:
    BaselineCvt* cvt_;
};

int cvt_baseline(const Args& a) {
    const Experiment ex = load_experiment(kSource + "/configs/cvt_tipin.yaml", iteration_override(a));
    const IdentificationProblem problem(ex);
    BaselineCvt cvt = make_baseline(ex, problem);
    BaselineEvaluator evaluator(cvt);
    const auto t0 = Clock::now();
    const PsoSummary s = run_pso(ex.estimation_settings.pso, search_box(problem), evaluator);
    const double wall = seconds_since(t0);
    print_row({"cvt-baseline", wall, static_cast<double>(s.evaluations), static_cast<double>(cvt.rhs_evaluations), 1,
               cost_note(s.best_cost)});
    return 0;
}

// The baseline is the same computation: its cost agrees with the library's to rounding.
int cvt_check(const Args&) {
    const Experiment ex = load_experiment(kSource + "/configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    BaselineCvt cvt = make_baseline(ex, problem);
    auto ws = problem.make_workspace();
    const auto truth = nlohmann::json::parse(std::ifstream(kSource + "/data/cvt/truth.json"));
    std::vector<std::vector<double>> points(3, std::vector<double>(problem.dimension()));
    for (std::size_t j = 0; j < problem.dimension(); ++j) {
        points[0][j] = truth["parameters"][problem.free_names()[j]].get<double>();
        points[1][j] = problem.range_lower()[j];
        points[2][j] = 0.5 * (problem.range_lower()[j] + problem.range_upper()[j]);
    }
    double worst = 0;
    for (const auto& p : points) {
        const double lib = problem.cost(p.data(), *ws), base = cvt.cost(p.data());
        const double rel = std::abs(lib - base) / std::abs(lib);
        worst = std::max(worst, rel);
        std::printf("library %.17g  baseline %.17g  relative difference %.2e\n", lib, base, rel);
    }
    std::printf("largest relative difference %.2e\n", worst);
    return worst < 1e-9 ? 0 : 1;
}

// (d) One simulation of the estimation window tiled `repeat` times: the recording's window
// samples repeated end to end, written as a CSV next to a copy of the experiment.
int cvt_window(const Args& a) {
    const Experiment base = load_experiment(kSource + "/configs/cvt_tipin.yaml");
    const Window& w = base.estimation.at(0);
    const std::vector<double>& t = base.data.column("t");
    const std::vector<double>& ttm = base.data.column("Ttm");
    const std::vector<double>& tds = base.data.column("Tds");
    const std::size_t n = w.last - w.start + 1, total = (n - 1) * static_cast<std::size_t>(a.repeat) + 1;
    const std::string dir = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp");
    const std::string csv = dir + "/tvid_bench_window_" + std::to_string(a.repeat) + ".csv";
    {
        std::ofstream out(csv);
        out.precision(17);
        out << "t,Ttm,Tds\n";
        const double dt = t[w.start + 1] - t[w.start];
        for (std::size_t k = 0; k < total; ++k) {
            const std::size_t i = w.start + (k == 0 ? 0 : 1 + (k - 1) % (n - 1));
            out << t[w.start] + dt * static_cast<double>(k) << ',' << ttm[i] << ',' << tds[i] << '\n';
        }
    }
    const Experiment ex = load_experiment(kSource + "/configs/cvt_tipin.yaml",
                                          {{"data.file", csv},
                                           {"windows.estimation", "[{samples: [0, " + std::to_string(total - 1) + "]}]"},
                                           {"windows.validation", "[]"}});
    const IdentificationProblem problem(ex);
    std::vector<double> centre(problem.dimension());
    for (std::size_t j = 0; j < centre.size(); ++j)
        centre[j] = 0.5 * (problem.range_lower()[j] + problem.range_upper()[j]);
    // Enough simulations for a measurable time: 2048 window-lengths of work in all.
    const std::size_t sims = std::max<std::size_t>(16, 2048 / static_cast<std::size_t>(a.repeat));
    std::vector<double> candidates, costs(sims);
    for (std::size_t i = 0; i < sims; ++i) candidates.insert(candidates.end(), centre.begin(), centre.end());
    ParallelEvaluator evaluator(problem, EvaluatorOptions(a.threads));
    const auto t0 = Clock::now();
    evaluator.evaluate(candidates.data(), sims, centre.size(), costs.data());
    const double wall = seconds_since(t0);
    print_row({"cvt-window-x" + std::to_string(a.repeat), wall, static_cast<double>(sims),
               static_cast<double>(evaluator.right_hand_sides()), evaluator.threads(), cost_note(costs[0])});
    return 0;
}

// (b) The 10-parameter engine fit on one cycle from the truth scaled alternately by 0.5 and 2.
int engine_lm(const Args& a) {
    const auto truth = nlohmann::json::parse(std::ifstream(kSource + "/data/engine/truth.json"));
    std::vector<Override> overrides;
    int k = 0;
    for (const char* name : {"J1", "J2", "J3", "m", "C1", "C2", "C3", "C21", "C32", "Cxx"}) {
        const double init = truth["parameters"][name].get<double>() * (k++ % 2 == 0 ? 0.5 : 2.0);
        std::ostringstream value;
        value.precision(17);
        value << init;
        overrides.push_back({std::string("parameters.") + name + ".init", value.str()});
    }
    const Experiment ex = load_experiment(kSource + "/configs/engine_idle_clean.yaml", overrides);
    const IdentificationProblem problem(ex);
    FitOptions o;
    o.threads = a.threads;
    const auto t0 = Clock::now();
    const FitResult fit = run_fit(problem, o);
    const double wall = seconds_since(t0);
    const LmSummary& lm = *fit.summary_of<LmSummary>();
    print_row({"engine-lm", wall, static_cast<double>(fit.run.evaluations), 0, fit.threads,
               cost_note(fit.run.best_cost) + ",iterations=" + std::to_string(fit.run.iterations) +
                   ",trials_ahead_taken=" + std::to_string(lm.taken_ahead) + "/" +
                   std::to_string(lm.evaluated_ahead) + ",after_optimizer_s=" + seconds_text(wall - fit.optimizer_seconds)});
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const Args a = parse(argc, argv);
    try {
        if (a.name == "cvt-pso") return cvt_pso(a, false);
        if (a.name == "cvt-pso-nonsmooth") return cvt_pso(a, true);
        if (a.name == "cvt-baseline") return cvt_baseline(a);
        if (a.name == "cvt-check") return cvt_check(a);
        if (a.name == "cvt-window") return cvt_window(a);
        if (a.name == "engine-lm") return engine_lm(a);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tvid_bench %s: %s\n", a.name.c_str(), e.what());
        return 2;
    }
    std::fprintf(stderr, "usage: tvid_bench cvt-pso|cvt-pso-nonsmooth|cvt-baseline|cvt-check|cvt-window|engine-lm [--threads N] "
                         "[--iterations K] [--repeat R]\n");
    return 2;
}
