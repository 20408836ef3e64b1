#pragma once
// The torsional modes of a network linearised about a window's start: the eigenvalues λ
// of A (Eigen's real EigenSolver), one mode per complex pair, each with its undamped natural
// frequency |λ|/2π, its damped frequency Im λ/2π, its damping ratio ζ = −Re λ/|λ| and its
// shape (the node-angle components of its eigenvector), also referred to a common shaft
// through the gear ratios. An overdamped degree of freedom (two real roots of one shape) is
// one mode with ζ = −(λ1 + λ2)/(2√(λ1λ2)) > 1 and f_n = √(λ1λ2)/2π; a lone real root (a
// first-order motion) has its corner frequency |λ|/2π and no ζ.

#include <complex>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "tvid/analysis/linear_network.hpp"
#include "tvid/estimation/identification_problem.hpp"

namespace tvid {

enum class ModeKind {
    rigid_body,   ///< the line turning as one body: λ ≈ 0 (free angle) or its speed's decay under friction
    overdamped,   ///< real eigenvalues of a twisting motion: a pair of one shape (ζ > 1), or a lone first-order root
    oscillating,  ///< a complex pair
};

const char* mode_kind_name(ModeKind kind);

struct TorsionalMode {
    ModeKind kind = ModeKind::oscillating;
    std::complex<double> eigenvalue;  ///< [1/s]; of a pair, the one with Im λ > 0; of two real roots, the slower
    /// The faster of an overdamped mode's two real roots [1/s]; NaN for every other mode.
    double second_eigenvalue = std::numeric_limits<double>::quiet_NaN();
    double frequency_hz = 0.0;        ///< |λ|/2π; √(λ1λ2)/2π of two real roots
    double damped_frequency_hz = 0.0; ///< Im λ/2π (0 for a real eigenvalue)
    /// −Re λ/|λ| (NaN for λ = 0; negative: growing); −(λ1 + λ2)/(2√(λ1λ2)) > 1 of two real
    /// roots; NaN for a lone real root (a first-order motion has no ζ).
    double damping_ratio = 0.0;
    /// Node angles of the eigenvector divided by its largest one (that node: 1, phase 0).
    std::vector<std::complex<double>> shape;
    /// The same with each node's angle referred to the reference node's shaft (θ_i / ratio_i),
    /// so that a rigid rotation reads 1 on every node of a geared line.
    std::vector<std::complex<double>> shape_common;
    std::size_t dominant_node = 0;    ///< the largest entry of shape_common
};

struct ModalAnalysis {
    std::vector<std::string> node_names;
    std::vector<double> ratio;        ///< each node's speed per unit speed of the reference node
    std::size_t reference_node = 0;
    bool free_rotation = false;       ///< the line can turn as one body (no stiffness to ground)
    std::vector<TorsionalMode> modes; ///< rigid-body modes first, then by frequency
};

/// The modes of `system`; `ratio[i]`: node i's speed per unit speed of node `reference`
/// (model/steady_motion.hpp's rigid_motion; 1 for a node no element ties to it).
ModalAnalysis torsional_modes(const LinearNetwork& system, const std::vector<double>& ratio, std::size_t reference);

/// The rigid-motion ratios of `spec`'s nodes to node `reference` (1 where untied).
std::vector<double> node_ratios(const NetworkSpec& spec, const std::vector<double>& params, std::size_t reference);

/// Where the linearisation is taken: window `window`'s start state, as the identification
/// problem prepares it (estimation/window_start.hpp), and its inputs there.
struct OperatingPoint {
    std::size_t window = 0;   ///< index among the estimation windows
    std::string label;        ///< the window's label
    std::string recording;    ///< the window's recording (data.recordings), or empty
    std::string initial_state;///< rest, equilibrium, measured or steady
    std::size_t sample = 0;   ///< the window's start sample, a row of its recording
    double time = 0.0;        ///< its time [s] on its recording's clock
    std::vector<double> x, u;
};

/// Operating point of estimation window `window` at model parameters `params`; throws
/// std::runtime_error when the start cannot be prepared (the reason in the message).
/// With `given` (its start as a simulation at the same parameters solved it), from that.
OperatingPoint window_operating_point(const IdentificationProblem& problem, const std::vector<double>& params,
                                      std::size_t window, const SolvedStart* given = nullptr);

/// Linearisation and modes at one operating point.
struct ModesStudy {
    OperatingPoint operating_point;
    LinearNetwork linear;
    ModalAnalysis modal;
};

/// The operating point of estimation window `window`, the linearisation there and its modes.
ModesStudy study_modes(const IdentificationProblem& problem, const std::vector<double>& params, std::size_t window,
                       AngleDependence angle_dependence, const SolvedStart* given = nullptr);

}  // namespace tvid
