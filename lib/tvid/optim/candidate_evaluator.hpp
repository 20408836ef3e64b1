#pragma once
// The fitness side of an optimizer: costs of a batch of candidate parameter vectors.
// Implementations may evaluate the batch in parallel; the costs they return must not
// depend on how the batch was split over threads.

#include <cstddef>

namespace tvid {

class CandidateEvaluator {
public:
    virtual ~CandidateEvaluator() = default;
    /// `candidates` holds `count` vectors of `dimension` values, one after the other;
    /// costs[i] receives the cost of candidate i (+inf for a candidate that fails).
    virtual void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) = 0;
    /// As evaluate(), knowing that the caller only asks whether candidate i beats bounds[i]
    /// (a particle's personal best): an implementation whose cost is a sum of non-negative
    /// terms may stop a candidate as soon as its partial sum reaches bounds[i] and return
    /// that partial sum (>= bounds[i], so "not better", as the full cost would be). A
    /// bound of +inf asks for the full cost. The default ignores the bounds.
    virtual void evaluate_bounded(const double* candidates, std::size_t count, std::size_t dimension,
                                  const double* /*bounds*/, double* costs) {
        evaluate(candidates, count, dimension, costs);
    }
    /// True when a stop request (Ctrl-C) cut the last evaluate() short: some candidates
    /// were skipped (cost +inf without a simulation), so the batch must be discarded.
    virtual bool stopped() const { return false; }
    /// Right-hand sides of the model evaluated so far (0 where the evaluator does not count
    /// them): the work behind the costs, which the stop at a bound reduces.
    virtual std::size_t right_hand_sides() const { return 0; }
};

}  // namespace tvid
