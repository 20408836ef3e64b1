#pragma once
// What an identification problem needs of an experiment, and nothing else: the network,
// its measured channels (unit-scaled), the free parameters and their bounds, the
// estimation windows, how windows start and are simulated, and how they are scored.
// Built from an Experiment by problem_definition(); IdentificationProblem and the
// estimation code around it (batch costs, sensitivities, least squares) compute from it.

#include <cmath>
#include <limits>
#include <vector>

#include "tvid/channels/channel_delay.hpp"
#include "tvid/channels/crank_angle_channels.hpp"
#include "tvid/channels/input_channels.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/network_spec.hpp"
#include "tvid/sim/simulation_settings.hpp"

namespace tvid {

struct ProblemDefinition {
    NetworkSpec network;
    /// The rows of each recording (one for data.file): a window lies in one, and its channels
    /// are shifted, differentiated and held within it (channels/recording_spans.hpp).
    std::vector<RowSpan> recordings;
    InputChannels inputs;                        ///< the network's inputs by time
    /// Per input of `inputs` (a rate after the inputs: 0): its declared noise's standard
    /// deviation (ChannelBinding::noise), 0 when none.
    std::vector<double> input_noise;
    CrankAngleChannels angle_inputs;             ///< and by crank angle (cylinder pressures)
    std::vector<std::vector<double>> measured;   ///< the measured outputs [output][sample]
    std::vector<int> output_indices;             ///< the network output of each measured one
    std::vector<ParameterSetting> parameters;    ///< one per network parameter: fixed or free, bounds
    std::vector<Window> estimation;              ///< the windows scored
    InitialStateKind initial_state = InitialStateKind::equilibrium;
    int initial_speed_output = -1;               ///< measured start: the measured output of the speed
    SteadyStartSpec steady;                      ///< steady start: its node, speed and averaging
    /// initial_state estimated (experiment/estimated_start.hpp): the start of estimation
    /// window k is seed[k], the recipe's state at the parameters' init (IdentificationProblem
    /// solves it once), plus the parameters of of_window[k]; initial_state is the recipe.
    struct EstimatedStarts {
        bool on = false;
        bool validation = false;  ///< validation windows' starts estimated on their first samples
        std::vector<std::vector<NetworkSpec::StartCoordinate>> of_window;
        std::vector<std::vector<double>> seed;
        std::vector<std::size_t> states;  ///< the state coordinates estimated (the same in every window)
    };
    EstimatedStarts estimated;
    /// And its speed column per sample, when it reads one: read exactly as a channel bound
    /// to that column reads it (its unit, scale and delay), so the start agrees with the
    /// model's channel. The first input bound to the column (steady_speed_input, an index
    /// into `inputs`: a workspace reads it shifted by a delay parameter's current value),
    /// else the first output (steady_speed_output, an index into `measured`), else the
    /// column as recorded in steady_speed [rad/s].
    std::vector<double> steady_speed;
    int steady_speed_input = -1;
    int steady_speed_output = -1;
    std::vector<double> crank_angle;             ///< measured crank angle per sample [rad], or empty
    int angle_node = -1;                         ///< the node whose angle crank_angle measures
    SimulationSettings simulation;
    /// Per node: a simulated speed beyond it is not physical (kSpeedLimitFactor times the
    /// largest speed measured of a node it is tied to, through the gear ratios, in the
    /// node's own unit: rad/s, or m/s on a linear node); infinite for a node tied to no
    /// measured speed.
    std::vector<double> speed_limits;
    /// Whether some node has a finite speed limit.
    bool speed_limited() const {
        for (double l : speed_limits)
            if (std::isfinite(l)) return true;
        return false;
    }
    CostKind cost = CostKind::l1;
    /// Each measured output's residual is multiplied by output_scale[k] in the cost: its
    /// weight, divided by its spread when `normalized`.
    std::vector<double> output_scale;
    /// The measured spread in the estimation windows, of the channel as recorded (not
    /// shifted by its delay): it depends neither on a delay parameter's init nor on a
    /// candidate's delay, so equal parameters cost the same, and a delay parameter at d
    /// scores as `delay: d` does. The speed limit reads the channels the same way.
    std::vector<double> output_spread;
    bool normalized = false;
    /// Each measured output's detrend and high-pass within a window (residual_filter.hpp);
    /// `filtered` when any output has one.
    std::vector<ScoringFilter> output_filter;
    bool filtered = false;
    JacobianKind jacobian = JacobianKind::sensitivity;
    /// A channel whose delay is a parameter (channel_delay.hpp): `inputs` and `measured`
    /// hold it shifted by the parameter's init, and a workspace shifts `recorded` again at
    /// each candidate's value (IdentificationProblem::apply_channel_delays).
    struct DelayedChannel {
        std::size_t channel = 0;        ///< its index in inputs (a rate follows its input) or in measured
        int parameter = -1;             ///< the delay's index in the model parameter vector
        std::vector<double> recorded;   ///< unit-scaled, not shifted
        std::vector<double> slope;      ///< its slopes at the samples (channel_delay.hpp)
        SampledSignal signal(const std::vector<double>& time) const { return {recorded, slope, time}; }
        /// Its recording `r` alone: what a window of that recording reads.
        SampledSignal signal(const std::vector<double>& time, RowSpan r) const { return signal_within(signal(time), r); }
    };
    std::vector<DelayedChannel> delayed_inputs, delayed_outputs;
    /// Per measured output: its delay parameter, or -1 (a number or none).
    std::vector<int> output_delay;
};

/// How far beyond the largest measured speed a simulated speed may go.
inline constexpr double kSpeedLimitFactor = 100.0;

/// The definition of `experiment`'s identification problem.
ProblemDefinition problem_definition(const Experiment& experiment);

}  // namespace tvid
