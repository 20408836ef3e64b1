#include "tvid/optim/pso.hpp"

#include "tvid/optim/parameter_scaling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>

namespace tvid {

namespace {

// A uniform draw in [0, 1) from the top 53 bits: unlike std::uniform_real_distribution
// its value is fixed by the standard's definition of mt19937_64 on every platform.
class UniformSource {
public:
    explicit UniformSource(std::uint64_t seed) : engine_(seed) {}
    double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
    double between(double a, double b) { return a + (b - a) * unit(); }
    std::size_t below(std::size_t n) { return static_cast<std::size_t>(unit() * static_cast<double>(n)); }

private:
    std::mt19937_64 engine_;
};

void grid_positions(int n, const SearchBox& box, std::vector<double>& pos, std::size_t& count) {
    const std::size_t m = box.range_lower.size();
    count = 1;
    for (std::size_t j = 0; j < m; ++j) count *= static_cast<std::size_t>(n);
    pos.resize(count * m);
    for (std::size_t i = 0; i < count; ++i) {
        std::size_t digits = i;  // particle i's grid coordinates, first parameter fastest
        for (std::size_t j = 0; j < m; ++j) {
            const auto g = static_cast<double>(digits % static_cast<std::size_t>(n));
            digits /= static_cast<std::size_t>(n);
            const double a = box.range_lower[j], b = box.range_upper[j];
            pos[i * m + j] = n == 1 ? 0.5 * (a + b) : a + (b - a) * g / (n - 1);
        }
    }
}

void latin_hypercube_positions(std::size_t count, const SearchBox& box, UniformSource& rng, std::vector<double>& pos) {
    const std::size_t m = box.range_lower.size();
    pos.resize(count * m);
    std::vector<std::size_t> strata(count);
    for (std::size_t j = 0; j < m; ++j) {
        for (std::size_t i = 0; i < count; ++i) strata[i] = i;
        for (std::size_t i = count; i > 1; --i) std::swap(strata[i - 1], strata[rng.below(i)]);  // Fisher–Yates
        const double a = box.range_lower[j], b = box.range_upper[j];
        for (std::size_t i = 0; i < count; ++i)
            pos[i * m + j] = a + (b - a) * (static_cast<double>(strata[i]) + rng.unit()) / static_cast<double>(count);
    }
}

}  // namespace

std::vector<double> pso_initial_positions(const PsoSettings& options, const SearchBox& box, std::size_t& count,
                                          std::uint64_t seed) {
    UniformSource rng(seed);
    std::vector<double> pos;
    const std::size_t m = box.range_lower.size();
    switch (options.start) {
        case PsoStart::grid: grid_positions(options.grid, box, pos, count); break;
        case PsoStart::latin_hypercube:
            count = static_cast<std::size_t>(options.particles);
            latin_hypercube_positions(count, box, rng, pos);
            break;
        case PsoStart::uniform:
            count = static_cast<std::size_t>(options.particles);
            pos.resize(count * m);
            for (std::size_t i = 0; i < count; ++i)
                for (std::size_t j = 0; j < m; ++j) pos[i * m + j] = rng.between(box.range_lower[j], box.range_upper[j]);
            break;
    }
    return pos;
}

namespace {

// The swarm's settledness at its last iteration (PsoConvergence).
PsoConvergence swarm_convergence(const std::vector<double>& personal, const std::vector<double>& personal_cost,
                                 std::size_t n, std::size_t m, const SearchBox& box,
                                 const std::vector<HistoryRow>& history) {
    PsoConvergence c;
    c.spread.assign(m, 0.0);
    for (std::size_t j = 0; j < m; ++j) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (std::size_t i = 0; i < n; ++i) {
            if (!std::isfinite(personal_cost[i])) continue;
            lo = std::min(lo, personal[i * m + j]);
            hi = std::max(hi, personal[i * m + j]);
        }
        const double width = box.upper[j] - box.lower[j];
        c.spread[j] = hi >= lo && width > 0 && std::isfinite(width) ? (hi - lo) / width : 0.0;
        c.max_spread = std::max(c.max_spread, c.spread[j]);
    }
    const int iterations = history.empty() ? 0 : history.back().iteration;
    c.window = std::min(iterations, std::max(10, iterations / 10));
    if (c.window > 0) {
        const double now = history.back().best_cost;
        const double before = history[history.size() - 1 - static_cast<std::size_t>(c.window)].best_cost;
        c.recent_improvement = std::isfinite(now) && std::isfinite(before) && now != 0.0
                                   ? (before - now) / std::abs(now)
                                   : (std::isfinite(now) && !std::isfinite(before) ? 1.0 : 0.0);
    }
    return c;
}

/// The swarm's state: n particles in m dimensions, their velocities and personal bests, and
/// the global best.
struct Swarm {
    std::size_t n, m;
    std::vector<double> p;                    // positions
    std::vector<double> v;                    // velocities, zero at the start
    std::vector<double> personal;             // P_i
    std::vector<double> personal_cost;
    std::vector<double> cost;
    std::vector<double> batch, batch_cost, batch_bound;
    std::vector<std::size_t> batch_index;
    std::vector<char> moved;
    std::vector<double> global;               // G
    double global_cost = std::numeric_limits<double>::infinity();

    Swarm(std::vector<double> start, std::size_t particles, std::size_t dimensions)
        : n(particles), m(dimensions), p(std::move(start)), v(n * m, 0.0), personal(p),
          personal_cost(n, std::numeric_limits<double>::infinity()), cost(n, std::numeric_limits<double>::infinity()),
          batch(n * m), batch_cost(n), batch_bound(n), batch_index(n), moved(n, 1), global(m, 0.0) {}

    /// Scores the particles that moved (an unmoved particle keeps its cost: the model is
    /// deterministic). Only "better than its personal best?" is asked of a particle: its
    /// best is the bound. False when a stop request cut the batch short: it is discarded
    /// whole, and the best stays the best of the last complete iteration.
    bool score_moved(CandidateEvaluator& evaluator, PsoSummary& s) {
        const double inf = std::numeric_limits<double>::infinity();
        std::size_t count = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (!moved[i]) continue;
            std::copy_n(&p[i * m], m, &batch[count * m]);
            batch_bound[count] = personal_cost[i];
            batch_index[count++] = i;
        }
        if (count > 0) evaluator.evaluate_bounded(batch.data(), count, m, batch_bound.data(), batch_cost.data());
        if (count > 0 && evaluator.stopped()) return false;
        s.evaluations += static_cast<long long>(count);
        for (std::size_t c = 0; c < count; ++c) {
            const double e = std::isfinite(batch_cost[c]) ? batch_cost[c] : inf;
            if (!std::isfinite(e) && s.failed_evaluations++ == 0)
                s.first_failed.assign(&batch[c * m], &batch[c * m] + m);
            cost[batch_index[c]] = e;
        }
        return true;
    }

    /// Personal and global bests, in particle order (ties keep the earlier one).
    void update_bests() {
        for (std::size_t i = 0; i < n; ++i) {
            if (cost[i] < personal_cost[i]) {
                personal_cost[i] = cost[i];
                std::copy_n(&p[i * m], m, &personal[i * m]);
            }
            if (personal_cost[i] < global_cost) {
                global_cost = personal_cost[i];
                std::copy_n(&personal[i * m], m, global.begin());
            }
        }
    }

    /// Eq. 24: the velocities and positions of the next iteration.
    void move(const PsoSettings& options, const SearchBox& box, UniformSource& rng) {
        double eta0 = 0, eta1 = 0, eta2 = 0;
        auto draw = [&] {
            eta0 = rng.between(0.0, options.w);
            eta1 = rng.between(0.0, options.c1);
            eta2 = rng.between(0.0, options.c2);
        };
        if (options.draw == PsoRandomDraw::per_iteration) draw();
        for (std::size_t i = 0; i < n; ++i) {
            if (options.draw == PsoRandomDraw::per_particle) draw();
            bool any_move = false;
            for (std::size_t j = 0; j < m; ++j) {
                if (options.draw == PsoRandomDraw::per_dimension) draw();
                const std::size_t ij = i * m + j;
                const double v_next = eta0 * v[ij] + eta1 * (personal[ij] - p[ij]) + eta2 * (global[j] - p[ij]);
                const double step = options.velocity_first ? v_next : v[ij];
                v[ij] = v_next;
                double q = p[ij] + step;
                // The bounds are walls: a particle that would leave stops on the wall.
                if (q < box.lower[j]) { q = box.lower[j]; v[ij] = 0.0; }
                if (q > box.upper[j]) { q = box.upper[j]; v[ij] = 0.0; }
                if (q != p[ij]) any_move = true;
                p[ij] = q;
            }
            moved[i] = any_move ? 1 : 0;
        }
    }
};

}  // namespace

PsoSummary run_pso(const PsoSettings& options, const SearchBox& box, CandidateEvaluator& evaluator,
                   const PsoProgress& progress) {
    const std::size_t m = box.lower.size();
    if (m == 0) throw std::invalid_argument("particle swarm: no free parameters");
    std::size_t n = 0;
    // The start positions use their own stream so that they do not shift the η draws.
    std::vector<double> p = pso_initial_positions(options, box, n, options.seed ^ 0x9E3779B97F4A7C15ull);
    for (std::size_t i = 0; i < n * m; ++i) p[i] = std::clamp(p[i], box.lower[i % m], box.upper[i % m]);
    UniformSource rng(options.seed);
    Swarm swarm(std::move(p), n, m);

    PsoSummary s;
    s.particles = static_cast<int>(n);
    s.termination_type = TerminationType::iteration_limit;
    s.termination = "iteration limit";
    for (int k = 0;; ++k) {
        if (!swarm.score_moved(evaluator, s)) {
            s.termination_type = TerminationType::stopped;
            s.termination = "stopped";
            break;
        }
        swarm.update_bests();
        s.history.push_back(HistoryRow{k, s.evaluations, swarm.global_cost});
        s.iterations = k;
        if (progress && !progress(s.history.back())) {
            s.termination_type = TerminationType::stopped;
            s.termination = "stopped";
            break;
        }
        if (k >= options.iterations) break;
        swarm.move(options, box, rng);
    }
    s.best = swarm.global;
    s.best_cost = swarm.global_cost;
    s.convergence = swarm_convergence(swarm.personal, swarm.personal_cost, n, m, box, s.history);
    if (!std::isfinite(swarm.global_cost) && s.termination_type != TerminationType::stopped) {
        s.termination_type = TerminationType::all_failed;
        s.termination = "all candidates failed";
    }
    // The swarm has no convergence test: its iterations run out when it is done.
    s.success = s.termination_type == TerminationType::iteration_limit;
    return s;
}

void to_parameters(const ParameterScaling& scaling, PsoSummary& s) {
    scaling.best_to_parameters(s);
    scaling.map_point(s.first_failed);
}

}  // namespace tvid
