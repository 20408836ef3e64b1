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
    /// True when a stop request (Ctrl-C) cut the last evaluate() short: some candidates
    /// were skipped (cost +inf without a simulation), so the batch must be discarded.
    virtual bool stopped() const { return false; }
};

}  // namespace tvid
