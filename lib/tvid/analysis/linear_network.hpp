#pragma once
// The network's equations linearised about an operating point (x̄, ū):
//   δẋ = A δx + B δu,   δy = C δx + D δu,
// A = ∂f/∂x and C = ∂y/∂x by dual numbers (the element code itself, as
// model/state_jacobian.hpp), B = ∂f/∂u and D = ∂y/∂u by central differences, exact to
// rounding for the inputs' linear paths (an applied torque, a prescribed speed into a
// spring-damper). A node whose speed a speed source prescribes keeps its angle state
// (driven by the input) but loses its speed state, which no equation reads.

#include <complex>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "tvid/channels/crank_angle_channels.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/network_spec.hpp"

namespace tvid {

const char* angle_dependence_name(AngleDependence a);

struct LinearNetwork {
    Eigen::MatrixXd A, B, C, D;
    std::vector<std::size_t> states;        ///< the full-state index (θ_i = i, ω_i = n + i) of each state kept
    std::vector<std::string> state_names;   ///< "theta:NODE", "omega:NODE"
    std::vector<std::string> input_names;   ///< B's and D's columns: the network's inputs, then their slopes
    std::vector<int> rate_of;               ///< per input: the column of its time derivative, or -1
    std::vector<std::string> output_names;  ///< C's and D's rows: every output of the network
    std::vector<std::string> node_names;
    std::vector<char> prescribed;           ///< per node: a speed source prescribes its speed
    std::vector<double> x, u;               ///< the operating point (full state, every input)
    AngleDependence angle_dependence = AngleDependence::revolution_mean;
    std::vector<ElementLinearisation> elements;

    /// Per node: the node whose angle state moves it (its ideal-gear group's root, or itself)
    /// and θ_node / θ_that (1 for an untied node).
    std::vector<std::size_t> angle_root;
    std::vector<double> angle_factor;

    std::size_t node_count() const { return node_names.size(); }
    /// The row/column of the angle state that moves node i (angle_factor[i] times it).
    std::size_t angle_state(std::size_t node) const;
};

/// Linearises `spec` with model parameters `params` about the state x and inputs u (every
/// input the model reads: the network's inputs, then the slopes of NetworkSpec::input_rates).
/// `angle_inputs`: the cylinders' pressure channels (may be null without cylinders).
LinearNetwork linearise_network(const NetworkSpec& spec, const std::vector<double>& params,
                                const CrankAngleChannels* angle_inputs, const std::vector<double>& x,
                                const std::vector<double>& u, AngleDependence angle_dependence);

/// H(jω) = C (jωI − A)⁻¹ b + d at each frequency [Hz], for input column `input` (its
/// slope's column, when it has one, enters as jω times the input) and output row `output`.
std::vector<std::complex<double>> frequency_response(const LinearNetwork& system, std::size_t input,
                                                     std::size_t output, const std::vector<double>& frequency_hz);

}  // namespace tvid
