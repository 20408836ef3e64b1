#include "tvid/estimation/batch_cost.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <type_traits>

#include "tvid/channels/channel_delay.hpp"
#include "tvid/estimation/window_score.hpp"
#include "tvid/sim/batch_rk4.hpp"
#include "tvid/sim/state_size_dispatch.hpp"
#include "tvid/util/parallel_region.hpp"

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

// Every candidate's score as IdentificationProblem::cost keeps it for one candidate,
// between the pieces of a window: its state, the sums so far, and its result once it is
// known (a cut at the bound, a failure, or the full cost).
struct CandidateScores {
    std::size_t parameter_count = 0;
    std::vector<double> parameters;  ///< full model parameter vectors, one after the other
    std::vector<double> state;       ///< the state where the last piece ended
    std::vector<double> total, window_sum, bound, result;  ///< window_sum: of the current window so far
    std::vector<char> live;           ///< still being scored

    void finish(std::size_t c, double cost) {
        result[c] = cost;
        live[c] = 0;
    }
};

// Packs of up to W candidates: which candidate each lane holds (lanes past `size` repeat
// the first, so that they compute nothing unusual, and are not scored).
struct Group {
    std::array<std::size_t, W> candidate{};
    std::size_t size = 0;
};

// A piece of a window: samples a to b of estimation window `window`.
struct Stage {
    std::size_t window = 0, a = 0, b = 0;
    bool score_first = false;  ///< score sample a before marching (the warm-up's first matching sample)
    bool ends_window = false;
};

// Which candidates wait for which stage. A group is formed from 16 candidates waiting
// for the same stage, or from fewer at the lowest stage still occupied (no more can
// arrive there); so no thread waits for the others at the end of a stage, as a barrier
// would make it.
class StageQueues {
public:
    explicit StageQueues(std::size_t stages) : ready_(stages), occupied_(stages, 0) {}

    /// Before the threads start: candidate c waits for stage 0.
    void add(std::size_t c) {
        ready_[0].push_back(c);
        ++occupied_[0];
        ++remaining_;
    }

    /// The next group and its stage; false when every candidate is done or `stop` is set.
    bool take(Group& group, std::size_t& stage, const std::atomic<bool>* stop) {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            if (stop && stop->load(std::memory_order_relaxed)) stopped_ = true;
            if (stopped_ || remaining_ == 0) {
                changed_.notify_all();
                return false;
            }
            // A full group, the furthest stage first (so that the candidates move on);
            // else whatever waits at the lowest occupied stage.
            for (std::size_t k = ready_.size(); k-- > 0;)
                if (ready_[k].size() >= static_cast<std::size_t>(W)) return pop(k, group, stage);
            for (std::size_t k = 0; k < ready_.size(); ++k)
                if (occupied_[k] > 0) {
                    if (!ready_[k].empty()) return pop(k, group, stage);
                    break;
                }
            changed_.wait(lock);
        }
    }

    /// The group of `stage` is done; `next` of its candidates go on to the next stage.
    void done(const Group& group, std::size_t stage, std::span<const std::size_t> next) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            occupied_[stage] -= group.size;
            remaining_ -= group.size - next.size();
            for (std::size_t c : next) {
                ready_[stage + 1].push_back(c);
                ++occupied_[stage + 1];
            }
        }
        changed_.notify_all();
    }

    bool stopped() const { return stopped_; }

    /// A thread failed: every take() returns false from now on.
    void abandon() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopped_ = true;
        }
        changed_.notify_all();
    }

private:
    bool pop(std::size_t k, Group& group, std::size_t& stage) {
        std::vector<std::size_t>& r = ready_[k];
        group.size = std::min<std::size_t>(W, r.size());
        for (std::size_t l = 0; l < static_cast<std::size_t>(W); ++l)
            group.candidate[l] = r[r.size() - (l < group.size ? l : 0) - 1];
        r.resize(r.size() - group.size);
        stage = k;
        return true;
    }

    std::mutex mutex_;
    std::condition_variable changed_;
    std::vector<std::vector<std::size_t>> ready_;  ///< candidates waiting for each stage
    std::vector<std::size_t> occupied_;            ///< candidates waiting for or running each stage
    std::size_t remaining_ = 0;                    ///< candidates not done
    bool stopped_ = false;
};

template <std::size_t N>
class RegroupedScoring {
public:
    RegroupedScoring(const IdentificationProblem& problem, std::span<BatchWorkspace* const> workspaces,
                     const std::atomic<bool>* stop)
        : problem_(problem), d_(problem.definition()), workspaces_(workspaces), stop_(stop) {
        delayed_output_.assign(d_.measured.size(), -1);
        for (std::size_t q = 0; q < d_.delayed_outputs.size(); ++q)
            delayed_output_[d_.delayed_outputs[q].channel] = static_cast<int>(q);
        // Each window in pieces of kRegroupMinSamples samples or more, at most kRegroupPieces.
        // A model with sampled elements (a digital controller) marches each window whole:
        // their memory restarts where a march starts (march_batch_rk4) and stays in the lanes.
        const bool whole_windows = has_sampled_elements(d_.network);
        for (std::size_t wi = 0; wi < d_.estimation.size(); ++wi) {
            const Window& w = d_.estimation[wi];
            const std::size_t from = problem_.warms_up(w) ? w.first : w.start;
            const std::size_t length = w.last > from ? w.last - from : 0;
            const std::size_t pieces =
                whole_windows ? 1 : std::clamp<std::size_t>(length / kRegroupMinSamples, 1, kRegroupPieces);
            for (std::size_t k = 0; k < pieces; ++k)
                stages_.push_back({wi, from + length * k / pieces, from + length * (k + 1) / pieces,
                                   k == 0 && problem_.warms_up(w), k + 1 == pieces});
        }
    }

    bool run(const double* candidates, std::size_t count, const double* bounds, double* costs) {
        const double inf = std::numeric_limits<double>::infinity();
        const std::size_t m = problem_.dimension();
        candidates_ = candidates;
        CandidateScores& s = scores_;
        s.parameter_count = d_.network.parameter_names.size();
        s.parameters.assign(count * s.parameter_count, 0.0);
        s.state.assign(count * N, 0.0);
        s.total.assign(count, 0.0);
        s.window_sum.assign(count, 0.0);
        s.result.assign(count, inf);
        s.bound.assign(count, inf);
        s.live.assign(count, 0);
        // A candidate with a non-finite value costs +inf unsimulated, as in cost().
        for (std::size_t c = 0; c < count; ++c) {
            if (bounds) s.bound[c] = bounds[c];
            if (!all_finite(candidates + c * m, m)) continue;
            s.live[c] = 1;
            problem_.full_parameters(candidates + c * m, workspaces_[0]->scalar->params);
            std::copy(workspaces_[0]->scalar->params.begin(), workspaces_[0]->scalar->params.end(),
                      s.parameters.begin() + static_cast<std::ptrdiff_t>(c * s.parameter_count));
        }
        bool complete = true;
        if (!stages_.empty()) {
            // The first window's starts, on all threads; then the stages.
            const auto n = static_cast<long long>(count);
            const int threads = static_cast<int>(workspaces_.size());
            FirstException errors;
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
            for (long long c = 0; c < n; ++c) try {
                if (s.live[static_cast<std::size_t>(c)])
                    start_window(static_cast<std::size_t>(c), 0, *workspaces_[static_cast<std::size_t>(omp_get_thread_num())]->scalar);
            } catch (...) {
                errors.capture();
            }
            errors.rethrow();
            StageQueues queues(stages_.size());
            for (std::size_t c = 0; c < count; ++c)
                if (s.live[c]) queues.add(c);
#pragma omp parallel num_threads(threads)
            {
                BatchWorkspace& ws = *workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
                std::vector<std::size_t> next;
                Group group;
                std::size_t stage = 0;
                try {
                    while (queues.take(group, stage, stop_)) {
                        march_stage(ws, group, stage, next);
                        queues.done(group, stage, next);
                    }
                } catch (...) {
                    errors.capture();
                    queues.abandon();  // the others wait for no group of this thread
                }
            }
            errors.rethrow();
            complete = !queues.stopped();
        }
        for (std::size_t c = 0; c < count; ++c) {
            if (s.live[c]) s.result[c] = complete ? finished_cost(s.total[c]) : inf;
            costs[c] = s.result[c];
        }
        return complete;
    }

private:
    // Candidate c's start of window `wi` from the scalar model with its parameters
    // (equilibrium or warm-up shooting); a candidate without one costs +inf.
    void start_window(std::size_t c, std::size_t wi, ProblemWorkspace& ws) {
        CandidateScores& s = scores_;
        ws.params.assign(s.parameters.begin() + static_cast<std::ptrdiff_t>(c * s.parameter_count),
                         s.parameters.begin() + static_cast<std::ptrdiff_t>((c + 1) * s.parameter_count));
        ws.model.set_parameters(ws.params.data());
        problem_.apply_channel_delays(ws);  // a measured start reads the shifted speed
        s.window_sum[c] = 0.0;
        if (problem_.start_window(d_.estimation[wi], ws, nullptr).status != SimulationStatus::ok) {
            s.finish(c, std::numeric_limits<double>::infinity());
            return;
        }
        if (ws.substeps > 1 || ws.implicit_steps) {
            // A stiff candidate takes a smaller step than the lanes share, or sdirk3's steps
            // (stable_step.hpp): scored alone, as cost() scores it.
            s.finish(c, problem_.cost(candidates_ + c * problem_.dimension(), ws));
            return;
        }
        std::copy_n(ws.x.begin(), N, s.state.begin() + static_cast<std::ptrdiff_t>(c * N));
    }

    // One stage for the candidates of `group`; `next` receives those that go on to the
    // next stage (at the end of a window: with their window's share added and the next
    // window's start solved).
    void march_stage(BatchWorkspace& ws, const Group& group, std::size_t k, std::vector<std::size_t>& next) {
        const Stage& stage = stages_[k];
        const Window& w = d_.estimation[stage.window];
        march_group(ws, group, w, stage.a, stage.b, stage.score_first);
        CandidateScores& s = scores_;
        next.clear();
        for (std::size_t l = 0; l < group.size; ++l) {
            const std::size_t c = group.candidate[l];
            if (!s.live[c]) continue;
            if (stage.ends_window) {
                // The candidates that ran to the end add the window's share (l1: its mean).
                const WindowScore<double> window(d_.cost, scored_sample_count(w), s.window_sum[c]);
                s.total[c] = window.partial_cost(s.total[c]);
                if (k + 1 == stages_.size()) continue;
                start_window(c, stages_[k + 1].window, *ws.scalar);
                if (!s.live[c]) continue;
            }
            if (k + 1 < stages_.size()) next.push_back(c);
        }
    }

    void march_group(BatchWorkspace& ws, const Group& group, const Window& w, std::size_t a, std::size_t b,
                     bool score_first) {
        CandidateScores& s = scores_;
        const double inf = std::numeric_limits<double>::infinity();
        const std::size_t n_out = d_.measured.size();
        // The group's lanes from the candidates' scores.
        std::array<P, N> x;
        P total, window_sum, bound;
        Lanes live(false), bounded(false);
        for (int l = 0; l < W; ++l) {
            const std::size_t c = group.candidate[static_cast<std::size_t>(l)];
            for (std::size_t i = 0; i < s.parameter_count; ++i) ws.params[i].set(l, s.parameters[c * s.parameter_count + i]);
            for (std::size_t j = 0; j < N; ++j) x[j].set(l, s.state[c * N + j]);
            total.set(l, s.total[c]);
            window_sum.set(l, s.window_sum[c]);
            bound.set(l, s.bound[c]);
            if (static_cast<std::size_t>(l) < group.size) {
                live.set(l, true);
                bounded.set(l, s.bound[c] < inf);
            }
        }
        ws.model.set_parameters(ws.params.data());
        const auto lane_finish = [&](int l, double cost) {
            s.finish(group.candidate[static_cast<std::size_t>(l)], cost);
            live.set(l, false);
        };

        WindowScore<P> window(d_.cost, scored_sample_count(w), window_sum);
        const std::vector<double>& time = problem_.inputs().time();
        // Output k at sample i: the recording, or, delayed by a parameter, each lane's own
        // reading of it (the bits of the scalar cost's shifted copy: channel_delay.hpp).
        const auto measured = [&](std::size_t k, std::size_t i) {
            const int delayed = delayed_output_[k];
            if (delayed < 0) return P(problem_.measured(k)[i]);
            const ProblemDefinition::DelayedChannel& c = d_.delayed_outputs[static_cast<std::size_t>(delayed)];
            const P& delay = ws.params[static_cast<std::size_t>(c.parameter)];
            std::array<std::size_t, W>& hints = ws.delay_hints[static_cast<std::size_t>(delayed)];
            const SampledSignal recorded = c.signal(time, d_.recordings[w.recording]);
            P y;
            for (int l = 0; l < W; ++l)
                y.set(l, delayed_value(recorded, time[i] + delay[l], hints[static_cast<std::size_t>(l)]));
            return y;
        };
        // Adds sample i's terms and stops the lanes whose partial cost reaches their bound.
        // `after_derivative`: the model's last derivative() was at this sample (the march's).
        auto score = [&](std::size_t i, const std::array<P, N>& xs, const double* u, bool after_derivative) {
            for (std::size_t k = 0; k < n_out; ++k) {
                const auto output = static_cast<std::size_t>(d_.output_indices[k]);
                const P y = after_derivative ? ws.model.output_after_derivative(output, xs.data())
                                             : ws.model.output(output, xs.data(), u);
                window.add(output_residual(P(d_.output_scale[k]), y, measured(k, i)));
            }
            const Lanes watched = bounded & live;
            if (!watched.any()) return;
            const P partial = window.partial_cost(total);
            const Lanes cut = watched & WindowScore<P>::reached(partial, bound);
            for (int l = 0; l < W; ++l)
                if (cut[l]) lane_finish(l, partial[l]);
        };
        if (score_first) {
            std::size_t hint = a;
            ws.u.resize(problem_.inputs().count());
            problem_.inputs().at(problem_.inputs().time()[a], hint, ws.u.data());
            score(a, x, ws.u.data(), false);
        }
        // A speed beyond the measured range fails the lane, as it fails the scalar simulation.
        const bool speed_limited = d_.speed_limited();
        std::array<P, N / 2> speed_limit;  // per node; infinite where nothing ties it to a measured speed
        for (std::size_t j = 0; j < N / 2; ++j)
            speed_limit[j] = P(j < d_.speed_limits.size() ? d_.speed_limits[j] : std::numeric_limits<double>::infinity());
        const auto observe = [&](std::size_t i, const std::array<P, N>& xs, const std::vector<double>& u,
                                 const Lanes& sane) {
            Lanes physical = sane;
            if (speed_limited)
                for (std::size_t j = N / 2; j < N; ++j) physical = physical & (abs(xs[j]) <= speed_limit[j - N / 2]);
            for (int l = 0; l < W; ++l)
                if (live[l] && !physical[l]) lane_finish(l, inf);  // diverged, not finite, or too fast
            if (i >= w.first && live.any()) score(i, xs, u.data(), true);
            return live;
        };
        Lanes active = live;
        march_batch_rk4<N, W>(ws.model, problem_.inputs(), a, b, x, d_.simulation.max_step, ws.u, ws.u_stage, active,
                              ws.rhs_evaluations, ws.pack_rhs_evaluations, observe);
        // The lanes still live carry their state and sums to the next piece.
        for (int l = 0; l < W; ++l) {
            if (!live[l]) continue;
            const std::size_t c = group.candidate[static_cast<std::size_t>(l)];
            for (std::size_t j = 0; j < N; ++j) s.state[c * N + j] = x[j][l];
            s.window_sum[c] = window.sum()[l];
        }
    }

    const IdentificationProblem& problem_;
    const ProblemDefinition& d_;
    std::span<BatchWorkspace* const> workspaces_;
    const std::atomic<bool>* stop_;
    const double* candidates_ = nullptr;  ///< the candidates of the current run, m values each
    CandidateScores scores_;
    std::vector<Stage> stages_;
    std::vector<int> delayed_output_;  ///< per output: its index in d_.delayed_outputs, or -1
};

}  // namespace

BatchWorkspace::BatchWorkspace(const IdentificationProblem& problem)
    : scalar(problem.make_workspace()), model(problem.definition().network) {
    model.set_crank_angle_inputs(&problem.crank_angle_inputs());
    params.resize(problem.definition().network.parameter_names.size());
    u.resize(problem.inputs().count());
    delay_hints.assign(problem.definition().delayed_outputs.size(), {});
}

bool batch_supported(const IdentificationProblem& problem) {
    const ProblemDefinition& d = problem.definition();
    // A filtered output is scored once its window is complete: the scalar cost does that.
    // An input delayed by a parameter differs from lane to lane, and the lanes share their inputs.
    return steps_by_rk4(d.simulation.method) && has_fixed_state_size(d.network.state_size()) &&
           !d.filtered && d.delayed_inputs.empty();
}

bool batch_costs(const IdentificationProblem& problem, const double* candidates, std::size_t count,
                 const double* bounds, std::span<BatchWorkspace* const> workspaces, const std::atomic<bool>* stop,
                 double* costs) {
    if (count == 0) return true;
    const auto run = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
        return RegroupedScoring<N>(problem, workspaces, stop).run(candidates, count, bounds, costs);
    };
    const auto one_at_a_time = [&] {  // not batchable
        for (std::size_t l = 0; l < count; ++l)
            costs[l] = problem.cost(candidates + l * problem.dimension(), *workspaces[0]->scalar,
                                    bounds ? bounds[l] : std::numeric_limits<double>::infinity());
        return true;
    };
    return dispatch_state_size(problem.definition().network.state_size(), run, one_at_a_time);
}

void batch_costs(const IdentificationProblem& problem, const double* candidates, std::size_t count,
                 const double* bounds, BatchWorkspace& ws, double* costs) {
    BatchWorkspace* const one[] = {&ws};
    batch_costs(problem, candidates, count, bounds, one, nullptr, costs);
}

}  // namespace tvid
