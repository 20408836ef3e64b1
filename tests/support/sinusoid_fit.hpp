#pragma once
// A small least-squares problem with many local minima and a known global one: the
// amplitude a and angular frequency ω of y = a sin(ω t), sampled at t = 0, 0.1, …, 9.9
// from (a, ω) = (1.5, 3). Away from ω = 3 the cost has a local minimum near every few
// tenths of ω, so a local method needs a start close to the truth.

#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "tvid/optim/candidate_evaluator.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"

namespace tvid::test {

struct SinusoidFit : LeastSquaresProblem, CandidateEvaluator {
    static constexpr double kAmplitude = 1.5, kFrequency = 3.0;
    std::vector<double> t, y;
    long long calls = 0;  ///< residual, Jacobian and candidate evaluations

    SinusoidFit() {
        for (int i = 0; i < 100; ++i) {
            t.push_back(0.1 * i);
            y.push_back(kAmplitude * std::sin(kFrequency * t.back()));
        }
    }
    std::size_t residual_count() const override { return t.size(); }
    bool residuals(const double* x, double* r) override {
        ++calls;
        for (std::size_t i = 0; i < t.size(); ++i) r[i] = x[0] * std::sin(x[1] * t[i]) - y[i];
        return true;
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        ++calls;
        for (std::size_t i = 0; i < t.size(); ++i) {
            const auto row = static_cast<Eigen::Index>(i);
            r[i] = x[0] * std::sin(x[1] * t[i]) - y[i];
            J(row, 0) = std::sin(x[1] * t[i]);
            J(row, 1) = x[0] * t[i] * std::cos(x[1] * t[i]);
        }
        return true;
    }
    double cost(const double* x) {
        double sum = 0.0;
        for (std::size_t i = 0; i < t.size(); ++i) sum += std::pow(x[0] * std::sin(x[1] * t[i]) - y[i], 2);
        return sum;
    }
    void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) override {
        for (std::size_t c = 0; c < count; ++c) {
            ++calls;
            costs[c] = cost(candidates + c * dimension);
        }
    }
};

}  // namespace tvid::test
