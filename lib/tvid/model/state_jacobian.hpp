#pragma once
// ∂f/∂x of a network's right-hand side dx/dt = f(x, u), the Jacobian a stiff (Rosenbrock)
// integrator needs, by forward-mode dual numbers: the same templated element code as f,
// run as NetworkModel<Dual> with the state as the variables, so the Jacobian is exact to
// rounding and follows every element without a difference quotient. States beyond
// kDualCapacity are seeded in chunks of kDualCapacity columns. Allocates nothing after
// the first bind to a spec.

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "tvid/model/dual.hpp"
#include "tvid/model/network_model.hpp"

namespace tvid {

class StateJacobian {
public:
    /// Follows `model`: its spec (the dual model is built on first use and rebuilt only
    /// when the spec changes), its crank-angle channels and its current parameters.
    void bind(const NetworkModel<double>& model) {
        const NetworkSpec& spec = model.spec();
        if (!dual_model_ || spec_ != &spec || shape_ != shape_of(spec)) {
            dual_model_.emplace(spec);
            spec_ = &spec;
            shape_ = shape_of(spec);
            parameters_.resize(spec.parameter_names.size());
            x_.resize(spec.state_size());
            f_.resize(spec.state_size());
        }
        dual_model_->set_crank_angle_inputs(model.crank_angle_inputs());
        const std::vector<double>& p = model.parameters();
        for (std::size_t j = 0; j < parameters_.size(); ++j) parameters_[j] = Dual(p[j]);  // constants
        dual_model_->set_parameters(parameters_.data());
    }

    std::size_t state_size() const { return x_.size(); }

    /// The dual model's sampled elements (NetworkModel::samples) follow the simulation's:
    /// restarted and sampled at the same states, their held outputs are constants of a step
    /// (no column of the Jacobian), as they are in f.
    void restart_sampling(const double* x, const double* u) {
        if (!dual_model_->samples()) return;
        for (std::size_t j = 0; j < x_.size(); ++j) x_[j] = Dual(x[j]);
        dual_model_->restart_sampling(x_.data(), u);
    }
    void sample(double t, const double* x, const double* u) {
        if (!dual_model_->samples()) return;
        for (std::size_t j = 0; j < x_.size(); ++j) x_[j] = Dual(x[j]);
        dual_model_->sample(t, x_.data(), u);
    }

    /// jacobian[i·n + j] = ∂f_i/∂x_j at (x, u), row-major n × n with n = state_size();
    /// also f(x, u) itself into `f` when given.
    void evaluate(const double* x, const double* u, double* jacobian, double* f = nullptr) {
        const std::size_t n = x_.size();
        for (std::size_t first = 0; first < n; first += kDualCapacity) {
            const std::size_t width = std::min<std::size_t>(kDualCapacity, n - first);
            // Columns first … first+width−1: those states carry a unit direction each.
            seed_state_directions(x, n, first, width, x_.data());
            dual_model_->derivative(x_.data(), u, f_.data());
            if (f && first == 0)
                for (std::size_t i = 0; i < n; ++i) f[i] = f_[i].value();
            for (std::size_t i = 0; i < n; ++i)
                for (std::size_t c = 0; c < width; ++c)
                    jacobian[i * n + first + c] = f_[i].derivative(static_cast<int>(c));
        }
    }

private:
    // The counts the dual model's buffers were sized for: parameters, nodes, outputs and
    // the elements of each kind.
    using Shape = std::array<std::size_t, 3 + kElementKindCount>;
    static Shape shape_of(const NetworkSpec& s) {
        Shape shape{s.parameter_names.size(), s.nodes.size(), s.outputs.size()};
        const auto counts = element_counts(s);
        std::copy(counts.begin(), counts.end(), shape.begin() + 3);
        return shape;
    }

    const NetworkSpec* spec_ = nullptr;
    Shape shape_{};
    std::optional<NetworkModel<Dual>> dual_model_;
    std::vector<Dual> parameters_, x_, f_;
};

}  // namespace tvid
