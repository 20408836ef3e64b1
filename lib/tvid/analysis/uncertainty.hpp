#pragma once
// Uncertainty of the estimate from the Jacobian J of the residuals at the optimum
// (the ResidualEvaluator's: forward sensitivities, delay columns, finite differences):
// covariance s²(JᵀJ)⁻¹ with s² = Σe²/(N − M), standard errors, 95 % intervals and
// correlations, computed in scaled parameters (p_j·∂r/∂p_j) so that inertias of 1e-3 and
// dampings of 1e1 are conditioned alike. Directions that the data
// do not determine (near-zero singular values of the scaled J) are reported, and the
// parameters in them get no standard error. The interval of a parameter of `scale: log` is
// formed in ln p (its scaled column p_j·∂r/∂p_j is ∂r/∂ln p_j) and mapped back: asymmetric in p.

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "tvid/analysis/input_noise.hpp"
#include "tvid/estimation/evaluator_options.hpp"
#include "tvid/estimation/identification_problem.hpp"

namespace tvid {

/// A parameter whose component in a null direction (a unit vector) exceeds this is
/// undetermined, and takes part in that direction's parameter combination.
constexpr double kNullDirectionComponent = 0.05;

struct ParameterUncertainty {
    bool available = false;           ///< false when the Jacobian could not be formed
    std::string problem;
    std::size_t residuals = 0;        ///< N
    int rank = 0;                     ///< numerical rank of the scaled JᵀJ
    double condition_number = 0.0;    ///< of the scaled JᵀJ (inf when rank deficient)
    std::vector<double> std_error;    ///< per free parameter; NaN when undetermined
    std::vector<double> ci_low, ci_high;
    std::vector<bool> determined;
    std::vector<std::vector<double>> correlation;  ///< NaN rows/cols for undetermined parameters
    /// Covariance of the free parameters (in their units); NaN rows/cols for undetermined ones.
    std::vector<std::vector<double>> covariance;
    /// Per free parameter: "two-sided"; "one-sided" when the parameter is on a bound (the
    /// interval runs from the bound inwards); "clipped" when it reached beyond a bound and
    /// was cut there (set by the fit's judgement, fit/fit_verdict.hpp).
    std::vector<std::string> interval;
    /// Unit vectors in relative parameter changes δp_j/|p_j| (absolute when p_j = 0), signed
    /// so that the first component of at least half the largest magnitude is positive.
    std::vector<std::vector<double>> null_directions;
    /// Σe² that one Gauss–Newton step from the point would remove, over the parameters
    /// inside their bounds (‖r‖² projected on their Jacobian columns, the linearised
    /// decrease): near 0 at a minimum of the least-squares cost. NaN when the optimizer's own
    /// Jacobian was taken (a least-squares fit, whose tolerances judged it) or when none was
    /// formed.
    double gauss_newton_decrease = std::numeric_limits<double>::quiet_NaN();
    double sum_of_squares = 0.0;  ///< Σe² at the point
    /// Per free parameter, the scale of its column in the scaled Jacobian: |p_j|, 1 at
    /// p_j = 0, an estimated start's coordinate scale for its correction. A null direction's
    /// component v_j is the change δp_j / column_scale[j].
    std::vector<double> column_scale;
    /// Per free parameter, a standard error that holds when the residuals are correlated in
    /// time or differ in variance between outputs (NaN when undetermined or not formed):
    /// the sandwich (JᵀJ)⁻¹ S (JᵀJ)⁻¹ with S the Newey–West estimate of the scores'
    /// long-run covariance, g_t = Σ_k J_tkᵀ r_tk per scored sample t (the outputs of one
    /// sample together), Bartlett weights over `robust_lags` lags within each window (Andrews'
    /// AR(1) plug-in bandwidth). For white residuals of one common variance it is the usual
    /// standard error, up to the estimates' noise. With a declared input noise (input_noise),
    /// at least std_error: the noise model's sandwich.
    std::vector<double> robust_std_error;
    std::size_t robust_lags = 0;
    /// Whether an input declares its noise (`noise:`). Then std_error, the intervals, the
    /// covariance and the correlations hold for a residual of white measurement noise per
    /// output plus the declared input noise carried through the model (analysis/input_noise.hpp):
    /// the sandwich (JᵀJ)⁻¹ Jᵀ Σ J (JᵀJ)⁻¹ with Σ = σ_m,k² I + the carried noise's covariance
    /// between samples and outputs (its lags up to twice its reach, tapered linearly over
    /// the second half), σ_m,k² = output k's residual variance less its carried noise (at
    /// least kWhiteShareFloor of it). Without: s²(JᵀJ)⁻¹, white residuals of one variance.
    bool input_noise = false;
    std::size_t input_noise_lags = 0;          ///< the carried noise's reach (its correlation_lags)
    std::vector<double> propagated_noise_rms;  ///< per measured output, in its unit (after its filter, if any)
};

/// The residuals' Jacobian at the optimum as the optimizer left it: ∂r/∂p over the free
/// parameters (N×M) from the ResidualEvaluator, and Σe² there. A least-squares fit has
/// just computed both; taking them saves a simulation and a sensitivity run.
struct JacobianAtOptimum {
    const Eigen::MatrixXd* jacobian = nullptr;  ///< none: computed here
    double sum_of_squares = 0.0;
    /// The declared input noise carried to the estimation windows at the point, in their
    /// order (input_noise_responses); none or empty: computed here when an input declares noise.
    const InputNoiseResponses* input_noise = nullptr;
};

/// The uncertainty at `free_best`. `known` (the Jacobian the least-squares fit took there
/// from the problem's ResidualEvaluator) is used when it has M columns and more than M
/// finite rows; otherwise a ResidualEvaluator computes the residuals and the Jacobian here,
/// with `evaluators` (a fit's: its threads and share of a batch's cores), with every column
/// kind the fit's own would have.
ParameterUncertainty estimate_uncertainty(const IdentificationProblem& problem, const std::vector<double>& free_best,
                                          const JacobianAtOptimum& known = {},
                                          const EvaluatorOptions& evaluators = EvaluatorOptions(1));

}  // namespace tvid
