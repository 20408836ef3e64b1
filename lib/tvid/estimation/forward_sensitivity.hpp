#pragma once
// Forward sensitivities of an identification problem (the methodology paper eq. 9): the derivatives
// ∂y/∂p of every simulated output at every scored sample with respect to the free
// parameters, from the augmented system integrated alongside the state (SensitivitySystem)
// through the same templated element code. The start of a window depends on the
// parameters too, and that dependence is carried into the sensitivities:
//  - `equilibrium`: dθ̄/dp = −(∂F/∂θ)⁻¹ ∂F/∂p from the static torques F (implicit
//    function theorem);
//  - `measured` with a warm-up: the solved angle offset a and speed s of the warm-up
//    shooting satisfy G(a, s, p) = 0 (the encoder node meets the measured crank angle at
//    two samples), so d(a, s)/dp = −(∂G/∂(a, s))⁻¹ ∂G/∂p, with ∂G from two extra
//    directions integrated through the warm-up;
//  - `rest`, or a measured start without warm-up: the start does not depend on p;
//  - `estimated`: the seed plus the window's corrections, each of which moves its own
//    coordinate of the state by 1.
// The free parameters may be taken in column blocks [j0, j1) so that blocks run on
// different threads; a column's values do not depend on the blocking with fixed-step RK4.

#include <Eigen/Dense>
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/sim/simulate.hpp"
#include "tvid/util/cache_line.hpp"
#include "tvid/util/function_ref.hpp"

namespace tvid {

/// The model with PackedDual<D> numbers for the fixed-step RK4 path, built once.
template <int D>
struct PackedSensitivityModel {
    explicit PackedSensitivityModel(const IdentificationProblem& problem)
        : model(problem.definition().network), params(problem.definition().network.parameter_names.size()) {
        model.set_crank_angle_inputs(&problem.crank_angle_inputs());
    }
    NetworkModel<PackedDual<D>> model;
    std::vector<PackedDual<D>> params;
};

/// Per-thread scratch space of the sensitivity simulation, built once; on cache lines of its own.
struct alignas(kCacheLine) SensitivityWorkspace {
    explicit SensitivityWorkspace(const IdentificationProblem& problem);
    template <int D>
    PackedSensitivityModel<D>& packed() {
        if constexpr (D == 8) return packed8;
        else return packed16;
    }
    std::unique_ptr<ProblemWorkspace> plain;  ///< the plain simulation: initial state and warm-up shooting;
                                              ///< its stop flag ends the sensitivity simulations too
    NetworkModel<Dual> model;
    SimulationBuffers buffers;
    std::vector<Dual> params;                 ///< full model parameter vector, the block's columns seeded
    std::vector<Dual> x, dxdt, y;             ///< state, its rate, outputs
    std::vector<double> z;                    ///< augmented state [x, S]
    std::vector<double> row_mid, row_first;   ///< the encoder node's sensitivity row in the warm-up
    /// d(a, s)/dp of the last window's shot warm-up (angle offset a, speed s) for the block's
    /// columns: [2(j − j0)] for a, [2(j − j0) + 1] for s; empty when that window was not shot
    /// or its sensitivities were not carried as PackedDual.
    std::vector<double> start_slopes;
    PackedSensitivityModel<8> packed8;        ///< fixed-step RK4 with up to 8 directions
    PackedSensitivityModel<16> packed16;      ///< … up to 16
};

/// The warm-up shooting's dependence on the parameters, written once for every path that
/// carries sensitivities through a warm-up: the shooting solves G(a, s, p) = 0, G the encoder
/// node's angle at two samples (mid, first) less the measured ones, for the angle offset a
/// and speed s, so d(a, s)/dp = −(∂G/∂(a, s))⁻¹ ∂G/∂p.
class ShootingSensitivity {
public:
    /// From ∂G/∂(a, s): the node's angle derivatives in a and s at mid and at first.
    ShootingSensitivity(double mid_a, double mid_s, double first_a, double first_s)
        : g00_(mid_a), g01_(mid_s), g10_(first_a), g11_(first_s), det_(mid_a * first_s - mid_s * first_a) {}
    /// False when ∂G/∂(a, s) is singular: the shooting has no sensitivity.
    bool regular() const { return std::isfinite(det_) && det_ != 0.0; }
    /// da/dp_j and ds/dp_j from ∂G/∂p_j = (mid_j, first_j).
    double offset_slope(double mid_j, double first_j) const { return -(g11_ * mid_j - g01_ * first_j) / det_; }
    double speed_slope(double mid_j, double first_j) const { return -(-g10_ * mid_j + g00_ * first_j) / det_; }
    static constexpr const char* kSingular = "the warm-up shooting has no sensitivity (singular)";

private:
    double g00_, g01_, g10_, g11_, det_;
};

/// One window's outputs and their derivatives for `tvid sensitivity`.
struct WindowSensitivity {
    const Window* window = nullptr;
    SimulationStatus status = SimulationStatus::ok;
    std::string problem;
    std::vector<double> time;                           ///< scored samples
    std::vector<std::vector<double>> output;            ///< [output][k]
    std::vector<std::vector<std::vector<double>>> dydp; ///< [output][parameter][k]
};

class ForwardSensitivity {
public:
    /// Columns one block can carry: the dual capacity less the two shooting directions.
    static constexpr std::size_t kMaxBlock = static_cast<std::size_t>(kDualCapacity) - 2;

    explicit ForwardSensitivity(const IdentificationProblem& problem) : problem_(&problem) {}

    /// Whether fixed-step RK4 simulations carry their sensitivities as PackedDual (the
    /// default) or go through the augmented system like every other integrator (to compare).
    void set_packed(bool on) { packed_ = on; }

    std::unique_ptr<SensitivityWorkspace> make_workspace() const;

    /// Columns [j0, j1) of the Jacobian ∂r/∂p of the residuals (IdentificationProblem::
    /// residuals order) at free parameter values `free`, written into J. False when a
    /// simulation fails. `starts`: the windows' starts that IdentificationProblem::residuals
    /// solved at these same values (then the warm-up shooting is not solved again).
    /// With `start_slopes` (2 rows per estimation window, M columns), also d(a, s)/dp of each
    /// window's shot warm-up into rows 2w and 2w + 1 of the block's columns (0 where unknown).
    bool jacobian_columns(const double* free, std::size_t j0, std::size_t j1, SensitivityWorkspace& ws,
                          Eigen::MatrixXd& J, const std::vector<SolvedStart>* starts = nullptr,
                          Eigen::MatrixXd* start_slopes = nullptr) const;

    /// Window w's outputs and their derivatives for every free parameter. A delay's column
    /// is that of the residual: for an input's delay the outputs' central difference, for
    /// an output's delay −(the recording's slope at t + d) (channel_delay.hpp).
    WindowSensitivity window_sensitivity(const double* free, const Window& w, SensitivityWorkspace& ws) const;

private:
    // window_sensitivity's columns of the delay parameters (the duals leave them zero).
    void delay_sensitivities(const double* free, const Window& w, SensitivityWorkspace& ws, WindowSensitivity& out) const;
    // Sets the plain and dual parameters, the block's columns [j0, j1) seeded among d directions.
    void set_parameters(const double* free, std::size_t j0, std::size_t j1, int d, SensitivityWorkspace& ws) const;

    // Simulates window w with the sensitivities of the columns [j0, j1) and calls
    // on_scored(i, y) at every scored sample, y pointing at the outputs (dual numbers:
    // value() and derivative(j − j0)). Fixed-step RK4 over a small state takes the
    // PackedDual path, anything else the augmented system.
    template <class Observer>
    SimulationStatus simulate(const double* free, const Window& w, std::size_t j0, std::size_t j1,
                              SensitivityWorkspace& ws, std::string* problem, Observer&& on_scored,
                              const SolvedStart* solved = nullptr) const;
    // The state as N PackedDual<D> numbers through the fixed-step RK4 (instantiated for
    // every even N up to kMaxFixedState in forward_sensitivity_packed_d*.cpp).
    template <int D>
    using PackedObserver = FunctionRef<bool(std::size_t, const PackedDual<D>*)>;
    template <std::size_t N, int D>
    SimulationStatus simulate_packed(const double* free, const Window& w, std::size_t j0, std::size_t j1,
                                     SensitivityWorkspace& ws, std::string* problem, PackedObserver<D> on_scored,
                                     const SolvedStart* solved) const;
    // The augmented system [x, S] of plain doubles through any odeint stepper.
    SimulationStatus simulate_augmented(const double* free, const Window& w, std::size_t j0, std::size_t j1,
                                        SensitivityWorkspace& ws, std::string* problem,
                                        FunctionRef<bool(std::size_t, const Dual*)> on_scored,
                                        const SolvedStart* solved) const;
    // The window's start: `solved`, or solved now by IdentificationProblem::start_window.
    WindowStart window_start(const Window& w, SensitivityWorkspace& ws, std::string* problem,
                             const SolvedStart* solved) const;

    // The equilibrium start's sensitivity dθ̄/dp for columns [j0, j1) (nodes × columns),
    // with ws.model's parameters set for those columns.
    bool equilibrium_sensitivity(std::size_t j0, std::size_t j1, SensitivityWorkspace& ws, Eigen::MatrixXd& dtheta) const;
    // The same for the steady-motion start: the twists' sensitivity (the speeds are the
    // given ones; a gear ratio as a parameter moves them, which is left out).
    bool steady_sensitivity(std::size_t j0, std::size_t j1, SensitivityWorkspace& ws, Eigen::MatrixXd& dtheta) const;
    // dθ/dp of the start when it depends on the parameters (equilibrium, steady); true with
    // dtheta empty when it does not; false with `problem` set when it has none.
    // For an estimated start (ProblemDefinition::EstimatedStarts) of window w, dx/dp of
    // the whole state: 1 where a column is the correction of that coordinate, 0 elsewhere.
    bool start_sensitivity(const Window& w, std::size_t j0, std::size_t j1, SensitivityWorkspace& ws,
                           Eigen::MatrixXd& dtheta, std::string* problem) const;

    const IdentificationProblem* problem_;
    bool packed_ = true;
};

}  // namespace tvid
