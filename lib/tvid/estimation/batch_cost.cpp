#include "tvid/estimation/batch_cost.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "tvid/sim/batch_rk4.hpp"
#include "tvid/sim/fixed_state_rk4.hpp"

namespace tvid {

namespace {

constexpr int W = kBatchLanes;
using P = BatchScalar;
using Lanes = Mask<W>;

bool all_finite(const double* v, std::size_t n) {
    for (std::size_t j = 0; j < n; ++j)
        if (!std::isfinite(v[j])) return false;
    return true;
}

// The lanes' scores over the estimation windows, as IdentificationProblem::cost keeps
// them for one candidate: the total of the finished windows, and each lane's result once
// it is known (a cut at the bound, a failure, or the full cost).
struct LaneScores {
    P total = P(0.0);
    std::array<double, W> result{};
    Lanes live{false};  ///< lanes still being scored

    void finish(int lane, double cost) {
        result[static_cast<std::size_t>(lane)] = cost;
        live.set(lane, false);
    }
};

template <std::size_t N>
void batch_costs_fixed(const IdentificationProblem& problem, const double* candidates, std::size_t count,
                       const double* bounds, BatchWorkspace& ws, double* costs) {
    const Experiment& ex = problem.experiment();
    const std::size_t m = problem.dimension();
    const double inf = std::numeric_limits<double>::infinity();
    const bool l1 = ex.estimation_settings.cost == CostKind::l1;
    const std::size_t n_out = ex.outputs.size();

    // Lanes: a candidate with a non-finite value costs +inf unsimulated, as in cost(); it
    // and the unused lanes simulate a finite candidate's parameters so that they compute
    // nothing unusual.
    LaneScores scores;
    std::size_t stand_in = count;
    for (std::size_t l = 0; l < count; ++l) {
        if (all_finite(candidates + l * m, m)) {
            scores.live.set(static_cast<int>(l), true);
            if (stand_in == count) stand_in = l;
        } else {
            scores.result[l] = inf;
        }
    }
    auto lane_source = [&](std::size_t l) {
        return l < count && scores.live[static_cast<int>(l)] ? candidates + l * m : candidates + stand_in * m;
    };
    if (stand_in < count) {
        problem.full_parameters(lane_source(0), ws.scalar->params);
        for (std::size_t i = 0; i < ws.params.size(); ++i) ws.params[i] = P(ws.scalar->params[i]);
        const std::vector<std::size_t>& free = problem.free_indices();
        for (std::size_t l = 0; l < static_cast<std::size_t>(W); ++l)
            for (std::size_t j = 0; j < m; ++j) ws.params[free[j]].set(static_cast<int>(l), lane_source(l)[j]);
        ws.model.set_parameters(ws.params.data());
    }

    P bound(inf);
    Lanes bounded(false);
    for (std::size_t l = 0; l < count; ++l)
        if (bounds && bounds[l] < inf) {
            bound.set(static_cast<int>(l), bounds[l]);
            bounded.set(static_cast<int>(l), true);
        }

    std::array<P, N> x;
    for (const Window& w : ex.estimation) {
        if (!scores.live.any()) break;
        // Each lane's start, from the scalar model with that lane's parameters.
        for (std::size_t j = 0; j < N; ++j) x[j] = P(0.0);
        for (int l = 0; l < W; ++l) {
            if (!scores.live[l]) continue;
            ProblemWorkspace& s = *ws.scalar;
            problem.full_parameters(lane_source(static_cast<std::size_t>(l)), s.params);
            s.model.set_parameters(s.params.data());
            if (problem.start_window(w, s, nullptr).status != SimulationStatus::ok) {
                scores.finish(l, inf);
                continue;
            }
            for (std::size_t j = 0; j < N; ++j) x[j].set(l, s.x[j]);
        }
        // Lanes without a start of their own copy a live one's.
        int model_lane = -1;
        for (int l = 0; l < W && model_lane < 0; ++l)
            if (scores.live[l]) model_lane = l;
        if (model_lane < 0) break;
        for (int l = 0; l < W; ++l)
            if (!scores.live[l])
                for (std::size_t j = 0; j < N; ++j) x[j].set(l, x[j][model_lane]);

        const auto n_scored = static_cast<double>(problem.scored_samples(w));
        P window_sum(0.0);
        std::size_t scored = 0;
        // Adds sample i's terms and stops the lanes whose partial cost reaches their bound.
        // `after_derivative`: the model's last derivative() was at this sample (the march's).
        auto score = [&](std::size_t i, const std::array<P, N>& xs, const double* u, bool after_derivative) {
            for (std::size_t k = 0; k < n_out; ++k) {
                const auto output = static_cast<std::size_t>(ex.output_indices[k]);
                const P y = after_derivative ? ws.model.output_after_derivative(output, xs.data())
                                             : ws.model.output(output, xs.data(), u);
                const P e = y - P(problem.measured(k)[i]);
                window_sum = window_sum + (l1 ? abs(e) : e * e);
            }
            ++scored;
            const Lanes watched = bounded & scores.live;
            if (!watched.any()) return;
            const P partial = scores.total + (l1 ? window_sum / P(n_scored) : window_sum);
            const Lanes cut = watched & (partial >= bound);
            for (int l = 0; l < W; ++l)
                if (cut[l]) scores.finish(l, partial[l]);
        };

        std::size_t from = w.start;
        if (problem.warms_up(w)) {
            from = w.first;
            std::size_t hint = w.first;
            ws.u.resize(problem.inputs().count());
            problem.inputs().at(problem.inputs().time()[w.first], hint, ws.u.data());
            score(w.first, x, ws.u.data(), false);
        }
        const auto observe = [&](std::size_t i, const std::array<P, N>& xs, const std::vector<double>& u,
                                 const Lanes& sane) {
            for (int l = 0; l < W; ++l)
                if (scores.live[l] && !sane[l]) scores.finish(l, inf);  // diverged or not finite
            if (i >= w.first && scores.live.any()) score(i, xs, u.data(), true);
            return scores.live;
        };
        Lanes active = scores.live;
        march_batch_rk4<N, W>(ws.model, problem.inputs(), from, w.last, x, ex.simulation.max_step, ws.u, ws.u_stage,
                              active, ws.rhs_evaluations, observe);
        // The lanes that ran to the end add the window's share (l1: its mean).
        const P share = l1 ? window_sum / P(static_cast<double>(scored)) : window_sum;
        scores.total = select(scores.live, scores.total + share, scores.total);
    }
    for (int l = 0; l < W; ++l)
        if (scores.live[l]) {
            const double total = scores.total[l];
            scores.result[static_cast<std::size_t>(l)] = std::isfinite(total) ? total : inf;
        }
    for (std::size_t l = 0; l < count; ++l) costs[l] = scores.result[l];
}

}  // namespace

BatchWorkspace::BatchWorkspace(const IdentificationProblem& problem)
    : scalar(problem.make_workspace()), model(problem.experiment().network) {
    model.set_crank_angle_inputs(&problem.crank_angle_inputs());
    params.resize(problem.experiment().network.parameter_names.size());
    u.resize(problem.inputs().count());
}

bool batch_supported(const IdentificationProblem& problem) {
    const Experiment& ex = problem.experiment();
    const std::size_t n = ex.network.state_size();
    return ex.simulation.method == IntegrationMethod::rk4 && n >= 2 && n <= kMaxFixedState && n % 2 == 0;
}

void batch_costs(const IdentificationProblem& problem, const double* candidates, std::size_t count,
                 const double* bounds, BatchWorkspace& ws, double* costs) {
    if (count == 0) return;
    const auto run = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
        batch_costs_fixed<N>(problem, candidates, count, bounds, ws, costs);
    };
    switch (problem.experiment().network.state_size()) {
        case 2: return run(std::integral_constant<std::size_t, 2>{});
        case 4: return run(std::integral_constant<std::size_t, 4>{});
        case 6: return run(std::integral_constant<std::size_t, 6>{});
        case 8: return run(std::integral_constant<std::size_t, 8>{});
        case 10: return run(std::integral_constant<std::size_t, 10>{});
        case 12: return run(std::integral_constant<std::size_t, 12>{});
        case 14: return run(std::integral_constant<std::size_t, 14>{});
        case 16: return run(std::integral_constant<std::size_t, 16>{});
        default: break;
    }
    // Not batchable: one candidate at a time.
    for (std::size_t l = 0; l < count; ++l)
        costs[l] = problem.cost(candidates + l * problem.dimension(), *ws.scalar,
                                bounds ? bounds[l] : std::numeric_limits<double>::infinity());
}

}  // namespace tvid
