#pragma once
// ∂f/∂x of a network's right-hand side dx/dt = f(x, u), the Jacobian a stiff (Rosenbrock)
// integrator needs, by forward-mode dual numbers: the same templated element code as f,
// run with the state as the variables, so the Jacobian is exact to rounding and follows
// every element without a difference quotient. The numbers are PackedDual<8>: eight
// columns in one SIMD pack per pass, a state of more than eight seeded in chunks of eight
// (the driveline's eight states: one pass at 72 bytes a number, where Dual's fixed
// capacity of 32 directions copies 264). Allocates nothing after the first bind to a spec.

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "tvid/model/packed_dual.hpp"
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
        for (std::size_t j = 0; j < parameters_.size(); ++j) parameters_[j] = Number(p[j]);  // constants
        dual_model_->set_parameters(parameters_.data());
    }

    std::size_t state_size() const { return x_.size(); }

    /// The dual model's sampled elements (NetworkModel::samples) follow the simulation's:
    /// restarted and sampled at the same states, their held outputs are constants of a step
    /// (no column of the Jacobian), as they are in f.
    void restart_sampling(const double* x, const double* u) {
        if (!dual_model_->samples()) return;
        for (std::size_t j = 0; j < x_.size(); ++j) x_[j] = Number(x[j]);
        dual_model_->restart_sampling(x_.data(), u);
    }
    void sample(double t, const double* x, const double* u) {
        if (!dual_model_->samples()) return;
        for (std::size_t j = 0; j < x_.size(); ++j) x_[j] = Number(x[j]);
        dual_model_->sample(t, x_.data(), u);
    }

    /// jacobian[i·n + j] = ∂f_i/∂x_j at (x, u), row-major n × n with n = state_size();
    /// also f(x, u) itself into `f` when given.
    void evaluate(const double* x, const double* u, double* jacobian, double* f = nullptr) {
        const std::size_t n = x_.size();
        for (std::size_t first = 0; first < n; first += kColumns) {
            const std::size_t width = std::min<std::size_t>(kColumns, n - first);
            // Columns first … first+width−1: those states carry a unit direction each.
            for (std::size_t j = 0; j < n; ++j)
                x_[j] = j >= first && j < first + width ? Number::variable(x[j], static_cast<int>(j - first)) : Number(x[j]);
            dual_model_->derivative(x_.data(), u, f_.data());
            if (f && first == 0)
                for (std::size_t i = 0; i < n; ++i) f[i] = f_[i].value();
            for (std::size_t i = 0; i < n; ++i)
                for (std::size_t c = 0; c < width; ++c)
                    jacobian[i * n + first + c] = f_[i].derivative(static_cast<int>(c));
        }
    }

private:
    static constexpr std::size_t kColumns = 8;
    using Number = PackedDual<static_cast<int>(kColumns)>;

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
    std::optional<NetworkModel<Number>> dual_model_;
    std::vector<Number> parameters_, x_, f_;
};

}  // namespace tvid
