#include "tvid/analysis/step_stability.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "tvid/model/state_jacobian.hpp"

namespace tvid {

StepStability assess_step_stability(const IdentificationProblem& problem, const std::vector<double>& params,
                                    const std::vector<SolvedStart>* starts) {
    StepStability s;
    const ProblemDefinition& def = problem.definition();
    if (!steps_by_rk4(def.simulation.method)) return s;
    const std::vector<double>& time = problem.inputs().time();
    auto ws = problem.make_workspace();
    StateJacobian jacobian;
    std::vector<double> u(problem.inputs().count()), a;
    if (starts && starts->size() != def.estimation.size()) starts = nullptr;
    for (std::size_t wi = 0; wi < def.estimation.size(); ++wi) {
        const Window& w = def.estimation[wi];
        problem.use_parameters(params, *ws);
        std::string why;
        const SolvedStart* solved = starts && (*starts)[wi].x_start.size() == ws->x.size() ? &(*starts)[wi] : nullptr;
        const WindowStart start =
            solved ? IdentificationProblem::restore_start(*solved, *ws) : problem.start_window(w, *ws, &why);
        if (start.status != SimulationStatus::ok) continue;
        if (start.implicit_steps) {  // beyond RK4's substeps: sdirk3's implicit steps, stable at any stiffness
            s.assessed = s.implicit = true;
            s.window = w.label;
            return s;
        }
        const std::size_t at = problem.warms_up(w) ? w.first : w.start;
        if (at + 1 >= time.size()) continue;
        const double interval = time[at + 1] - time[at];
        // The step the window is simulated at: the experiment's, over a stiff candidate's substeps.
        const double h = (def.simulation.max_step > 0 ? std::min(def.simulation.max_step, interval) : interval) /
                         static_cast<double>(std::max<std::size_t>(ws->substeps, 1));
        std::size_t hint = at;
        ws->inputs->at(time[at], hint, u.data());
        jacobian.bind(ws->model);
        const auto n = static_cast<Eigen::Index>(jacobian.state_size());
        a.assign(static_cast<std::size_t>(n * n), 0.0);
        jacobian.evaluate(ws->x.data(), u.data(), a.data());
        const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> A(a.data(), n, n);
        if (!A.allFinite()) continue;
        const Eigen::EigenSolver<Eigen::MatrixXd> eigen(A, false);
        if (eigen.info() != Eigen::Success) continue;
        s.assessed = true;
        for (Eigen::Index k = 0; k < n; ++k) {
            const std::complex<double> lambda = eigen.eigenvalues()[k];
            const double rate = std::abs(lambda);
            if (!(rate > 0.0)) continue;  // the free rotation of a line: no dynamics
            const double margin = rate * h / rk4_stability_radius(std::arg(lambda));
            if (margin <= s.margin) continue;
            s.margin = margin;
            s.window = w.label;
            s.step = h;
            s.substeps = ws->substeps;
            s.rate = rate;
            s.frequency_hz = std::abs(lambda.imag()) / (2 * std::numbers::pi);
            s.damping_ratio = -lambda.real() / rate;
        }
    }
    return s;
}

}  // namespace tvid
