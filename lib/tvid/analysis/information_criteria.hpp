#pragma once
// The information criteria of a least-squares fit, as the System Identification Toolbox
// reports them for nlgreyest (Ljung, System Identification, 2nd ed., sec. 16.4). With N the
// samples, n_y the outputs, n_p the free parameters and E the N × n_y prediction errors:
//   V    = det(EᵀE / N)                                   (the loss function)
//   FPE  = V (1 + n_p/N) / (1 − n_p/N)
//   AIC  = N log V + 2 n_p + N n_y (log 2π + 1)           (raw: −2 log L + 2 n_p for Gaussian errors)
//   AICc = AIC + 2 n_p (n_p + 1) / (N − n_p − 1)
//   nAIC = log V + 2 n_p / N
//   BIC  = N log V + N n_y (log 2π + 1) + n_p log N
// Lower is better; they compare models of one recording, never across recordings.

#include <Eigen/Core>
#include <cstddef>

namespace tvid {

struct InformationCriteria {
    bool available = false;  ///< false when N <= n_p + 1 or V is not positive
    std::size_t samples = 0;
    int outputs = 0;
    int parameters = 0;
    double loss = 0.0;       ///< V
    double fpe = 0.0, aic = 0.0, aicc = 0.0, naic = 0.0, bic = 0.0;
};

/// `errors`: N × n_y, one row per sample (rows with a non-finite entry are left out).
InformationCriteria information_criteria(const Eigen::MatrixXd& errors, int parameters);

}  // namespace tvid
