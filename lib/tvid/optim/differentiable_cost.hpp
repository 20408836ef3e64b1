#pragma once
// The objective of a general minimizer (NLopt): a scalar cost of the parameters and, for
// gradient-based algorithms, its gradient. The minimizer knows nothing of models: a fit
// wraps its simulation in a DifferentiableCost.

namespace tvid {

class DifferentiableCost {
public:
    virtual ~DifferentiableCost() = default;
    /// The cost at x; +inf when it cannot be evaluated (e.g. the simulation diverged).
    virtual double value(const double* x) = 0;
    /// The cost at x and its gradient into `gradient` (as many values as x); +inf when
    /// it cannot be evaluated (the gradient is then unspecified).
    virtual double value_and_gradient(const double* x, double* gradient) = 0;
    /// Model simulations run so far when the cost counts them (a gradient may take
    /// several); -1 when it does not, and evaluations are counted instead.
    virtual long long simulations() const { return -1; }
    /// Right-hand sides of the model evaluated so far (0 where not counted).
    virtual long long right_hand_sides() const { return 0; }
};

}  // namespace tvid
