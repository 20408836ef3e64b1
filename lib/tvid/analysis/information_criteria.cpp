#include "tvid/analysis/information_criteria.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

namespace tvid {

InformationCriteria information_criteria(const Eigen::MatrixXd& errors, int parameters) {
    InformationCriteria c;
    c.outputs = static_cast<int>(errors.cols());
    c.parameters = parameters;
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(errors.cols(), errors.cols());
    std::size_t n = 0;
    for (Eigen::Index i = 0; i < errors.rows(); ++i) {
        if (!errors.row(i).allFinite()) continue;
        gram.noalias() += errors.row(i).transpose() * errors.row(i);
        ++n;
    }
    c.samples = n;
    const double dn = static_cast<double>(n), np = parameters;
    if (c.outputs == 0 || dn <= np + 1.0) return c;
    c.loss = (gram / dn).determinant();
    if (!(c.loss > 0.0) || !std::isfinite(c.loss)) return c;
    c.available = true;
    const double log_v = std::log(c.loss);
    const double gaussian = dn * c.outputs * (std::log(2.0 * std::numbers::pi) + 1.0);
    c.fpe = c.loss * (1.0 + np / dn) / (1.0 - np / dn);
    c.aic = dn * log_v + 2.0 * np + gaussian;
    c.aicc = c.aic + 2.0 * np * (np + 1.0) / (dn - np - 1.0);
    c.naic = log_v + 2.0 * np / dn;
    c.bic = dn * log_v + gaussian + np * std::log(dn);
    return c;
}

}  // namespace tvid
