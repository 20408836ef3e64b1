#pragma once
// What an identification problem needs of an experiment, and nothing else: the network,
// its measured channels (unit-scaled), the free parameters and their bounds, the
// estimation windows, how windows start and are simulated, and how they are scored.
// Built from an Experiment by problem_definition(); IdentificationProblem and the
// estimation code around it (batch costs, sensitivities, least squares) compute from it.

#include <vector>

#include "tvid/channels/crank_angle_channels.hpp"
#include "tvid/channels/input_channels.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/network_spec.hpp"
#include "tvid/sim/simulation_settings.hpp"

namespace tvid {

struct ProblemDefinition {
    NetworkSpec network;
    InputChannels inputs;                        ///< the network's inputs by time
    CrankAngleChannels angle_inputs;             ///< and by crank angle (cylinder pressures)
    std::vector<std::vector<double>> measured;   ///< the measured outputs [output][sample]
    std::vector<int> output_indices;             ///< the network output of each measured one
    std::vector<ParameterSetting> parameters;    ///< one per network parameter: fixed or free, bounds
    std::vector<Window> estimation;              ///< the windows scored
    InitialStateKind initial_state = InitialStateKind::equilibrium;
    int initial_speed_output = -1;               ///< measured start: the measured output of the speed
    SteadyStartSpec steady;                      ///< steady start: its node, speed and averaging
    std::vector<double> steady_speed;            ///< and its speed column per sample, when it reads one
    std::vector<double> crank_angle;             ///< measured crank angle per sample [rad], or empty
    int angle_node = -1;                         ///< the node whose angle crank_angle measures
    SimulationSettings simulation;
    CostKind cost = CostKind::l1;
    JacobianKind jacobian = JacobianKind::sensitivity;
};

/// The definition of `experiment`'s identification problem.
ProblemDefinition problem_definition(const Experiment& experiment);

}  // namespace tvid
