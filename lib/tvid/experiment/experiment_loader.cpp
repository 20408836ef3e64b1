// load_experiment: reads an experiment file (format 1, docs/experiment-format.md), applies command-line
// overrides, validates every key and resolves paths, columns and windows.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <fstream>
#include <sstream>
#include <string_view>

#include "tvid/experiment/smoothing_speeds.hpp"
#include "tvid/experiment/channel_reader.hpp"
#include "tvid/experiment/controller_clock.hpp"
#include "tvid/experiment/data_reader.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/experiment_tree.hpp"
#include "tvid/experiment/estimated_start.hpp"
#include "tvid/experiment/model_reader.hpp"
#include "tvid/experiment/optimizer_settings_reader.hpp"
#include "tvid/experiment/overrides.hpp"
#include "tvid/experiment/parameter_reader.hpp"
#include "tvid/experiment/recording_join.hpp"
#include "tvid/experiment/window_reader.hpp"
#include "tvid/experiment/yaml_reader.hpp"
#include "tvid/io/input_file.hpp"
#include "tvid/io/sha256.hpp"
#include "tvid/model/steady_motion.hpp"
#include "tvid/sim/observation_loops.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

namespace {

// A delay parameter moves a channel by interpolation within the recording: its bounds (or
// its fixed value) must keep it shorter than the recording, and it needs both.
void check_delay_parameters(const YamlMap& section, const NetworkSpec& network,
                            const std::vector<ParameterSetting>& parameters, const RecordingRead& shortest) {
    const double recording_seconds = shortest.seconds();
    NetworkSpec model_only = network;  // which parameters the model itself uses
    model_only.delay_parameters.clear();
    const std::vector<bool> in_model = parameters_in_use(model_only);
    for (int index : network.delay_parameters) {
        const ParameterSetting& p = parameters[static_cast<std::size_t>(index)];
        if (in_model[static_cast<std::size_t>(index)])
            section.fail(p.name, p.name + " is a channel's delay [s] and also a quantity of the model: give the delay "
                                          "a parameter of its own");
        const std::string span = " s; " + shortest.phrase() + " is " + number_text(recording_seconds) + " s long";
        if (p.fixed) {
            if (!(std::abs(p.init) < recording_seconds))
                section.fail(p.name, "the delay " + p.name + " = " + number_text(p.init) + span);
            continue;
        }
        if (!p.has_min || !p.has_max)
            section.fail(p.name, "the delay " + p.name + " needs min and max (in seconds, within the recording)");
        if (!(std::abs(p.min) < recording_seconds && std::abs(p.max) < recording_seconds))
            section.fail(p.name, "the delay " + p.name + "'s bounds [" + number_text(p.min) + ", " + number_text(p.max) +
                                     "]" + span);
    }
}

// The largest swarm a grid start may ask for (grid^M particles).
constexpr double kMaxParticles = 1e6;

// The line of a document marker ('---' or '...' at the start of a line) that follows the
// first document's content, or 0. yaml-cpp's Load reads the first document and ignores the
// rest; its LoadAll can spin without end on malformed input (found by fuzzing), so the
// markers are looked for in the text.
int second_document_line(const std::string& text) {
    bool content_seen = false, ended = false;  // ended: a '...' closed the first document
    int line = 1;
    for (std::size_t start = 0; start < text.size(); ++line) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        const std::string_view l(text.data() + start, end - start);
        const auto is_marker = [&](std::string_view m) {
            return l.substr(0, 3) == m && (l.size() == 3 || l[3] == ' ' || l[3] == '\t' || l[3] == '\r');
        };
        const std::size_t first = l.find_first_not_of(" \t\r");
        const bool content = first != std::string_view::npos && l[first] != '#';
        if (is_marker("---")) {
            if (content_seen) return line;
        } else if (is_marker("...")) {
            ended = content_seen;
        } else if (content) {
            if (ended) return line;
            content_seen = true;
        }
        start = end + 1;
    }
    return 0;
}

// The experiment file's YAML; `sha256` receives the digest of the bytes parsed.
YAML::Node parse_file(const std::filesystem::path& file, std::string& sha256) {
    const std::string name = file.string();
    std::string content = read_input_file(file, "experiment file", kMaxExperimentBytes);
    sha256 = sha256_of_text(content);
    // Lone CR line ends (classic Mac OS), which yaml-cpp reads as one long line (a file
    // opening with a comment then looked empty): made LF, so lines count as an editor shows.
    for (std::size_t i = 0; i < content.size(); ++i)
        if (content[i] == '\r' && (i + 1 == content.size() || content[i + 1] != '\n')) content[i] = '\n';
    for (std::size_t i = 0; i < content.size(); ++i) {
        const auto c = static_cast<unsigned char>(content[i]);
        if (c == 0 || (c < 0x20 && c != '\n' && c != '\r' && c != '\t')) {
            const auto line = 1 + std::count(content.begin(), content.begin() + static_cast<std::ptrdiff_t>(i), '\n');
            throw InputError(name, static_cast<int>(line), "", "not a text file (binary data)");
        }
    }
    if (const int line = second_document_line(content); line > 0)
        throw InputError(name, line, "", "a second YAML document (after '---'): an experiment file holds one");
    YAML::Node root;
    try {
        root = YAML::Load(content);
    } catch (const YAML::Exception& e) {
        throw InputError(name, e.mark.is_null() ? 0 : e.mark.line + 1, "", "YAML syntax error: " + e.msg);
    }
    if (!root.IsDefined() || root.IsNull())
        throw InputError(name, 1, "", "the file is empty (an experiment starts with 'tvid: 1')");
    if (!root.IsMap())
        throw InputError(name, root.Mark().is_null() ? 1 : root.Mark().line + 1, "",
                         "expected an experiment (keys tvid, data, model, ...), not a single value or list");
    return root;
}

// "windows.estimation.0.time" -> "windows.estimation[0].time", as the reader names keys.
std::string reader_path(const std::string& key) {
    std::string out;
    std::size_t start = 0;
    for (;;) {
        const std::size_t dot = key.find('.', start);
        const std::string seg = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        const bool index = !seg.empty() && seg.find_first_not_of("0123456789") == std::string::npos;
        out += index && !out.empty() ? "[" + seg + "]" : (out.empty() ? "" : ".") + seg;
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    return out;
}

SimulationSettings read_simulation(const YamlMap& m) {
    m.allow_only({"method", "step", "rtol", "atol", "max_steps"});
    SimulationSettings s;
    if (m.has("method")) {
        std::vector<std::string> names;
        for (const IntegrationMethodRow& row : kIntegrationMethods) names.emplace_back(row.name);
        s.method = find_integration_method(m.choice("method", names))->kind;
    }
    if (m.has("step")) {
        const YAML::Node step = m.get("step");
        if (!(step.IsScalar() && step.Scalar() == "sample")) {
            s.max_step = m.number("step");
            if (!(s.max_step > 0)) m.fail("step", "the step must be 'sample' or a positive number of seconds");
        }
    }
    for (const char* key : {"rtol", "atol"}) {
        if (!m.has(key)) continue;
        const double v = m.number(key);
        if (!(v > 0)) m.fail(key, "a tolerance must be positive");
        (std::string(key) == "rtol" ? s.rtol : s.atol) = v;
    }
    if (m.has("max_steps")) {
        const long long n = m.integer("max_steps");
        if (n < 1) m.fail("max_steps", "the step budget must be at least 1");
        s.max_steps = static_cast<std::size_t>(n);
    }
    return s;
}

// A fixed step so small, or a gap in the time column so long, that one simulation would
// take more than kMaxFixedStepsPerSimulation steps: refused, naming the longest interval.
void check_fixed_step_count(const YamlMap& simulation, const RecordingRead& recording, double max_step) {
    const CsvTable& data = recording.table;
    const std::vector<double>& time = data.column(recording.time_column);
    const FixedStepCount steps = fixed_steps_over(time, max_step);
    if (steps.total <= kMaxFixedStepsPerSimulation) return;
    const std::size_t i = steps.longest_at;
    simulation.fail("step", "a step of " + number_text(max_step) + " s takes " + number_text(steps.total) +
                                " steps per simulation of the recording, more than the " +
                                number_text(kMaxFixedStepsPerSimulation) + " allowed (its longest sample interval, " +
                                number_text(time[i + 1] - time[i]) + " s from line " +
                                std::to_string(data.line_of_row(i)) + " of " + data.file().string() + ", takes " +
                                number_text(steps.longest) + "); use a larger step or check the time column");
}

// initial_state: { kind: steady, node: NAME, speed: RAD_PER_S or COLUMN, samples: N }.
SteadyStartSpec read_steady_start(const YamlMap& m, const NetworkSpec& network,
                                  const std::vector<RecordingRead>& recordings, bool estimated) {
    const CsvTable& data = recordings.front().table;
    if (estimated) m.allow_only({"kind", "from", "validation", "node", "speed", "samples"});
    else m.allow_only({"kind", "node", "speed", "samples"});
    SteadyStartSpec s;
    const std::string node = m.text("node");
    s.node = network.node_index(node);
    if (s.node < 0) m.fail("node", "no node named '" + node + "' in the model");
    if (!m.has("speed")) m.fail_missing("speed", "(the node's speed in rad/s, or a column whose mean gives it)");
    const YAML::Node speed = m.get("speed");
    const std::string text = speed.IsScalar() ? speed.Scalar() : std::string();
    if (!text.empty() && data.has_column(text)) {
        s.speed_column = text;
        for (const RecordingRead& r : recordings)  // the column of every recording
            if (!r.table.has_column(text)) m.fail("speed", "no column named '" + text + "' in " + r.table.file().string());
    } else {
        const char c = text.empty() ? ' ' : text.front();
        if (!text.empty() && !(std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.'))
            m.fail("speed", "no column named '" + text + "' in " + data.file().string());
        const std::optional<double> v = m.optional_number("speed");
        if (!v || !std::isfinite(*v))
            m.fail("speed", "expected a speed in rad/s or a column of " + data.file().string());
        s.speed = *v;
    }
    if (m.has("samples")) {
        const long long k = m.integer("samples");
        if (k < 1 || k > 100'000'000) m.fail("samples", "expected a number of samples to average, at least 1");
        s.samples = static_cast<std::size_t>(k);
    }
    return s;
}

EstimationSettings read_estimation(const YamlMap& m) {
    std::vector<std::string> keys{"cost", "normalize", "optimizer", "strict"};
    for (std::string& section : optimizer_section_keys()) keys.push_back(std::move(section));
    m.allow_only(keys);
    EstimationSettings s;
    if (m.has("strict")) s.strict = m.flag("strict");
    if (m.has("cost")) s.cost = m.choice("cost", {"l1", "l2"}) == "l1" ? CostKind::l1 : CostKind::l2;
    if (m.has("normalize"))
        s.normalize = m.choice("normalize", {"spread", "none"}) == "spread" ? OutputNormalization::spread
                                                                            : OutputNormalization::none;
    if (m.has("optimizer")) {
        s.optimizer = read_optimizer_kind(m);
        s.optimizer_given = true;
    }
    read_optimizer_sections(m, s);
    // Levenberg–Marquardt minimizes a sum of squares (the methodology paper eq. 7), also as the polish
    // of pso+lm and in every start of multistart.
    if (optimizer_traits(s.optimizer).least_squares && s.cost != CostKind::l2)
        m.fail(m.has("cost") ? "cost" : "optimizer", std::string("the ") + optimizer_name(s.optimizer) +
                                                         " optimizer minimizes a sum of squares: set cost: l2");
    return s;
}

}  // namespace

namespace {

// data: the recordings read; what the experiment names after the first, and the axes the
// windows are read on (each recording's own).
std::vector<RecordingAxes> recording_axes(const DataSection& data, Experiment& ex) {
    const RecordingRead& first = data.recordings.front();
    ex.data_file = first.recording.file;
    ex.time_column = first.time_column;
    ex.angle_column = data.angle_column;
    ex.cycle_deg = data.cycle_deg;
    std::vector<RecordingAxes> axes;
    const std::vector<RowSpan> rows = recording_rows(data);
    for (std::size_t k = 0; k < data.recordings.size(); ++k) {
        const RecordingRead& r = data.recordings[k];
        axes.push_back({r.table.column(r.time_column), r.crank_deg, data.angle_column.empty() ? 720.0 : data.cycle_deg,
                        r.recording.name, rows[k].begin});
    }
    return axes;
}

// A grid start places grid^M particles: refuse swarms that could never be evaluated,
// naming the setting that asked for the grid (it may come from --set), or the default.
void check_swarm_size(const YamlMap& top, const YamlSource& src, const YamlMap& parameters, const Experiment& ex,
                      bool swarm) {
    const PsoSettings& pso = ex.estimation_settings.pso;
    std::size_t free_count = 0;
    for (const ParameterSetting& p : ex.parameters) free_count += p.fixed ? 0 : 1;
    if (swarm && pso.start == PsoStart::grid && std::pow(static_cast<double>(pso.grid), static_cast<double>(free_count)) > kMaxParticles) {
        const std::string problem = "a grid of " + std::to_string(pso.grid) + " points on " + std::to_string(free_count) +
                                    " free parameters is more than 1e6 particles; use start: latin_hypercube with particles: N";
        if (!top.has("estimation"))
            src.fail(parameters.node(), "estimation.pso.grid", problem + " (the default start is a grid of 2 points)");
        const YamlMap est = top.map("estimation");
        if (est.has("pso")) {
            const YamlMap pso_map = est.map("pso");
            if (pso_map.has("grid")) pso_map.fail("grid", problem);
        }
        est.fail("pso", problem);
    }

}

// initial_state: and what ties it to the model: an engine turns, a speed source turns its
// node, a measured start needs a measured speed.
void read_initial_state(const YamlMap& top, const YamlMap& data, const DataSection& recorded, Experiment& ex) {
    // A running engine has no static equilibrium: its models start from the measurement.
    const bool engine = !ex.network.angle_input_names.empty();  // a channel read by crank angle: it turns
    if (engine) ex.initial_state = InitialStateKind::measured;
    if (top.has("initial_state")) {
        const bool detailed = top.get("initial_state").IsMap();
        const YamlMap start = detailed ? top.map("initial_state") : top;
        const std::string key = detailed ? "kind" : "initial_state";
        std::vector<std::string> kinds, recipes;
        for (const InitialStateRow& row : kInitialStateKinds) kinds.emplace_back(row.name);
        recipes = kinds;
        kinds.emplace_back("estimated");
        std::string kind = start.choice(key, kinds);
        const bool estimated = kind == "estimated";
        if (estimated) {
            // The start identified with the model, seeded by a recipe (estimated_start.hpp).
            if (!detailed)
                top.fail("initial_state", "estimated needs the recipe of its seed: initial_state: { kind: estimated, "
                                          "from: steady | measured | equilibrium | rest }");
            if (!start.has("from"))
                start.fail_missing("from", "(the recipe that seeds the estimated start: steady, measured, equilibrium "
                                           "or rest)");
            kind = start.choice("from", recipes);
            ex.estimated_start.on = true;
            ex.estimated_start.where = start.source().where(start.node(), start.path());
            if (start.has("validation"))
                ex.estimated_start.validation = start.choice("validation", {"from", "estimated"}) == "estimated";
            if (!ex.angle_column.empty())
                start.fail("kind", "an estimated start is for a line driven by time channels; with a crank-angle "
                                   "channel the start is shot on the encoder (initial_state: measured)");
            // A sampled controller's memory (its integral, its held command, its past
            // angles) is part of the start and is not among the coordinates estimated: it
            // would restart as if the line had been at rest there, which it was not.
            if (has_sampled_elements(ex.network))
                start.fail("kind", "an estimated start estimates angles and speeds, not a sampled controller's memory "
                                   "(its integral, held command and past angles), which would restart as if the line "
                                   "had been steady there: start from initial_state: rest, measured or steady, where "
                                   "the controller's start is known");
        }
        const InitialStateRow& row = *find_initial_state(kind);
        ex.initial_state = row.kind;
        const bool has_keys = row.keys[0] != nullptr;
        if (detailed && !has_keys)
            estimated ? start.allow_only({"kind", "from", "validation"}) : start.allow_only({"kind"});
        if (ex.initial_state == InitialStateKind::steady) {
            if (!detailed)
                top.fail("initial_state", "steady needs its node and speed: initial_state: { kind: steady, node: "
                                          "NAME, speed: RAD_PER_S or COLUMN }");
            ex.steady = read_steady_start(start, ex.network, recorded.recordings, estimated);
            if (const std::string held = held_to_ground(ex.network); !held.empty())
                start.fail("kind", "steady on a line held to ground by " + held +
                                       ": it cannot turn steadily, and at rest its start is the static equilibrium "
                                       "(initial_state: equilibrium, measured or rest)");
        }
        if (engine && !row.turns)
            top.fail("initial_state", "a model with cylinders turns: it starts from the measured crank angle and "
                                      "speed (initial_state: measured)");
    }
    const InitialStateRow& row = initial_state_row(ex.initial_state);
    if (const auto held = state_nodes(ex.network); row.static_balance && !held.empty()) {
        const std::string why = "node " + held.front() + " holds a position controller's integral, which carries the "
                                "load at an equilibrium, where every speed is zero: start from initial_state: rest, "
                                "measured or estimated";
        if (top.has("initial_state")) top.fail("initial_state", why);
        top.fail_missing("initial_state", "(" + why + ")");
    }
    if (row.static_balance && prescribes_motion(ex.network)) {
        const std::string why = "a speed source turns its node: start from initial_state: { kind: steady, node: NAME, "
                                "speed: COLUMN } or measured";
        if (top.has("initial_state")) top.fail("initial_state", why);
        top.fail_missing("initial_state", "(" + why + ")");
    }
    if (row.reads_measured_speed) {
        // Every node starts turning at the first measured speed, through the gear ratios,
        // at the measured crank angle when there is one.
        if (ex.angle_column.empty() && engine)
            top.fail("initial_state", "measured needs the crank-angle channel: give data.angle");
        for (std::size_t k = 0; k < ex.outputs.size() && ex.initial_speed_output < 0; ++k)
            if (output_is_speed(ex.network.outputs[static_cast<std::size_t>(ex.output_indices[k])].kind))
                ex.initial_speed_output = static_cast<int>(k);
        if (ex.initial_speed_output < 0) top.fail("initial_state", "measured needs a measured speed among the outputs");
        if (ex.angle_node < 0 && !ex.angle_column.empty() && (ex.warmup > 0 || ex.warmup_cycles > 0))
            data.fail_missing("angle_node", "(the node whose angle the crank-angle channel measures: the warm-up is "
                                            "shot to meet it)");
    }
}

// simulation: and report:.
void read_simulation_and_report(const YamlMap& top, const std::filesystem::path& folder, const DataSection& recorded,
                                Experiment& ex) {
    if (top.has("simulation")) {
        const YamlMap simulation = top.map("simulation");
        ex.simulation = read_simulation(simulation);
        if (takes_fixed_steps(ex.simulation.method) && ex.simulation.max_step > 0)
            for (const RecordingRead& r : recorded.recordings) check_fixed_step_count(simulation, r, ex.simulation.max_step);
    }
    if (top.has("report")) {
        const YamlMap report = top.map("report");
        report.allow_only({"dir"});
        if (report.has("dir")) {
            const std::filesystem::path dir = report.text("dir");
            ex.report_dir = (dir.is_absolute() ? dir : folder / dir).lexically_normal();
        }
    }
}

}  // namespace

ExperimentTree read_experiment_tree(const std::filesystem::path& file, const std::vector<Override>& overrides) {
    std::string sha256;
    YAML::Node root = parse_file(file, sha256);
    apply_overrides(root, overrides);
    std::vector<std::string> override_keys;
    for (const Override& o : overrides) override_keys.push_back(reader_path(o.key));
    return ExperimentTree{root, YamlSource(file.string(), override_keys), sha256};
}

Experiment load_experiment(const std::filesystem::path& file, const std::vector<Override>& overrides) {
    const ExperimentTree tree = read_experiment_tree(file, overrides);
    const YamlSource& src = tree.source;
    const YamlMap top(src, tree.root, "");
    // design: is read by `tvid design` alone (design/design_spec.hpp).
    top.allow_only({"tvid", "name", "data", "model", "inputs", "outputs", "parameters", "windows", "initial_state",
                    "simulation", "estimation", "report", "design"});

    Experiment ex;
    ex.file = file;
    ex.config_sha256 = tree.sha256;
    if (!top.has("tvid")) top.fail_missing("tvid", "format version: the file must start with 'tvid: 1'");
    if (top.integer("tvid") != 1) top.fail("tvid", "format version " + top.get("tvid").Scalar() + " is not known (this tvid reads format 1)");
    ex.name = top.has("name") ? top.text("name") : file.stem().string();
    // The name is the default report folder's (results/NAME): one plain folder name.
    if (top.has("name") && (ex.name.empty() || ex.name == "." || ex.name == ".." ||
                            ex.name.find_first_of("/\\") != std::string::npos))
        top.fail("name", "'" + ex.name + "' names the report folder results/NAME: use a plain name without '/' "
                         "(give the place with report.dir or -o)");

    const YamlMap data = top.map("data");
    const std::filesystem::path folder = file.parent_path();
    DataSection recorded = read_data_section(data, folder);
    const std::vector<RecordingAxes> axes = recording_axes(recorded, ex);

    // The model, its channels and parameters.
    const YamlMap parameters = top.map("parameters");
    ex.network = read_model(top.map("model"), parameters.keys(), ex.model_constants);
    check_controller_clocks(top.map("model"), recorded, ex.network);
    ex.inputs = read_inputs(top.map("inputs"), ex.network, recorded.recordings, parameters.keys());
    if (data.has("angle_node")) {
        if (ex.angle_column.empty()) data.fail("angle_node", "names the node of the crank-angle channel: give data.angle too");
        const std::string node = data.text("angle_node");
        ex.angle_node = ex.network.node_index(node);
        if (ex.angle_node < 0) data.fail("angle_node", "no node named '" + node + "' in the model");
    } else if (!ex.angle_column.empty()) {
        ex.angle_node = ex.network.node_index("flywheel");  // where engines carry their crank encoder
    }
    if (!ex.network.angle_input_names.empty() && ex.angle_column.empty())
        data.fail_missing("angle", "(the model reads cylinder pressures by crank angle: name the crank-angle column)");
    check_cylinder_pressures(top.map("inputs"), ex.inputs, recorded.recordings);
    OutputBindings outputs = read_outputs(top.map("outputs"), ex.network, recorded.recordings, parameters.keys());
    ex.outputs = std::move(outputs.channels);
    ex.output_indices = std::move(outputs.indices);
    if (top.has("estimation")) ex.estimation_settings = read_estimation(top.map("estimation"));
    const bool swarm = optimizer_traits(ex.estimation_settings.optimizer).swarm;
    ex.parameters = read_parameters(parameters, ex.network, swarm);
    check_delay_parameters(parameters, ex.network, ex.parameters, shortest_recording(recorded));
    check_search_box(parameters, ex.parameters, ex.estimation_settings);

    check_swarm_size(top, src, parameters, ex, swarm);

    // Windows and the remaining settings.
    const WindowSet windows = read_windows(top.map("windows"), axes);
    ex.estimation = windows.estimation;
    ex.validation = windows.validation;
    ex.warmup = windows.warmup;
    ex.warmup_cycles = windows.warmup_cycles;
    read_initial_state(top, data, recorded, ex);
    refuse_sampled_warmup(top, ex);
    read_simulation_and_report(top, folder, recorded, ex);
    join_recordings(std::move(recorded), ex);
    choose_smoothing_speeds(ex);
    if (ex.estimated_start.on) define_estimated_starts(ex);
    return ex;
}

}  // namespace tvid
