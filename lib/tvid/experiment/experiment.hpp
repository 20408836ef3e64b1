#pragma once
// An identification experiment (docs/experiment-format.md), loaded
// and validated: the model network, which parameters are free and their bounds, the
// measured channels, the windows, and the simulation, estimation and report settings.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "tvid/channels/recording_spans.hpp"
#include "tvid/experiment/initial_state_kinds.hpp"
#include "tvid/experiment/optimizer_kinds.hpp"
#include "tvid/io/csv_table.hpp"
#include "tvid/model/network_spec.hpp"
#include "tvid/model/presets.hpp"
#include "tvid/optim/parameter_scale.hpp"
#include "tvid/sim/simulation_settings.hpp"

namespace tvid {

/// Where a setting came from, for error messages that name file, line and key.
struct SourceLocation {
    std::string file;  ///< the experiment file as given, or "--set" for a command-line override
    int line = 0;      ///< 1-based
    std::string key;   ///< dotted key path, e.g. "parameters.rho1.min"
};

struct ParameterSetting {
    std::string name;
    double init = 0.0;                 ///< start value (the value for fixed parameters)
    bool fixed = false;
    double min = -1e300, max = 1e300;  ///< bounds; ±1e300 when not given
    bool has_min = false, has_max = false;
    std::optional<std::pair<double, double>> range;  ///< initial search domain (PSO grid, multistart)
    /// `scale: log | linear`: whether the optimizers search the parameter or its logarithm
    /// (optim/parameter_scaling.hpp); log needs a positive min.
    ParameterScale scale = ParameterScale::linear;
    /// `expr:` a formula of other parameters (held; init is its value at theirs), or empty.
    std::string expr;
    SourceLocation where;
};

/// The box a parameter's search starts in: its range, or its bounds where no range is
/// given (nothing when a bound is missing).
std::optional<std::pair<double, double>> search_interval(const ParameterSetting& p);

/// True when `p` is free, searched linearly, and its search box is positive and spans more
/// than `decades` decades (upper / lower > 10^decades): sampled linearly, almost all of its
/// starts or particles land in the top decade, and `scale: log` would spread them evenly.
bool spans_decades(const ParameterSetting& p, double decades);

/// A channel of the CSV file bound to a model input or output.
/// An output's scoring within each window (estimation/residual_filter.hpp): `detrend:
/// mean | linear` removes the residuals' mean or linear trend, `highpass: HZ` filters
/// them. Neither by default.
enum class Detrend { none, mean, linear };
struct ScoringFilter {
    Detrend detrend = Detrend::none;
    double highpass = 0.0;  ///< [Hz], 0: none
    bool active() const { return detrend != Detrend::none || highpass > 0; }
};

struct ChannelBinding {
    std::string model_name;  ///< e.g. "Ttm"
    std::string column;      ///< CSV column
    double scale = 1.0;      ///< unit conversion applied when reading (e.g. bar -> Pa)
    /// [s] how late the channel was recorded: at model time t it reads t + delay
    /// (channels/channel_delay.hpp). A number, or a parameter (NetworkSpec::delay_parameters).
    Field delay;
    double weight = 1.0;     ///< an output's weight in the cost (its residuals are multiplied by it)
    ScoringFilter scoring;   ///< an output's detrend and high-pass in the cost
    bool by_angle = false;   ///< a crank-angle channel (cylinder pressure), read against data.angle
    /// Inputs only: the standard deviation of the white noise the channel was logged with, in
    /// SI (`noise:` times the unit's factor); 0 when none is declared. The fit propagates it
    /// to the outputs (analysis/input_noise.hpp).
    double noise = 0.0;
    SourceLocation where;
};

/// A window of the recording, resolved to 0-based sample indices. The simulation starts
/// at sample `start` (= `first`, or earlier by the warm-up) from the initial state; the
/// scored samples are those i with first <= i <= last and i > start (the start sample is
/// the initial condition, not a prediction: Yoshida & Takamatsu eq. 19 sums i = 1..m).
struct Window {
    std::string label;       ///< e.g. "time 1.5 to 3", "run2: time 0 to 4" (no comma: it is a CSV cell)
    std::size_t start = 0;
    std::size_t first = 0;
    std::size_t last = 0;
    SourceLocation where;
    std::size_t recording = 0;  ///< its recording, an index into Experiment::recordings
};

/// One recording of the experiment: data.file, or an entry of data.recordings. Several
/// are laid end to end in Experiment::data (experiment/recording_join.hpp), each in its
/// rows: a later one's clock is moved where needed so that time keeps rising, and its
/// crank angle by whole cycles likewise. Every window lies within one recording.
struct ExperimentRecording {
    std::string name;             ///< data.recordings[k].name; empty for data.file
    std::filesystem::path file;   ///< resolved against the experiment's folder
    std::string sha256;           ///< SHA-256 of the file's bytes as read
    RowSpan rows;                 ///< its samples in Experiment::data
    double time_offset = 0.0;     ///< [s] added to its time stamps in Experiment::data
    double angle_offset = 0.0;    ///< [deg] whole cycles added to its crank angle in crank_angle
    SourceLocation where;         ///< its entry (data.file or data.recordings[k])
};

/// `initial_state: { kind: steady, … }`: the line in steady rotation (steady_motion.hpp)
/// at one node's speed, twisted to carry the mean inputs.
struct SteadyStartSpec {
    int node = -1;               ///< the node whose speed is given
    double speed = 0.0;          ///< [rad/s], when speed_column is empty
    std::string speed_column;    ///< or the mean of this column of the recording [rad/s]
    std::size_t samples = 0;     ///< samples averaged from the window's start (0: its warm-up, or 50)
};
/// `initial_state: { kind: estimated, from: RECIPE, validation: from | estimated }`: the start
/// of each estimation window is identified with the model. The `from:` recipe
/// (initial_state) gives every window's seed at the parameters' init; the start is the
/// seed plus one parameter per independent coordinate (NetworkSpec::start_coordinates):
/// every node's speed, and every node's angle but one per rigid rotation the outputs and
/// the elements cannot see (a line not tied to ground).
struct EstimatedStartSpec {
    bool on = false;
    /// `validation: estimated`: a validation window's start is estimated from its first
    /// samples with the model held (its warm-up, or its first tenth), as nlgreyest's
    /// compare does; otherwise validation windows start from the recipe.
    bool validation = false;
    SourceLocation where;  ///< the initial_state entry
};

enum class CostKind { l1, l2 };
/// How the Jacobian of the residuals is formed (LM steps, standard errors): forward
/// sensitivities (the methodology paper eq. 9) or central finite differences.
enum class JacobianKind { sensitivity, fd };


/// How the outputs' residuals are made comparable in the cost: `spread` divides each by
/// its measured spread (standard deviation) in the estimation windows; `none` keeps raw
/// units; `automatic` is `spread` for several outputs and `none` for one (where it would
/// only scale the cost).
enum class OutputNormalization { automatic, spread, none };

struct EstimationSettings {
    CostKind cost = CostKind::l1;
    OutputNormalization normalize = OutputNormalization::automatic;  ///< `normalize: spread | none`
    OptimizerKind optimizer = OptimizerKind::pso;
    bool optimizer_given = false;  ///< the experiment (or --optimizer, --set) names it; else the swarm is the default
    /// Each optimizer kind's own settings section (`pso:`, `lm:`, `nlopt:`, `multistart:`; a
    /// field each, experiment/optimizer_kinds/table.hpp).
#define TVID_OPTIMIZER_SETTINGS_FIELD(section, Kind) Kind::Settings section;
    TVID_OPTIMIZER_SECTIONS(TVID_OPTIMIZER_SETTINGS_FIELD)
#undef TVID_OPTIMIZER_SETTINGS_FIELD
    JacobianKind jacobian = JacobianKind::sensitivity;  ///< `lm: { jacobian: sensitivity | fd }`
    /// `strict: true`: a verdict with an error (fit/fit_verdict.hpp) makes `tvid fit` exit 1,
    /// as `--strict` does.
    bool strict = false;
};

/// Where a dry friction's or a road load's smoothed sign turns (its smoothing_speed), and
/// why: given in the experiment, or chosen from the data (experiment/smoothing_speeds.hpp).
struct SmoothingChoice {
    std::string element;         ///< the element's name
    std::string kind;            ///< "friction" or "road_load"
    double speed = 0.0;          ///< the smoothing speed [rad/s or m/s] (a parameter's start value)
    std::string unit;            ///< "rad/s" or "m/s"
    bool given = false;          ///< the experiment gave it
    std::string basis;           ///< how it was chosen, for the report ("1 % of 0.2 m/s, ...")
    double largest_speed = 0.0;  ///< the largest measured speed across the element [rad/s or m/s]; 0 when none
    /// Of the samples in motion (a measured speed across the element above 3 times its
    /// channel's noise), the share within kSmoothingShareSpeeds smoothing speeds of zero,
    /// where the smoothed sign is a viscous term; negative when no channel measures that
    /// speed, or it never moves.
    double share_within = -1.0;
};

struct Experiment {
    std::filesystem::path file;          ///< the experiment file
    std::string config_sha256;           ///< SHA-256 of the experiment file's bytes as read (before --set)
    std::string name;
    std::filesystem::path data_file;     ///< resolved against the experiment's folder (the first recording's)
    CsvTable data;                       ///< the whole recording, or the recordings end to end
    std::vector<ExperimentRecording> recordings;  ///< at least one; several with data.recordings
    std::string time_column;
    std::string angle_column;            ///< data.angle: crank angle [deg], empty when not given
    std::vector<double> crank_angle;     ///< cumulative crank angle [rad] per sample (unwrapped, each recording's moved by its angle_offset), or empty
    int angle_node = -1;                 ///< the node whose angle data.angle measures (data.angle_node), or -1
    double cycle_deg = 720.0;            ///< crank angle of one engine cycle
    NetworkSpec network;
    PresetConstants model_constants;      ///< a preset's constants as given under `model:`
    std::vector<ChannelBinding> inputs;   ///< network inputs by time, then by crank angle, in network order
    std::vector<ChannelBinding> outputs;  ///< the outputs compared with measurements
    std::vector<int> output_indices;      ///< index into network.outputs per entry of `outputs`
    std::vector<ParameterSetting> parameters;  ///< one per network parameter, in network order
    std::vector<Window> estimation;
    std::vector<Window> validation;
    double warmup = 0.0;                  ///< seconds simulated before each window, not scored (or:)
    int warmup_cycles = 0;                ///< engine cycles simulated before each window, not scored
    InitialStateKind initial_state = InitialStateKind::equilibrium;
    SteadyStartSpec steady;               ///< initial_state steady (or from: steady)
    EstimatedStartSpec estimated_start;   ///< initial_state estimated; then initial_state is its from:
    int initial_speed_output = -1;        ///< measured: index into `outputs` of the speed that starts every node
    SimulationSettings simulation;
    EstimationSettings estimation_settings;
    std::filesystem::path report_dir;     ///< resolved; empty when not given
    std::vector<SmoothingChoice> smoothing;  ///< each dry friction's and road load's smoothing_speed
};

/// A command-line override `key.path=value`, applied to the YAML before validation.
struct Override {
    std::string key;
    std::string value;
};

/// Loads, validates and resolves an experiment file. Throws InputError
/// (FILE:LINE: key: what is wrong) on any problem.
Experiment load_experiment(const std::filesystem::path& file, const std::vector<Override>& overrides = {});

/// Parses "a.b.c=value"; throws InputError("--set", 0, text, ...) when malformed.
Override parse_override(const std::string& text);

}  // namespace tvid
