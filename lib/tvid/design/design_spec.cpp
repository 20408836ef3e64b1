#include "tvid/design/design_spec.hpp"

#include <cmath>

#include "tvid/experiment/experiment_tree.hpp"
#include "tvid/experiment/yaml_reader.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

const char* to_string(DesignCriterion c) {
    switch (c) {
        case DesignCriterion::d_optimal: return "d_optimal";
        case DesignCriterion::a_optimal: return "a_optimal";
        case DesignCriterion::worst_relative_se: return "worst_relative_se";
    }
    return "d_optimal";
}

std::size_t DesignSpec::samples() const { return static_cast<std::size_t>(std::llround(duration * sample_rate)) + 1; }

namespace {

constexpr double kMaxDesignSamples = 2.0e7;

// The time input named `name` (its model name), as an index into ex.inputs.
std::size_t time_input(const YamlMap& design, const std::string& key, const Experiment& ex, const std::string& name) {
    std::string names;
    for (std::size_t k = 0; k < ex.inputs.size(); ++k) {
        const ChannelBinding& in = ex.inputs[k];
        if (in.model_name == name) {
            if (in.by_angle)
                design.fail(key, "'" + name + "' is read by crank angle: tvid design excites an input read by time");
            return k;
        }
        if (!in.by_angle) names += (names.empty() ? "" : ", ") + in.model_name;
    }
    design.fail(key, "'" + name + "' is not an input of the model (its inputs: " + (names.empty() ? "none" : names) + ")");
}

// The mean sample interval of the data's time column.
double recorded_sample_rate(const Experiment& ex) {
    const std::vector<double>& t = ex.data.column(ex.time_column);
    if (t.size() < 2 || !(t.back() > t.front())) return 0.0;
    // Rounded to 9 digits: the clock's rounding (999.9999999999 Hz) is not a rate anyone set.
    const double rate = static_cast<double>(t.size() - 1) / (t.back() - t.front());
    const double unit = std::pow(10.0, std::floor(std::log10(rate)) - 8);
    return std::round(rate / unit) * unit;
}

// The first estimation window's length in time.
double first_window_duration(const Experiment& ex) {
    if (ex.estimation.empty()) return 0.0;
    const std::vector<double>& t = ex.data.column(ex.time_column);
    const Window& w = ex.estimation.front();
    return t[w.last] - t[w.first];
}

void read_record(const YamlMap& design, const Experiment& ex, DesignSpec& spec) {
    spec.sample_rate = design.has("sample_rate") ? design.number("sample_rate") : recorded_sample_rate(ex);
    if (!(spec.sample_rate > 0) || !std::isfinite(spec.sample_rate))
        design.fail("sample_rate", "must be a positive number of samples per second");
    spec.duration = design.has("duration") ? design.number("duration") : first_window_duration(ex);
    if (!(spec.duration > 0) || !std::isfinite(spec.duration))
        design.fail("duration", "must be a positive number of seconds");
    if (spec.duration * spec.sample_rate > kMaxDesignSamples)
        design.fail("duration", number_text(spec.duration) + " s at " + number_text(spec.sample_rate) +
                                    " Hz is more than " + number_text(kMaxDesignSamples) + " samples");
    if (spec.duration * spec.sample_rate < 2)
        design.fail("duration", number_text(spec.duration) + " s at " + number_text(spec.sample_rate) +
                                    " Hz is fewer than 3 samples");
}

void read_band(const YamlMap& design, DesignSpec& spec) {
    if (!design.has("band")) design.fail_missing("band", "(the excitation's band [low, high] in Hz)");
    const auto [low, high] = read_interval(design.source(), design.get("band"), design.key_path("band"), true);
    const double nyquist = spec.sample_rate / 2;
    if (low < 0) design.fail("band", "its low end " + number_text(low) + " Hz is below 0");
    if (high > nyquist)
        design.fail("band", "its high end " + number_text(high) + " Hz is above the Nyquist frequency " +
                                number_text(nyquist) + " Hz of the sample rate " + number_text(spec.sample_rate) + " Hz");
    // The record's frequency grid: whole periods within its samples' span, samples / rate.
    const double df = spec.sample_rate / static_cast<double>(spec.samples());
    if (std::floor(high / df + 1e-9) < std::max(1.0, std::ceil(low / df - 1e-9)))
        design.fail("band", "[" + number_text(low) + ", " + number_text(high) + "] Hz holds no frequency of the record's grid (multiples of " +
                                number_text(df) + " Hz, one over the record's length): widen it or lengthen the duration");
    spec.band_low = low;
    spec.band_high = high;
}

void read_range(const YamlMap& design, DesignSpec& spec) {
    if (!design.has("limits")) design.fail_missing("limits", "(the input's range [low, high] in its channel's unit)");
    const auto [low, high] = read_interval(design.source(), design.get("limits"), design.key_path("limits"), true);
    spec.limit_low = low;
    spec.limit_high = high;
    spec.base = design.has("base") ? design.number("base") : 0.0;
    if (!(low < spec.base && spec.base < high))
        design.fail("limits", "[" + number_text(low) + ", " + number_text(high) + "] excludes the operating point base = " +
                                  number_text(spec.base) + (design.has("base") ? "" : " (base not given: 0)") +
                                  ": the input must be free to move both ways about it");
    if (!design.has("rms")) design.fail_missing("rms", "(the input's root mean square about base, in its channel's unit)");
    spec.rms = design.number("rms");
    spec.rms_where = design.source().where(design.get("rms"), design.key_path("rms"));
    if (!(spec.rms > 0) || !std::isfinite(spec.rms)) design.fail("rms", "must be a positive number");
}

void read_levels(const YamlMap& design, const Experiment& ex, DesignSpec& spec) {
    spec.levels.assign(ex.inputs.size(), 0.0);
    spec.levels[spec.input] = spec.base;
    if (!design.has("hold")) return;
    const YamlMap hold = design.map("hold");
    for (const std::string& name : hold.keys()) {
        const std::size_t k = time_input(hold, name, ex, name);
        if (k == spec.input) hold.fail(name, "is the designed input: its level is design.base");
        spec.levels[k] = hold.number(name);
    }
}

void read_noise(const YamlMap& design, const Experiment& ex, DesignSpec& spec) {
    if (!design.has("noise")) design.fail_missing("noise", "(each output's noise standard deviation: noise: { OUTPUT: SIGMA, ... })");
    const YamlMap noise = design.map("noise");
    spec.noise.assign(ex.outputs.size(), 0.0);
    spec.noise_given.assign(ex.outputs.size(), 0.0);
    for (const std::string& name : noise.keys()) {
        std::size_t k = 0;
        while (k < ex.outputs.size() && ex.outputs[k].model_name != name) ++k;
        if (k == ex.outputs.size()) {
            std::string names;
            for (const ChannelBinding& o : ex.outputs) names += (names.empty() ? "" : ", ") + o.model_name;
            noise.fail(name, "'" + name + "' is not an output of the experiment (its outputs: " + names + ")");
        }
        const double sigma = noise.number(name);
        if (!(sigma > 0) || !std::isfinite(sigma))
            noise.fail(name, "the noise standard deviation must be above 0 (it was " + number_text(sigma) +
                                 "): a noise-free output would determine every parameter exactly");
        spec.noise_given[k] = sigma;
        spec.noise[k] = sigma * ex.outputs[k].scale;
    }
    for (std::size_t k = 0; k < ex.outputs.size(); ++k)
        if (spec.noise[k] == 0.0)
            design.fail("noise", "gives no noise standard deviation for the output " + ex.outputs[k].model_name +
                                     ": give one for every output");
}

}  // namespace

DesignSpec read_design_spec(const Experiment& ex, const std::vector<Override>& overrides) {
    const ExperimentTree tree = read_experiment_tree(ex.file, overrides);
    const YamlMap top(tree.source, tree.root, "");
    if (!top.has("design"))
        top.fail_missing("design", "(tvid design reads a design: section: input, duration, band, limits, rms, "
                                   "noise; docs/experiment-design.md)");
    const YamlMap design = top.map("design");
    design.allow_only({"input", "duration", "sample_rate", "band", "limits", "rms", "base", "hold", "noise", "criterion",
                       "bands", "evaluations", "robust"});
    DesignSpec spec;
    spec.where = tree.source.where(design.node(), "design");
    if (!design.has("input")) design.fail_missing("input", "(the model input to design)");
    spec.input = time_input(design, "input", ex, design.text("input"));
    if (ex.estimated_start.on)
        top.fail("initial_state", "is estimated: tvid design predicts with the start known; give the recipe of its "
                                  "seed (e.g. --set initial_state=rest)");
    if (initial_state_row(ex.initial_state).reads_measured_speed)
        top.fail("initial_state", std::string("is ") + initial_state_row(ex.initial_state).name +
                                      ": it reads the recording's speed, which a designed record has not; tvid design "
                                      "starts from rest, equilibrium or steady");
    read_record(design, ex, spec);
    read_band(design, spec);
    read_range(design, spec);
    read_levels(design, ex, spec);
    read_noise(design, ex, spec);
    if (design.has("criterion")) {
        const std::string c = design.choice("criterion", {"d_optimal", "a_optimal", "worst_relative_se"});
        spec.criterion = c == "a_optimal"           ? DesignCriterion::a_optimal
                         : c == "worst_relative_se" ? DesignCriterion::worst_relative_se
                                                    : DesignCriterion::d_optimal;
    }
    if (design.has("bands")) {
        const long long b = design.integer("bands");
        if (b < 1 || b > 32) design.fail("bands", "must be a whole number from 1 to 32");
        spec.bands = static_cast<int>(b);
    }
    if (design.has("robust")) {
        const YamlMap robust = design.map("robust");
        robust.allow_only({"draws", "spread", "seed"});
        if (!robust.has("draws")) robust.fail_missing("draws", "(how many parameter sets to draw about the nominal values)");
        const long long n = robust.integer("draws");
        if (n < 1 || n > 64) robust.fail("draws", "must be a whole number from 1 to 64");
        spec.draws = static_cast<int>(n);
        if (robust.has("spread")) {
            spec.draw_spread = robust.number("spread");
            if (!(spec.draw_spread > 0 && spec.draw_spread <= 10))
                robust.fail("spread", "must be above 0 and at most 10 (a factor within [1/(1 + spread), 1 + spread])");
        }
        if (robust.has("seed")) {
            const long long seed = robust.integer("seed");
            if (seed < 0) robust.fail("seed", "must be a whole number of 0 or more");
            spec.draw_seed = static_cast<std::uint64_t>(seed);
        }
    }
    if (design.has("evaluations")) {
        const long long e = design.integer("evaluations");
        if (e < 1 || e > 100000) design.fail("evaluations", "must be a whole number from 1 to 100000");
        spec.evaluations = static_cast<int>(e);
    }
    return spec;
}

}  // namespace tvid
