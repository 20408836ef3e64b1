#pragma once
// What a fit of a record would determine, predicted before it is measured: the Fisher
// information F = Σ_outputs Σ_samples (∂y/∂θ)(∂y/∂θ)ᵀ / σ² of the free parameters θ, from
// the exact forward sensitivities of the simulated outputs at nominal parameter values
// and each output's white-noise standard deviation σ, and its inverse, the covariance a
// least-squares fit would reach (the Cramér–Rao bound). Local: linearised at the nominal
// values.

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "tvid/design/design_spec.hpp"
#include "tvid/experiment/experiment.hpp"

namespace tvid {

struct PredictedUncertainty {
    bool simulated = false;
    std::string problem;                  ///< why the simulation failed, when it did
    std::vector<std::string> names;       ///< the free parameters
    std::vector<double> nominal;          ///< their nominal values
    Eigen::MatrixXd fisher;               ///< F over the free parameters, in their units
    Eigen::MatrixXd covariance;           ///< F⁻¹ (NaN rows and columns for parameters not determined)
    Eigen::MatrixXd correlation;
    std::vector<double> standard_error;   ///< sqrt of F⁻¹'s diagonal; NaN when not determined
    /// standard_error / |nominal|; for a nominal value of 0, the standard error itself.
    std::vector<double> relative_se;
    /// False for a parameter in a direction that F does not see (its eigenvalue below 1e-12
    /// of the largest, with the parameters scaled by their nominal values).
    std::vector<bool> determined;
    /// The criteria, each a relative standard error (lower is better): the geometric mean
    /// of the scaled covariance's principal standard deviations (D-optimal), the RMS of the
    /// relative standard errors (A-optimal), their largest. Infinite when a parameter is
    /// not determined.
    double d_optimal = 0.0, a_optimal = 0.0, worst_relative_se = 0.0;

    double criterion(DesignCriterion c) const;
};

/// The prediction for the experiment made by design_experiment, at the full parameter
/// vector `params` (the experiment's order), with each output's noise `noise` (SI, per
/// Experiment::outputs).
PredictedUncertainty predict_uncertainty(const Experiment& design, const std::vector<double>& params,
                                         const std::vector<double>& noise);

/// The prediction from the Fisher information itself (F, the nominal values): what
/// predict_uncertainty does after the sensitivities.
void fill_uncertainty(PredictedUncertainty& u);

}  // namespace tvid
