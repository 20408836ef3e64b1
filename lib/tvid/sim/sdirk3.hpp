#pragma once
// A fixed-step implicit method for stiff models at the recording's own step: Alexander's
// (1977) three-stage SDIRK of order 3, L-stable and stiffly accurate (the last stage is the
// step's result). Each stage Z_i = x + h Σ_j<i a_ij K_j + hγ K_i, K_i = f(Z_i, u(t + c_i h)),
// is solved by simplified Newton iterations on the model's exact state Jacobian
// (StateJacobian, dual numbers), refreshed when they converge slowly, with a backtracking
// guard. A stiff mode (a sticking dry friction, a stiff
// spring on a small inertia) then decays within a step as it physically does instead of
// limiting the step, which stays the sample interval (split only by simulation.step).
//
// Sensitivities are those of the discrete method itself, as RK4's are through its stages:
// with S = ∂x/∂q, differentiating stage i gives
//   (I − hγ J(Z_i)) dK_i = J(Z_i) E_i + ∂f/∂q,   E_i = S + h Σ_j<i a_ij dK_j,
// whose right side is one dual-number pass of f at Z_i carrying E_i as its derivatives, and
// then S' = E_3 + hγ dK_3. A step whose Newton iterations do not converge is split in halves
// (at most kMaxHalvings times) before the simulation gives up.

#include <Eigen/Core>
#include <Eigen/LU>
#include <cstddef>
#include <vector>

#include "tvid/channels/input_channels.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/state_jacobian.hpp"
#include "tvid/sim/simulation_status.hpp"

namespace tvid {

/// Alexander's L-stable SDIRK3 (Hairer & Wanner, Solving ODEs II, table IV.6.5): γ is the
/// root of x³ − 3x² + 3x/2 − 1/6 in (1/3, 1/2); the last row of A is b.
struct Sdirk3Tableau {
    static constexpr double gamma = 0.43586652150845899941601945;
    static constexpr double b1 = -(6 * gamma * gamma - 16 * gamma + 1) / 4;
    static constexpr double b2 = (6 * gamma * gamma - 20 * gamma + 5) / 4;
    static constexpr double a[3][3] = {{gamma, 0, 0}, {(1 - gamma) / 2, gamma, 0}, {b1, b2, gamma}};
    static constexpr double c[3] = {gamma, (1 + gamma) / 2, 1.0};
};

class Sdirk3 {
public:
    static constexpr int kMaxNewtonIterations = 30;
    /// The shortest fraction of a Newton update the backtracking tries.
    static constexpr double kSmallestFraction = 1.0 / 256;
    static constexpr int kMaxHalvings = 6;
    /// A stage counts as solved when every Newton update is below this share of its state's
    /// scale (the larger of the state and the largest it has been in this simulation).
    static constexpr double kNewtonTolerance = 1e-10;
    /// Newton's Jacobian is evaluated afresh when an update is more than this share of the
    /// last one: a stale J (friction that stuck when it was taken, slips now) converges
    /// linearly at best. (The driveline's LM from ±50 %: 2.7 s at 0.3, 3.2 s at 0.5.)
    static constexpr double kRefreshRate = 0.3;

    /// Follows `model` (its parameters as set) over `inputs`; sensitivities off.
    void bind(NetworkModel<double>& model, const InputChannels& inputs);

    /// Sensitivities along `directions` parameter directions: `dual` is the model with its
    /// parameters seeded along them, `x`, `f` scratch of the state size.
    void bind_sensitivities(NetworkModel<Dual>& dual, int directions, std::vector<Dual>& x, std::vector<Dual>& f);

    /// The scale of each state at the simulation's start (the Newton tolerance's floor).
    void begin(const double* x);

    /// The sampled elements (NetworkModel::samples) restarted at the simulation's start and
    /// sampled at each later sample, in the model (its outputs) and in the Jacobian's (f).
    void restart_sampling(const double* x, const double* u) {
        model_->restart_sampling(x, u);
        jacobian_.restart_sampling(x, u);
    }
    void sample(double t, const double* x, const double* u) {
        model_->sample(t, x, u);
        jacobian_.sample(t, x, u);
    }

    /// Crosses sample interval i of `time` in steps of at most max_step (0: one step): x the
    /// state, s its sensitivities (n × directions, row-major; null without sensitivities).
    SimulationStatus cross(const std::vector<double>& time, std::size_t i, double max_step, double* x, double* s);

    std::size_t rhs_evaluations = 0;       ///< f (Newton iterations), running total
    std::size_t jacobian_evaluations = 0;  ///< ∂f/∂x, running total
    std::size_t steps = 0;              ///< steps taken, running total
    std::size_t halvings = 0;           ///< steps split because Newton did not converge

private:
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    SimulationStatus advance(double t, double h, double* x, double* s, int depth);

    // One step of h from t; x (and s) change only when every stage is solved.
    bool step(double t, double h, double* x, double* s);

    // Simplified Newton on F(Z) = Z − base − hγ f(Z, u(t)) = 0 from Z = base + hγ·guess (or
    // base): f in doubles at every iterate, the Jacobian kept from stage to stage and step to
    // step (γ is the same in all three stages, h in all steps: so is the LU of I − hγ J) and
    // evaluated afresh at the current iterate when the updates stop shrinking fast (by
    // kRefreshRate) or the residual grows (then also stepping back along the last update).
    // Leaves Z in z_.
    bool solve_stage(double t, double hg, const Eigen::VectorXd* guess);

    // J = ∂f/∂x at z and the current stage's inputs into `j` (row-major).
    bool evaluate_jacobian(const Eigen::VectorXd& z, std::vector<double>& j);

    // The LU of I − hγ J into `lu`.
    void factor(const std::vector<double>& j, double hg, Eigen::PartialPivLU<Eigen::MatrixXd>& lu);

    // dK_i from the stage's Jacobian; on the last stage S' = E_3 + hγ dK_3.
    bool stage_sensitivity(int i, double h, const double* s);

    NetworkModel<double>* model_ = nullptr;
    const InputChannels* inputs_ = nullptr;
    StateJacobian jacobian_;
    std::size_t n_ = 0, d_ = 0, hint_ = 0;
    Eigen::VectorXd base_, z_, f_, r_, delta_, z_before_, scale_;
    Eigen::VectorXd k_[3];
    std::vector<double> j_, j_stage_, u_;  ///< Newton's Jacobian (kept over steps), the stage's
    Eigen::MatrixXd m_;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu_, stage_lu_;  ///< Newton's, the sensitivities'
    double factored_hg_ = 0.0;                           ///< the hγ of lu_ (0: none)
    bool guess_known_ = false, stale_ = true;
    SimulationStatus failure_ = SimulationStatus::ok;
    // Sensitivities.
    NetworkModel<Dual>* dual_ = nullptr;
    std::vector<Dual>*xd_ = nullptr, *fd_ = nullptr;
    Eigen::MatrixXd e_, g_, s_next_;
    Eigen::MatrixXd dk_[3];
};

}  // namespace tvid
