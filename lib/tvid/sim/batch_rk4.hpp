#pragma once
// RK4 over W simulations at once: the fixed-size RK4 of fixed_state_rk4.hpp (the same
// stages, coefficients, stage inputs and order of operations) with a state of packs,
// lane i one candidate's simulation. Every lane computes the bits its candidate's scalar
// simulation computes; lanes only share the time grid and the inputs.
//
// At every sample the observer sees the state and which lanes are sane (finite, below
// the divergence limit, as fixed_state_is_sane tests the scalar state) and answers which
// lanes must go on; the march ends when none must. The first stage of the next step is
// evaluated before the observer is called, at the sample's state and inputs, so the
// observer reads the outputs from it (NetworkModel::output_after_derivative) instead of
// evaluating the elements once more.
//
// Sampled elements (a digital controller) restart their memory where the march starts and
// sample at every later sample, before the observer: a caller marches a simulation of such
// a model whole, from its true start.

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "tvid/model/network_model.hpp"
#include "tvid/channels/input_channels.hpp"
#include "tvid/sim/observation_loops.hpp"
#include "tvid/sim/rk4_stages.hpp"
#include "tvid/sim/simulation_status.hpp"
#include "tvid/simd/pack.hpp"

namespace tvid {

/// The lanes whose state is finite and within kDivergenceLimit in every component.
template <std::size_t N, int W>
Mask<W> sane_lanes(const std::array<Pack<W>, N>& x) {
    Mask<W> sane(true);
    for (std::size_t j = 0; j < N; ++j) sane = sane & (abs(x[j]) <= Pack<W>(kDivergenceLimit));  // NaN fails
    return sane;
}

/// RK4 from sample `start` to `last` for the W lanes of `x`, `max_step` as in
/// march_fixed_state_rk4, calling `observer(i, x, u, sane)` at every sample i in
/// (start, last] with u the inputs at time[i]; it returns the lanes still needed. `active`
/// holds the lanes needed at the start and is left with those needed at the end; `rhs`
/// grows by the right-hand sides of the needed lanes (what their scalar simulations would
/// have evaluated), `pack_rhs` by those of the packs (the work done: W lanes each).
template <std::size_t N, int W, class Observer>
void march_batch_rk4(NetworkModel<Pack<W>>& model, const InputChannels& inputs, std::size_t start, std::size_t last,
                     std::array<Pack<W>, N>& x, double max_step, std::vector<double>& u,
                     std::vector<double>& u_stage, Mask<W>& active, std::size_t& rhs, std::size_t& pack_rhs,
                     Observer&& observer) {
    using P = Pack<W>;
    u.resize(inputs.count());
    Rk4StageInputs in(inputs, u_stage, start);
    Rk4Stages<P, N> k;
    std::size_t needed = 0;
    for (int l = 0; l < W; ++l) needed += active[l] ? 1 : 0;
    if (needed == 0 || start >= last) return;
    // Sampled elements restart at `start` (the caller marches whole simulations).
    const auto step = [&](const FixedStep& s) {
        const double dt = s.dt;
        // The stage inputs; k1, at the substep's start, is known at a later sample (from
        // arriving there, below).
        in.read(s, false);
        if (s.substep > 0) {
            model.derivative(x.data(), in.u0, k.k1.data());
        } else if (s.sample == start) {
            model.derivative(x.data(), u.data(), k.k1.data());
            ++pack_rhs;
        }
        rk4_from_first_stage(model, x, k, in, P(0.5 * dt), P(dt), P((1.0 / 6.0) * dt), P((1.0 / 3.0) * dt));
        rhs += 4 * needed;
        pack_rhs += 4;
    };
    const auto look = [&](std::size_t i) {
        model.derivative(x.data(), u.data(), k.k1.data());  // the next step's first stage, at sample i
        active = observer(i, x, u, sane_lanes(x)) & active;
        needed = 0;
        for (int l = 0; l < W; ++l) needed += active[l] ? 1 : 0;
        return needed > 0 ? SimulationStatus::ok : SimulationStatus::stopped_by_observer;
    };
    const auto lanes_checked_by_observer = [] { return SimulationStatus::ok; };
    march_over_samples(start, last, FixedSubsteps(inputs.time(), max_step, step, lanes_checked_by_observer),
                       sample_hooks(inputs, u, ModelMemory<NetworkModel<P>, P>{model, x.data()}, look));
}

}  // namespace tvid
