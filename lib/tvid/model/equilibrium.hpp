#pragma once
// Static equilibrium of a network: node angles θ̄ with zero net torque on every node at
// rest (ω = 0) under the inputs u. Yoshida & Takamatsu eq. 18: the simulation starts from the
// equilibrium for the input at the window's first sample.

#include <string>
#include <vector>

#include "tvid/model/network_model.hpp"

namespace tvid {

struct EquilibriumResult {
    bool found = false;
    std::vector<double> theta;
    std::string problem;  ///< why no equilibrium was found
};

/// The nodes flagged in `members` (one flag per node), as the subject of a sentence:
/// "node b has", "nodes b and c have" (at most 4 named). For the hidden reference node of a
/// speed_controller whose ki is 0 (`p`: the parameter vector) it adds why: a P-only
/// controller holds no twist.
std::string nodes_without_hold(const NetworkSpec& spec, const std::vector<double>& p, const std::vector<char>& members);

/// One node: bracketing plus TOMS 748 on the (monotone) static torque; several nodes:
/// damped Newton with a finite-difference Jacobian. Never throws for bad parameters;
/// `found` is false instead.
EquilibriumResult solve_equilibrium(NetworkModel<double>& model, const double* u);

}  // namespace tvid
