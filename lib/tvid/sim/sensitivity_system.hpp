#pragma once
// The forward-sensitivity system of the methodology paper eq. 9 as one odeint system of plain doubles:
// z = [x, S] with S = ∂x/∂q (state size N × D directions q, row-major), and
//
//   x' = f(x, p),   S' = ∂f/∂x · S + ∂f/∂q
//
// evaluated in one pass of the templated model code with dual numbers: the state carries
// its sensitivity rows as derivatives, the parameters carry their own seeded directions
// (set on the model by the caller), so the Dual right-hand side holds f and S' at once.
// Any odeint stepper then integrates the state and its sensitivities together; with RK4
// the sensitivities are exactly the derivatives of the RK4 solution.

#include <cstddef>
#include <vector>

#include "tvid/model/dual.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/channels/input_channels.hpp"

namespace tvid {

class SensitivitySystem {
public:
    /// `model` has its parameters set with D seeded directions; `x`, `dxdt` are scratch of
    /// the state size. Allocation-free per evaluation.
    SensitivitySystem(NetworkModel<Dual>& model, const InputChannels& inputs, std::vector<double>& u,
                      std::vector<Dual>& x, std::vector<Dual>& dxdt, int directions)
        : model_(&model), inputs_(&inputs), u_(&u), x_(&x), dxdt_(&dxdt), directions_(directions) {}

    void operator()(const std::vector<double>& z, std::vector<double>& dzdt, double t) {
        inputs_->at(t, hint_, u_->data());
        const std::size_t n = x_->size();
        const auto d = static_cast<std::size_t>(directions_);
        unpack(z, n, d, *x_);
        model_->derivative(x_->data(), u_->data(), dxdt_->data());
        for (std::size_t i = 0; i < n; ++i) {
            const Dual& f = (*dxdt_)[i];
            dzdt[i] = f.value();
            double* row = dzdt.data() + n + i * d;
            const int live = f.size();
            for (std::size_t j = 0; j < d; ++j) row[j] = static_cast<int>(j) < live ? f.derivatives()[j] : 0.0;
        }
    }

    /// The model's sampled elements (NetworkModel::samples) restarted and sampled at the
    /// Dual state z holds: the outputs they hold carry their derivatives (through the
    /// sampled states and the parameters) into S' until the next sample.
    void restart_sampling(const std::vector<double>& z, const std::vector<double>& u) {
        if (!model_->samples()) return;
        unpack(z, x_->size(), static_cast<std::size_t>(directions_), *x_);
        model_->restart_sampling(x_->data(), u.data());
    }
    void sample(double t, const std::vector<double>& z, const std::vector<double>& u) {
        if (!model_->samples()) return;
        unpack(z, x_->size(), static_cast<std::size_t>(directions_), *x_);
        model_->sample(t, x_->data(), u.data());
    }

    /// The Dual state (value, sensitivity rows) held in z.
    static void unpack(const std::vector<double>& z, std::size_t n, std::size_t d, std::vector<Dual>& x) {
        for (std::size_t i = 0; i < n; ++i) {
            Dual& xi = x[i];
            xi.set_value(z[i]);
            xi.resize(static_cast<int>(d));
            const double* row = z.data() + n + i * d;
            for (std::size_t j = 0; j < d; ++j) xi.derivatives()[j] = row[j];
        }
    }

private:
    NetworkModel<Dual>* model_;
    const InputChannels* inputs_;
    std::vector<double>* u_;
    std::vector<Dual>* x_;
    std::vector<Dual>* dxdt_;
    int directions_;
    std::size_t hint_ = 0;
};

}  // namespace tvid
