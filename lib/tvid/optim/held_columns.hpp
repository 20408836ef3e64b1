#pragma once
// A least-squares problem in some of another's parameters, the others held at given values:
// the start of a recording fitted with a model fitted elsewhere held (`tvid batch --cross`
// with estimated starts). The Jacobian is the whole problem's, its held columns dropped.

#include <Eigen/Core>
#include <cstddef>
#include <utility>
#include <vector>

#include "tvid/optim/levenberg_marquardt.hpp"

namespace tvid {

class HeldColumns final : public LeastSquaresProblem {
public:
    /// `whole` at `point`, with only the parameters `columns` (indices into point) free.
    HeldColumns(LeastSquaresProblem& whole, std::vector<double> point, std::vector<std::size_t> columns)
        : whole_(whole), point_(std::move(point)), columns_(std::move(columns)) {}

    std::size_t residual_count() const override { return whole_.residual_count(); }
    bool residuals(const double* x, double* r) override { return whole_.residuals(at(x), r); }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        whole_J_.resize(static_cast<Eigen::Index>(residual_count()), static_cast<Eigen::Index>(point_.size()));
        if (!whole_.jacobian(at(x), r, whole_J_)) return false;
        for (std::size_t k = 0; k < columns_.size(); ++k)
            J.col(static_cast<Eigen::Index>(k)) = whole_J_.col(static_cast<Eigen::Index>(columns_[k]));
        return true;
    }
    bool stopped() const override { return whole_.stopped(); }
    long long simulations() const override { return whole_.simulations(); }

    /// The whole problem's parameters at the free ones x.
    std::vector<double> whole_point(const double* x) {
        at(x);
        return point_;
    }

private:
    const double* at(const double* x) {
        for (std::size_t k = 0; k < columns_.size(); ++k) point_[columns_[k]] = x[k];
        return point_.data();
    }

    LeastSquaresProblem& whole_;
    std::vector<double> point_;
    std::vector<std::size_t> columns_;
    Eigen::MatrixXd whole_J_;
};

}  // namespace tvid
