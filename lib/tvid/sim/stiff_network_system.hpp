#pragma once
// The network as the (system, Jacobian) pair that odeint's Rosenbrock stepper takes, on
// the ublas vectors it requires: f(x, u(t)); ∂f/∂x by dual numbers through the element
// code (StateJacobian); and ∂f/∂t, which comes from the inputs alone. Within a sample
// interval [t_i, t_i+1] the inputs are linear in t, and they enter f through applied
// torques, affine in u, so ∂f/∂t = (f(x, u_i+1) − f(x, u_i)) / (t_i+1 − t_i) exactly.

#include <boost/numeric/odeint.hpp>
#include <boost/numeric/ublas/matrix.hpp>
#include <boost/numeric/ublas/vector.hpp>
#include "tvid/sim/ublas_cxx20.hpp"  // after the uBLAS headers, before any use
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "tvid/model/network_model.hpp"
#include "tvid/model/state_jacobian.hpp"
#include "tvid/channels/input_channels.hpp"

namespace tvid {

using UblasVector = boost::numeric::ublas::vector<double>;
using UblasMatrix = boost::numeric::ublas::matrix<double>;

/// odeint's coefficients of Hairer & Wanner's RODAS with the sign of γ4 = Σ_j γ4j restored
/// to −0.0362 (Boost.Odeint has +0.0362). γ_i weighs ∂f/∂t in stage i, so with the wrong
/// sign a non-autonomous system (driven by measured inputs) is integrated only to first
/// order in t; an autonomous one never notices.
struct RodasCoefficients : boost::numeric::odeint::default_rosenbrock_coefficients<double> {
    const double d4 = -0.3620000000000023e-01;  // hides the base's d4
};
using Rosenbrock4 = boost::numeric::odeint::rosenbrock4<double, RodasCoefficients>;

/// Scratch space of the stiff integrator, reused from one simulation to the next.
struct StiffBuffers {
    Rosenbrock4 rosenbrock4;              ///< copied into each simulation's controller
    UblasVector state;                    ///< x while rosenbrock4 steps it
    StateJacobian jacobian;               ///< the dual-number model, built on first use for a spec
    std::vector<double> u_start, u_end;   ///< inputs at the ends of the current sample interval
    std::vector<double> f_start, f_end;   ///< f(x, u_start), f(x, u_end)
    std::vector<double> f;                ///< f(x, u(t)) from the Jacobian's evaluation
};

class StiffNetworkSystem {
public:
    StiffNetworkSystem(NetworkModel<double>& model, const InputChannels& inputs, std::vector<double>& u,
                       StiffBuffers& buffers)
        : model_(&model), inputs_(&inputs), u_(&u), b_(&buffers) {
        const std::size_t n = model.state_size(), m = inputs.count();
        b_->jacobian.bind(model);
        b_->u_start.resize(m);
        b_->u_end.resize(m);
        b_->f_start.resize(n);
        b_->f_end.resize(n);
        b_->f.resize(n);
        u_->resize(m);
    }

    /// The steps that follow lie in sample interval [time[i], time[i+1]].
    void enter_interval(std::size_t i) {
        const std::vector<double>& time = inputs_->time();
        inputs_changing_ = false;
        for (std::size_t k = 0; k < inputs_->count(); ++k) {
            b_->u_start[k] = inputs_->value(k, i);
            b_->u_end[k] = inputs_->value(k, i + 1);
            inputs_changing_ = inputs_changing_ || b_->u_start[k] != b_->u_end[k];
        }
        interval_ = time[i + 1] - time[i];
    }

    /// The sampled elements (NetworkModel::samples) restarted at the simulation's start and
    /// sampled at each later sample, in f and in its Jacobian alike.
    void restart_sampling(const std::vector<double>& x, const std::vector<double>& u) {
        model_->restart_sampling(x.data(), u.data());
        b_->jacobian.restart_sampling(x.data(), u.data());
    }
    void sample(double t, const std::vector<double>& x, const std::vector<double>& u) {
        model_->sample(t, x.data(), u.data());
        b_->jacobian.sample(t, x.data(), u.data());
    }

    /// dx/dt = f(x, u(t)).
    void rhs(const UblasVector& x, UblasVector& dxdt, double t) {
        ++evaluations;
        inputs_->at(t, hint_, u_->data());
        model_->derivative(&x[0], u_->data(), &dxdt[0]);
    }

    /// J = ∂f/∂x at (x, u(t)) and dfdt = ∂f/∂t (zero while the inputs hold still).
    void jacobian(const UblasVector& x, UblasMatrix& J, double t, UblasVector& dfdt) {
        ++jacobians;
        const std::size_t n = x.size();
        inputs_->at(t, hint_, u_->data());
        b_->jacobian.evaluate(&x[0], u_->data(), &J.data()[0], b_->f.data());
        if (inputs_changing_) {
            evaluations += 2;
            model_->derivative(&x[0], b_->u_start.data(), b_->f_start.data());
            model_->derivative(&x[0], b_->u_end.data(), b_->f_end.data());
            for (std::size_t i = 0; i < n; ++i) dfdt[i] = (b_->f_end[i] - b_->f_start[i]) / interval_;
        } else {
            for (std::size_t i = 0; i < n; ++i) dfdt[i] = 0.0;
        }
        // A step starts from x: if f or J is not finite there, no step size can help.
        start_finite_ = true;
        for (std::size_t i = 0; i < n; ++i) start_finite_ = start_finite_ && std::isfinite(b_->f[i]) && std::isfinite(dfdt[i]);
        for (std::size_t i = 0; i < n * n && start_finite_; ++i) start_finite_ = std::isfinite(J.data()[i]);
    }

    /// Whether f, ∂f/∂x and ∂f/∂t were finite at the start of the last step tried.
    bool start_finite() const { return start_finite_; }

    /// The pair odeint's rosenbrock4 steps: (x, dxdt, t) and (x, J, t, dfdt).
    auto odeint_system() {
        return std::make_pair([this](const UblasVector& x, UblasVector& dxdt, double t) { rhs(x, dxdt, t); },
                              [this](const UblasVector& x, UblasMatrix& J, double t, UblasVector& dfdt) {
                                  jacobian(x, J, t, dfdt);
                              });
    }

    std::size_t evaluations = 0;  ///< f evaluations with double
    std::size_t jacobians = 0;    ///< Jacobian evaluations (one dual-number f per kDualCapacity states)

private:
    NetworkModel<double>* model_;
    const InputChannels* inputs_;
    std::vector<double>* u_;
    StiffBuffers* b_;
    std::size_t hint_ = 0;
    double interval_ = 1.0;
    bool inputs_changing_ = false;
    bool start_finite_ = true;
};

}  // namespace tvid
