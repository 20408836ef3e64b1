// Which integrator for which model? For the engine crankshaft (stiff: twist modes up to
// ~3e4 rad/s, samples ~67 us apart, 1441-sample cycles behind a two-cycle warm-up), the
// CVT clearance model (1 ms samples) and the vehicle driveline (a sticking dry friction,
// a real mode near -5.6e4 1/s, 1 ms samples), this program simulates the first estimation
// window and the first validation window with the true parameters (data/*/truth.json) under
// fixed-step rk4, fixed-step implicit sdirk3, adaptive dopri5 and adaptive rosenbrock4 at
// several settings, and prints
// per setting: the wall time of one window simulation (median of the repeats; for the
// engine this includes the warm-up shooting, several simulations of the warm-up), the
// right-hand-side and Jacobian evaluations per window, the RMS and largest output error
// against a dopri5 reference at rtol = atol = 1e-12, and the RMS residual against the
// recorded noise-free data (what the identification sees). A last column measures how
// smooth the output is in the parameters, which the finite-difference Jacobian of `lm`
// relies on (see jacobian_noise).
//
//   tvid_integrator_comparison [--repeats N] [--only engine|cvt|driveline] [--method rk4|sdirk3|dopri5|rosenbrock4]
//
// It prints figures; it never passes or fails.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"

using namespace tvid;
using clock_type = std::chrono::steady_clock;

namespace {

struct Case {
    std::string method, setting;
    SimulationSettings settings;
};

SimulationSettings rk4(double step) {
    SimulationSettings s;
    s.max_step = step;  // 0: one step per sample interval
    return s;
}

SimulationSettings sdirk3(double step) {
    SimulationSettings s;
    s.method = IntegrationMethod::sdirk3;
    s.max_step = step;
    return s;
}

SimulationSettings adaptive(IntegrationMethod method, double tolerance) {
    SimulationSettings s;
    s.method = method;
    s.rtol = s.atol = tolerance;
    return s;
}

std::string tolerance_text(double tolerance) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "rtol=atol=%.0e", tolerance);
    return buf;
}

std::string step_text(double step) {
    char buf[32];
    if (step == 0.0) std::snprintf(buf, sizeof buf, "step: sample");
    else std::snprintf(buf, sizeof buf, "step: %.3g s", step);
    return buf;
}

// rk4 and sdirk3 at the sample interval and with substeps, dopri5 and rosenbrock4 at 1e-4 … 1e-10.
std::vector<Case> cases(const std::vector<double>& rk4_steps, const std::vector<double>& sdirk3_steps) {
    std::vector<Case> out;
    for (double step : rk4_steps) out.push_back({"rk4", step_text(step), rk4(step)});
    for (double step : sdirk3_steps) out.push_back({"sdirk3", step_text(step), sdirk3(step)});
    for (IntegrationMethod m : {IntegrationMethod::dopri5, IntegrationMethod::rosenbrock4})
        for (double tol : {1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10})
            out.push_back({m == IntegrationMethod::dopri5 ? "dopri5" : "rosenbrock4", tolerance_text(tol),
                           adaptive(m, tol)});
    return out;
}

// The true parameters of the experiment's model, in its parameter order.
std::vector<double> true_parameters(const Experiment& ex, const std::string& truth_file) {
    std::ifstream in(truth_file);
    const auto truth = nlohmann::json::parse(in)["parameters"];
    std::vector<double> p;
    for (const ParameterSetting& s : ex.parameters) p.push_back(truth.at(s.name).get<double>());
    return p;
}

struct Run {
    std::vector<WindowTrace> traces;  // one per window
    double seconds = 0.0;             // per window, median over the repeats
    double rhs = 0.0, jacobians = 0.0;  // per window
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// Simulates every window `repeats` times with the experiment's current settings.
Run simulate(const IdentificationProblem& problem, const std::vector<const Window*>& windows,
             const std::vector<double>& params, int repeats) {
    Run run;
    auto ws = problem.make_workspace();
    for (const Window* w : windows) {
        std::vector<double> seconds;
        const std::size_t rhs0 = ws->buffers.rhs_evaluations, jac0 = ws->buffers.jacobian_evaluations;
        for (int r = 0; r < repeats; ++r) {
            const auto t0 = clock_type::now();
            WindowTrace tr = problem.trace(params, *w, *ws);
            seconds.push_back(std::chrono::duration<double>(clock_type::now() - t0).count());
            if (r == 0) run.traces.push_back(std::move(tr));
        }
        run.seconds += median(seconds) / static_cast<double>(windows.size());
        run.rhs += static_cast<double>(ws->buffers.rhs_evaluations - rhs0) / repeats / static_cast<double>(windows.size());
        run.jacobians +=
            static_cast<double>(ws->buffers.jacobian_evaluations - jac0) / repeats / static_cast<double>(windows.size());
    }
    return run;
}

struct Errors {
    double rms = 0.0, max = 0.0;
};

// Output errors of `run` against `reference` (or against the measured data when null).
Errors errors(const Run& run, const Run* reference) {
    double sum = 0.0, worst = 0.0;
    std::size_t count = 0;
    for (std::size_t w = 0; w < run.traces.size(); ++w) {
        const WindowTrace& tr = run.traces[w];
        for (std::size_t k = 0; k < tr.simulated.size(); ++k)
            for (std::size_t i = 0; i < tr.simulated[k].size(); ++i) {
                const double target = reference ? reference->traces[w].simulated[k][i] : tr.measured[k][i];
                const double e = tr.simulated[k][i] - target;
                sum += e * e;
                worst = std::max(worst, std::abs(e));
                ++count;
            }
    }
    return {std::sqrt(sum / static_cast<double>(std::max<std::size_t>(count, 1))), worst};
}

// The output's finite-difference derivative along parameter j over the first window,
// (y(p + h) − y(p − h)) / 2h with h = step·|p_j|, all outputs and samples in one vector.
std::vector<double> output_derivative(const IdentificationProblem& problem, const Window& w, std::vector<double> p,
                                      std::size_t j, double step, ProblemWorkspace& ws) {
    const double h = step * std::abs(p[j]), pj = p[j];
    p[j] = pj + h;
    const WindowTrace plus = problem.trace(p, w, ws);
    p[j] = pj - h;
    const WindowTrace minus = problem.trace(p, w, ws);
    std::vector<double> d;
    for (std::size_t k = 0; k < plus.simulated.size(); ++k)
        for (std::size_t i = 0; i < plus.simulated[k].size() && i < minus.simulated[k].size(); ++i)
            d.push_back((plus.simulated[k][i] - minus.simulated[k][i]) / (2 * h));
    return d;
}

// How far the Jacobian column that `lm` would use (h = 6e-6·|p_j|) strays from the one at
// ten times the step: ‖D(6e-6) − D(6e-5)‖ / ‖D(6e-5)‖. Smooth outputs give the truncation
// error of the wider difference (~1e-8) plus rounding; adaptive step control adds its
// tolerance-level noise divided by h.
double jacobian_noise(const IdentificationProblem& problem, const Window& w, const std::vector<double>& p,
                      std::size_t j) {
    auto ws = problem.make_workspace();
    const std::vector<double> fine = output_derivative(problem, w, p, j, 6e-6, *ws);
    const std::vector<double> coarse = output_derivative(problem, w, p, j, 6e-5, *ws);
    double diff = 0.0, norm = 0.0;
    for (std::size_t i = 0; i < fine.size() && i < coarse.size(); ++i) {
        diff += (fine[i] - coarse[i]) * (fine[i] - coarse[i]);
        norm += coarse[i] * coarse[i];
    }
    return std::sqrt(diff / norm);
}

bool all_ok(const Run& run, std::string* problem) {
    for (const WindowTrace& tr : run.traces)
        if (tr.status != SimulationStatus::ok) {
            *problem = tr.problem.empty() ? to_string(tr.status) : tr.problem;
            return false;
        }
    return true;
}

void compare(const std::string& config, const std::string& truth_file, const std::vector<double>& rk4_steps,
             const std::vector<double>& sdirk3_steps, const char* unit, const std::string& probe, int repeats,
             const std::string& method) {
    Experiment ex = load_experiment(config);
    std::optional<IdentificationProblem> problem;  // built for each integrator: it keeps the settings it was built with
    const std::vector<double> params = true_parameters(ex, truth_file);
    std::size_t probe_index = 0;
    while (probe_index + 1 < ex.parameters.size() && ex.parameters[probe_index].name != probe) ++probe_index;
    const std::vector<const Window*> windows = {&ex.estimation.front(), &ex.validation.front()};

    ex.simulation = adaptive(IntegrationMethod::dopri5, 1e-12);
    problem.emplace(ex);
    const Run reference = simulate(*problem, windows, params, 1);
    std::string problem_text;
    if (!all_ok(reference, &problem_text)) {
        std::printf("%s: the reference simulation failed: %s\n", ex.name.c_str(), problem_text.c_str());
        return;
    }
    const Errors reference_vs_data = errors(reference, nullptr);
    std::size_t samples = 0;
    for (const WindowTrace& tr : reference.traces) samples += tr.time.size();
    std::printf("\n%s: windows '%s' and '%s' (%zu scored samples), output %s [%s], %d repeats\n", ex.name.c_str(),
                windows[0]->label.c_str(), windows[1]->label.c_str(), samples, ex.outputs.front().model_name.c_str(),
                unit, repeats);
    std::printf("reference dopri5 rtol=atol=1e-12: %.1f ms per window, %.0f f per window, RMS vs data %.3g\n",
                reference.seconds * 1e3, reference.rhs, reference_vs_data.rms);
    std::printf("FD Jacobian noise: column %s on window '%s'\n", probe.c_str(), windows[0]->label.c_str());
    std::printf("| method | setting | ms / window | f evals / window | Jacobians / window | RMS error vs reference | "
                "max error vs reference | RMS residual vs data | FD Jacobian noise |\n");
    std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Case& c : cases(rk4_steps, sdirk3_steps)) {
        if (!method.empty() && c.method != method) continue;
        ex.simulation = c.settings;
        problem.emplace(ex);
        const Run run = simulate(*problem, windows, params, repeats);
        if (!all_ok(run, &problem_text)) {
            std::printf("| %s | %s | %.2f | %.0f | %.0f | failed: %s | | | |\n", c.method.c_str(), c.setting.c_str(),
                        run.seconds * 1e3, run.rhs, run.jacobians, problem_text.c_str());
            continue;
        }
        const Errors vs_reference = errors(run, &reference), vs_data = errors(run, nullptr);
        const double noise = jacobian_noise(*problem, *windows[0], params, probe_index);
        std::printf("| %s | %s | %.2f | %.0f | %.0f | %.2e | %.2e | %.4e | %.1e |\n", c.method.c_str(),
                    c.setting.c_str(), run.seconds * 1e3, run.rhs, run.jacobians, vs_reference.rms, vs_reference.max,
                    vs_data.rms, noise);
        std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
    int repeats = 5;
    std::string only, method;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
        else if (!std::strcmp(argv[i], "--method") && i + 1 < argc) method = argv[++i];
    }
    const std::string root = TVID_SOURCE_DIR;
    if (only.empty() || only == "engine")
        compare(root + "/configs/engine_idle_clean.yaml", root + "/data/engine/truth.json",
                {0.0, 2e-5, 1e-5, 5e-6, 2.5e-6}, {0.0, 2e-5}, "rad/s", "J1", repeats, method);
    if (only.empty() || only == "cvt")
        compare(root + "/configs/cvt_tipin_clean.yaml", root + "/data/cvt/truth.json", {0.0, 5e-4, 2.5e-4, 1e-4},
                {0.0, 2.5e-4}, "N m", "k_plus", repeats, method);
    if (only.empty() || only == "driveline")
        compare(root + "/configs/driveline_clean.yaml", root + "/data/driveline/truth.json",
                {1e-4, 5e-5, 2.5e-5}, {0.0, 5e-4, 2.5e-4, 1e-4}, "rad/s", "Fh", repeats, method);
    return 0;
}
