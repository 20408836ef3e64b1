#pragma once
// One classical RK4 step over a fixed-size state, as the fixed-state march (one
// simulation, double or dual numbers) and the batch march (SIMD lanes of candidates) both
// take it: the same stages, coefficients and order of operations as odeint's runge_kutta4
// (x + dt/2·k1, x + dt/2·k2, x + dt·k3, x + dt/6·k1 + dt/3·k2 + dt/3·k3 + dt/6·k4).

#include <array>
#include <cstddef>
#include <vector>

#include "tvid/channels/input_channels.hpp"
#include "tvid/sim/observation_loops.hpp"

namespace tvid {

/// The inputs at RK4's stage times over one fixed step: its start (u0), half a step on (um)
/// and a step on (u1). At the sampling step they are the samples and the precomputed sample
/// midpoints (InputChannels::midpoint); with substeps the interval is known and only the
/// interpolation weight changes.
class Rk4StageInputs {
public:
    Rk4StageInputs(const InputChannels& inputs, std::vector<double>& buffer, std::size_t start)
        : inputs_(&inputs), n_(inputs.count()), hint_(start) {
        buffer.resize(3 * n_);
        u0 = buffer.data();
        um = u0 + n_;
        u1 = um + n_;
    }

    /// The stage inputs of step s; `with_start` false leaves u0 at the sampling step to a
    /// caller that already has the sample's inputs.
    void read(const FixedStep& s, bool with_start) {
        const std::size_t i = s.sample;
        if (s.substeps == 1) {
            for (std::size_t k = 0; k < n_; ++k) {
                if (with_start) u0[k] = inputs_->value(k, i);
                um[k] = inputs_->midpoint(k, i);
                u1[k] = inputs_->value(k, i + 1);
            }
        } else if (n_ > 0) {
            inputs_->at(s.t, hint_, u0);
            inputs_->at(s.t + 0.5 * s.dt, hint_, um);
            inputs_->at(s.t + s.dt, hint_, u1);
        }
    }

    double* u0 = nullptr;
    double* um = nullptr;
    double* u1 = nullptr;

private:
    const InputChannels* inputs_;
    std::size_t n_;
    std::size_t hint_;
};

/// The stage buffers of an RK4 step over a state of N entries of type T.
template <class T, std::size_t N>
struct Rk4Stages {
    std::array<T, N> xt, k1, k2, k3, k4;
};

/// The rest of an RK4 step once its first stage k1 = f(x, u0) is in `k`: the other three
/// stages at the inputs `in` holds, and the update of x. C is the type of the step's
/// coefficients (double, or a pack of them for SIMD lanes).
template <class Model, class T, std::size_t N, class C>
[[gnu::always_inline]] inline void rk4_from_first_stage(Model& model, std::array<T, N>& x, Rk4Stages<T, N>& k,
                                                        const Rk4StageInputs& in, C half, C full, C sixth, C third) {
    for (std::size_t j = 0; j < N; ++j) k.xt[j] = x[j] + half * k.k1[j];
    model.derivative(k.xt.data(), in.um, k.k2.data());
    for (std::size_t j = 0; j < N; ++j) k.xt[j] = x[j] + half * k.k2[j];
    model.derivative(k.xt.data(), in.um, k.k3.data());
    for (std::size_t j = 0; j < N; ++j) k.xt[j] = x[j] + full * k.k3[j];
    model.derivative(k.xt.data(), in.u1, k.k4.data());
    for (std::size_t j = 0; j < N; ++j)
        x[j] = x[j] + sixth * k.k1[j] + third * k.k2[j] + third * k.k3[j] + sixth * k.k4[j];
}

}  // namespace tvid
