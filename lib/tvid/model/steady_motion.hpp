#pragma once
// A line in steady rotation: every node turning at the speed the gear ratios give it
// from one reference node, twisted so that its elements carry the (mean) torques. The
// rigid-body rotation stays free (nothing holds the line to ground): the whole line may
// accelerate as one body, at the rate the net torque gives it.

#include <string>
#include <vector>

#include "tvid/model/network_model.hpp"

namespace tvid {

/// How the nodes turn together: ω_i = ratio[i] · ω_reference along the elements that join
/// two nodes (a shaft: the same speed; a gear mesh of ratio n from a to b: ω_b = ω_a / n).
struct RigidMotion {
    std::vector<double> ratio;  ///< per node; 0 where `tied` is false
    std::vector<char> tied;     ///< whether a chain of elements joins the node to the reference
    std::string problem;        ///< not empty: the ratios around a loop disagree
};

/// The first element that holds a node to ground ("'mount' (node motor to ground)"), or to
/// an angle (a position controller), or "": a line so held cannot turn steadily, and at
/// rest its start is the equilibrium.
std::string held_to_ground(const NetworkSpec& spec);

/// The ratios of `spec`'s nodes for the parameter vector p (gear ratios may be parameters).
RigidMotion rigid_motion(const NetworkSpec& spec, const std::vector<double>& p, int reference);

/// The largest speed each node turns at, when node m is known to turn at up to largest[m]
/// (0: not known): carried to every node tied to m through the gear ratios between them (a
/// ball screw's 1250 rad/m turns a linear speed in m/s into the motor's in rad/s), the
/// largest where several reach a node; 0 for a node tied to no known speed.
std::vector<double> speeds_through_rigid_ties(const NetworkSpec& spec, const std::vector<double>& p,
                                              const std::vector<double>& largest);

struct SteadyMotion {
    bool found = false;
    std::vector<double> x;       ///< the state [θ, ω]
    double acceleration = 0.0;   ///< the reference node's acceleration (the rigid body's, scaled)
    std::vector<double> ratio;   ///< rigid_motion's ratios
    std::string problem;         ///< why no steady motion was found
};

/// The steady motion of `model` (parameters set) under the inputs u: node `reference` at
/// angle `angle` turning at `speed`, every node at its ratio of both, with the twists at
/// which every node accelerates as the rigid body does: J_i θ_i'' = ratio_i · α for one α.
/// Damped Newton on the twists and α, the Jacobian by differences (damped_newton.hpp).
/// A line held to ground (line_held_to_ground) has no steady motion: not found, saying so.
/// Never throws.
SteadyMotion solve_steady_motion(NetworkModel<double>& model, const double* u, int reference, double speed,
                                 double angle);

}  // namespace tvid
