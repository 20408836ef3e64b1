// The experiment loader (docs/experiment-format.md): the shipped
// configuration resolves to the expected parameters, channels and windows; --set
// overrides; and every bad input is one InputError "FILE:LINE: key.path: what is wrong"
// that names the right line and key.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/problem_definition.hpp"
#include "tvid/experiment/channel_reader.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using tvid::Experiment;
using tvid::InputError;
using tvid::Override;

namespace {

// ---------------------------------------------------------------------------------------
// Scaffolding: a small recording and a valid experiment; each case edits some lines.

// 101 samples, t = 0, 0.001, ..., 0.100 s; columns for the preset and the custom network.
std::string recording_csv() {
    std::ostringstream s;
    s << "t,Ttm,Tds,u,w,a,T\n";
    for (int i = 0; i <= 100; ++i)
        s << i * 0.001 << ',' << 10 + 0.1 * i << ',' << -5 + 0.1 * i << ',' << 0.5 * i << ',' << 2 * i << ','
          << 0.01 * i << ',' << 1 + i << '\n';
    return s.str();
}

// The preset experiment. Line numbers in the file are index + 1.
const std::vector<std::string> kPreset = {
    "tvid: 1",                                                          // 1
    "name: unit",                                                       // 2
    "data: { file: rec.csv, time: t }",                                 // 3
    "model: { preset: cvt_clearance }",                                 // 4
    "inputs: { Ttm: Ttm }",                                             // 5
    "outputs: { Tds: Tds }",                                            // 6
    "parameters:",                                                      // 7
    "  rho1:    { init: 1.5, min: 0.1, max: 10, range: [1, 2] }",       // 8
    "  k_minus: { init: 3000, min: 1, max: 1.0e6 }",                    // 9
    "  k_plus:  { init: 8000, min: 1, max: 1.0e6 }",                    // 10
    "  c_minus: { init: 4, min: 0, max: 100 }",                         // 11
    "  c_plus:  { init: 19, min: 0, max: 100 }",                        // 12
    "  mu:      { init: 0.0035, min: 0, max: 0.1 }",                    // 13
    "  sigma:   { value: 1132.81 }",                                    // 14
    "  d_ds:    { init: -7, min: -100, max: 100 }",                     // 15
    "  d_tm:    { init: 13, min: -100, max: 100 }",                     // 16
    "windows:",                                                         // 17
    "  estimation: [ { time: [0.010, 0.050] } ]",                       // 18
    "  validation: [ { samples: [60, 90] } ]",                          // 19
    "estimation:",                                                      // 20
    "  pso: { start: latin_hypercube, particles: 4, iterations: 1 }",   // 21
};

// Line 11 of kCustom with the clearance between the two nodes instead of to ground.
const std::string kStopBetweenNodes =
    "    - { type: clearance, name: stop, between: [motor, load], k_minus: 100, k_plus: 200, c_minus: 1, c_plus: 2, mu: mu_c }";

// A custom network using every element type except cylinder.
const std::vector<std::string> kCustom = {
    "tvid: 1",                                                                                     // 1
    "name: custom",                                                                                // 2
    "data: { file: rec.csv, time: t }",                                                            // 3
    "model:",                                                                                      // 4
    "  nodes:",                                                                                    // 5
    "    - { name: motor, J: J_m }",                                                               // 6
    "    - { name: load, inverse_J: 20 }",                                                         // 7
    "  elements:",                                                                                 // 8
    "    - { type: torque, name: drive, node: motor, input: T_in, offset: d_in, scale: 2 }",       // 9
    "    - { type: spring_damper, name: shaft, between: [motor, load], k: k_s, c: 0.5 }",          // 10
    "    - { type: clearance, name: stop, between: [load], k_minus: 100, k_plus: 200, c_minus: 1, c_plus: 2, mu: mu_c }",  // 11
    "    - { type: friction, name: bearing, node: load, c: c_f }",                                 // 12
    "    - { type: gear_mesh, name: stage, between: [motor, load], ratio: 3, k: 5000, c: 1, mu: 0.01, sigma: sig }",  // 13
    "    - { type: spring_damper, name: mount, between: [motor, ground], k: 50 }",                 // 14
    "inputs: { T_in: u }",                                                                         // 15
    "outputs:",                                                                                    // 16
    "  w_load:  { column: w, speed: load }",                                                       // 17
    "  a_motor: { column: a, angle: motor }",                                                      // 18
    "  T_shaft: { column: T, torque: shaft, offset: d_T }",                                        // 19
    "parameters:",                                                                                 // 20
    "  J_m:  { init: 0.1, min: 0.01, max: 1 }",                                                    // 21
    "  d_in: { value: 0.5 }",                                                                      // 22
    "  k_s:  { init: 1000, min: 10, max: 1.0e5 }",                                                 // 23
    "  mu_c: { value: 0.002 }",                                                                    // 24
    "  c_f:  { init: 0.1, min: 0, max: 10 }",                                                      // 25
    "  sig:  { value: 2000 }",                                                                     // 26
    "  d_T:  { init: 0, min: -10, max: 10 }",                                                      // 27
    "windows:",                                                                                    // 28
    "  estimation: [ { samples: [10, 50] } ]",                                                     // 29
    "initial_state: rest",                                                                         // 30
};

std::string join(const std::vector<std::string>& lines) {
    std::string s;
    for (const auto& l : lines) s += l + "\n";
    return s;
}

// `lines` with line `line` (1-based) replaced.
std::vector<std::string> with(std::vector<std::string> lines, int line, const std::string& text) {
    lines.at(static_cast<std::size_t>(line - 1)) = text;
    return lines;
}

// `lines` with `text` inserted after line `line` (1-based; 0 = at the top).
std::vector<std::string> inserted(std::vector<std::string> lines, int line, const std::string& text) {
    lines.insert(lines.begin() + line, text);
    return lines;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A scratch folder with the recording; writes experiments and loads them.
struct Scratch {
    TempDir dir;
    Scratch() { dir.write("rec.csv", recording_csv()); }

    std::filesystem::path write(const std::vector<std::string>& lines, const std::string& name = "exp.yaml") const {
        return dir.write(name, join(lines));
    }
    Experiment load(const std::vector<std::string>& lines, const std::vector<Override>& overrides = {}) const {
        return tvid::load_experiment(write(lines), overrides);
    }
};

std::vector<Override> overrides(std::initializer_list<const char*> texts) {
    std::vector<Override> out;
    for (const char* t : texts) out.push_back(tvid::parse_override(t));
    return out;
}

// Loads `file` and returns the InputError it must raise (nullopt, with a failed check, if none).
std::optional<InputError> load_error(const std::filesystem::path& file, const std::vector<Override>& ov = {}) {
    try {
        (void)tvid::load_experiment(file, ov);
    } catch (const InputError& e) {
        return e;
    }
    FAIL_CHECK("loaded without an error: " << file.string());
    return std::nullopt;
}

// The error is "FILE:LINE: KEY: ..." with exactly that file, line and key, on one line,
// and its text mentions `fragment`.
void check_error(const std::optional<InputError>& e, const std::string& file, int line, const std::string& key,
                 const std::string& fragment) {
    REQUIRE(e.has_value());
    const std::string what = e->what();
    INFO(what);
    CHECK(e->file() == file);
    CHECK(e->line() == line);
    CHECK(e->key() == key);
    std::string prefix = file;
    if (line > 0) prefix += ":" + std::to_string(line);
    prefix += ": ";
    if (!key.empty()) prefix += key + ": ";
    CHECK(what.rfind(prefix, 0) == 0);
    CHECK(what.find('\n') == std::string::npos);
    CHECK(contains(what, fragment));
}

// Writes `lines`, loads, and checks the error names that file, `line` and `key`.
void expect_error(const std::vector<std::string>& lines, int line, const std::string& key, const std::string& fragment,
                  const std::vector<Override>& ov = {}) {
    Scratch s;
    const auto file = s.write(lines);
    check_error(load_error(file, ov), file.string(), line, key, fragment);
}

// An error raised by a --set value: "--set: KEY: ...".
void expect_set_error(const std::vector<std::string>& lines, const std::vector<Override>& ov, const std::string& key,
                      const std::string& fragment) {
    Scratch s;
    const auto file = s.write(lines);
    check_error(load_error(file, ov), "--set", 0, key, fragment);
}

std::size_t scored_samples(const tvid::Window& w) {
    std::size_t n = 0;
    for (std::size_t i = w.first; i <= w.last; ++i) n += i > w.start ? 1 : 0;
    return n;
}

const tvid::ParameterSetting& parameter(const Experiment& ex, const std::string& name) {
    for (const auto& p : ex.parameters)
        if (p.name == name) return p;
    FAIL("no parameter " << name);
    throw std::logic_error("unreachable");
}

}  // namespace

// =======================================================================================
// The shipped configuration

TEST_CASE("configs/cvt_tipin.yaml loads with its parameters, channels and windows", "[experiment]") {
    const auto file = source_dir() / "configs" / "cvt_tipin.yaml";
    const Experiment ex = tvid::load_experiment(file);

    CHECK(ex.name == "cvt-tipin");
    // The data file is resolved against the experiment's folder, not the working folder.
    CHECK(std::filesystem::equivalent(ex.data_file, source_dir() / "data" / "cvt" / "tipin_a.csv"));
    CHECK(ex.data_file.lexically_normal() == (source_dir() / "configs" / ".." / "data/cvt/tipin_a.csv").lexically_normal());
    CHECK(ex.report_dir.lexically_normal() == (source_dir() / "results" / "cvt-tipin").lexically_normal());
    CHECK(ex.time_column == "t");
    CHECK(ex.data.rows() == 2501);

    CHECK(ex.network.preset == "cvt_clearance");
    REQUIRE(ex.inputs.size() == 1);
    CHECK(ex.inputs[0].model_name == "Ttm");
    CHECK(ex.inputs[0].column == "Ttm");
    CHECK(ex.inputs[0].scale == 1.0);
    REQUIRE(ex.outputs.size() == 1);
    CHECK(ex.outputs[0].model_name == "Tds");
    CHECK(ex.outputs[0].column == "Tds");
    CHECK(ex.output_indices == std::vector<int>{0});

    // Parameters in the preset's order; all free, init = the middle of the search range.
    struct Expected {
        const char* name;
        double min, max, lo, hi;
    };
    const Expected expected[] = {
        {"rho1", 0.01, 100, 1, 2},          {"k_minus", 1, 1.0e6, 1.0e3, 1.0e4}, {"k_plus", 1, 1.0e6, 1.0e3, 1.0e4},
        {"c_minus", 0, 1.0e4, 10, 20},      {"c_plus", 0, 1.0e4, 10, 20},        {"mu", 0, 0.1, 1.0e-3, 5.0e-3},
        {"sigma", 10, 1.0e5, 1.0e3, 5.0e3}, {"d_ds", -100, 100, -10, -5},        {"d_tm", -100, 100, 10, 15},
    };
    REQUIRE(ex.parameters.size() == 9);
    for (std::size_t i = 0; i < 9; ++i) {
        const auto& p = ex.parameters[i];
        const Expected& e = expected[i];
        INFO(e.name);
        CHECK(p.name == e.name);
        CHECK_FALSE(p.fixed);
        CHECK(p.has_min);
        CHECK(p.has_max);
        CHECK(p.min == e.min);
        CHECK(p.max == e.max);
        REQUIRE(p.range.has_value());
        CHECK(p.range->first == e.lo);
        CHECK(p.range->second == e.hi);
        CHECK(p.init == Approx(0.5 * (e.lo + e.hi)));
        CHECK(p.where.file == file.string());
        CHECK(p.where.line == 15 + static_cast<int>(i));  // one parameter per line from line 15
    }

    // Windows resolved to sample indices: 1 kHz from t = 1.0 s.
    REQUIRE(ex.estimation.size() == 1);
    const tvid::Window& est = ex.estimation[0];
    CHECK(est.first == 500);
    CHECK(est.last == 2000);
    CHECK(est.start == 500);
    CHECK(scored_samples(est) == 1500);  // i in (first, last]
    CHECK(est.label == "time 1.5 to 3");
    CHECK_FALSE(contains(est.label, ","));
    REQUIRE(ex.validation.size() == 2);
    CHECK(ex.validation[0].first == 0);
    CHECK(ex.validation[0].last == 500);
    CHECK(ex.validation[1].first == 2000);
    CHECK(ex.validation[1].last == 2500);
    CHECK(scored_samples(ex.validation[0]) + scored_samples(ex.validation[1]) == 1000);
    CHECK(ex.warmup == 0.0);

    CHECK(ex.initial_state == tvid::InitialStateKind::equilibrium);
    CHECK(ex.simulation.method == tvid::IntegrationMethod::rk4);
    CHECK(ex.simulation.max_step == 0.0);
    CHECK(ex.estimation_settings.cost == tvid::CostKind::l1);
    const tvid::PsoSettings& pso = ex.estimation_settings.pso;
    CHECK(pso.start == tvid::PsoStart::grid);
    CHECK(pso.grid == 2);
    CHECK(pso.iterations == 250);
    CHECK(pso.w == 1.0);
    CHECK(pso.c1 == 0.4);
    CHECK(pso.c2 == 0.4);
    CHECK(pso.seed == 1);
}

TEST_CASE("a relative data path is resolved against the experiment's folder", "[experiment]") {
    TempDir tmp;
    tmp.write("recordings/rec.csv", recording_csv());
    std::vector<std::string> lines = with(kPreset, 3, "data: { file: ../recordings/rec.csv, time: t }");
    const auto file = tmp.write("experiments/exp.yaml", join(lines));
    const Experiment ex = tvid::load_experiment(file);
    CHECK(std::filesystem::equivalent(ex.data_file, tmp.path() / "recordings" / "rec.csv"));
    CHECK(ex.data.rows() == 101);

    // An absolute path is taken as it is.
    lines = with(kPreset, 3, "data: { file: '" + (tmp.path() / "recordings" / "rec.csv").string() + "', time: t }");
    const auto file2 = tmp.write("elsewhere/exp.yaml", join(lines));
    CHECK(tvid::load_experiment(file2).data.rows() == 101);
}

TEST_CASE("the base preset experiment loads", "[experiment]") {
    Scratch s;
    const Experiment ex = s.load(kPreset);
    CHECK(ex.name == "unit");
    REQUIRE(ex.estimation.size() == 1);
    CHECK(ex.estimation[0].first == 10);
    CHECK(ex.estimation[0].last == 50);
    REQUIRE(ex.validation.size() == 1);
    CHECK(ex.validation[0].first == 60);
    CHECK(ex.validation[0].last == 90);
    CHECK(ex.validation[0].start == 60);
    CHECK(ex.validation[0].label == "samples 60 to 90");
    CHECK(ex.estimation_settings.pso.start == tvid::PsoStart::latin_hypercube);
    CHECK(ex.estimation_settings.pso.particles == 4);
    CHECK(ex.estimation_settings.pso.iterations == 1);
    CHECK(ex.report_dir.empty());
}

// =======================================================================================
// Overrides

TEST_CASE("parse_override splits key and value", "[experiment][overrides]") {
    Override o = tvid::parse_override("estimation.pso.iterations=50");
    CHECK(o.key == "estimation.pso.iterations");
    CHECK(o.value == "50");
    o = tvid::parse_override("name=a=b");  // only the first '=' separates
    CHECK(o.key == "name");
    CHECK(o.value == "a=b");
    o = tvid::parse_override("windows.estimation.0.time=[2.0, 2.5]");
    CHECK(o.key == "windows.estimation.0.time");
    CHECK(o.value == "[2.0, 2.5]");
    o = tvid::parse_override("name=");
    CHECK(o.key == "name");
    CHECK(o.value.empty());
}

TEST_CASE("a malformed override is an error from --set", "[experiment][overrides]") {
    for (const char* text : {"novalue", "=5", ".a=1", "a.=1", "a..b=1", "a b=1", "a/b=1"}) {
        INFO(text);
        try {
            (void)tvid::parse_override(text);
            FAIL_CHECK("accepted");
        } catch (const InputError& e) {
            CHECK(e.file() == "--set");
            CHECK(e.line() == 0);
            CHECK(std::string(e.what()).rfind("--set: ", 0) == 0);
            CHECK(std::string(e.what()).find('\n') == std::string::npos);
        }
    }
    try {
        (void)tvid::parse_override("novalue");
    } catch (const InputError& e) {
        CHECK(e.key() == "novalue");
        CHECK(contains(e.what(), "key=value"));
    }
}

TEST_CASE("overrides change the loaded experiment", "[experiment][overrides]") {
    const auto file = source_dir() / "configs" / "cvt_tipin.yaml";

    SECTION("a list index selects a window") {
        const Experiment ex = tvid::load_experiment(file, overrides({"windows.estimation.0.time=[2.0, 2.5]"}));
        REQUIRE(ex.estimation.size() == 1);
        CHECK(ex.estimation[0].first == 1000);
        CHECK(ex.estimation[0].last == 1500);
        CHECK(ex.validation.size() == 2);  // untouched
    }
    SECTION("scalar values") {
        const Experiment ex = tvid::load_experiment(
            file, overrides({"estimation.pso.iterations=7", "estimation.pso.seed=42", "name=renamed",
                             "parameters.rho1.max=50", "estimation.pso.start=latin_hypercube"}));
        CHECK(ex.estimation_settings.pso.iterations == 7);
        CHECK(ex.estimation_settings.pso.seed == 42);
        CHECK(ex.estimation_settings.pso.start == tvid::PsoStart::latin_hypercube);
        CHECK(ex.name == "renamed");
        CHECK(parameter(ex, "rho1").max == 50);
        CHECK(parameter(ex, "rho1").min == 0.01);  // the rest of the entry stays
    }
    SECTION("YAML values: a mapping and a list") {
        const Experiment ex = tvid::load_experiment(
            file, overrides({"parameters.sigma={ value: 1132.81 }", "windows.validation=[ { samples: [0, 10] } ]",
                             "estimation.pso={ start: uniform, particles: 8, iterations: 2 }"}));
        const auto& sigma = parameter(ex, "sigma");
        CHECK(sigma.fixed);
        CHECK(sigma.init == 1132.81);
        CHECK_FALSE(sigma.range.has_value());
        REQUIRE(ex.validation.size() == 1);
        CHECK(ex.validation[0].first == 0);
        CHECK(ex.validation[0].last == 10);
        CHECK(ex.estimation_settings.pso.start == tvid::PsoStart::uniform);
        CHECK(ex.estimation_settings.pso.particles == 8);
        CHECK(ex.estimation_settings.pso.grid == 2);  // the whole section was replaced: defaults
        CHECK(ex.estimation_settings.pso.seed == 1);
    }
}

TEST_CASE("overrides create missing sections", "[experiment][overrides]") {
    Scratch s;
    // The base has no simulation, report or initial_state keys.
    const Experiment ex = s.load(kPreset, overrides({"simulation.method=dopri5", "simulation.rtol=1e-9",
                                                     "report.dir=out/here", "initial_state=rest", "windows.warmup=0.002"}));
    CHECK(ex.simulation.method == tvid::IntegrationMethod::dopri5);
    CHECK(ex.simulation.rtol == 1e-9);
    CHECK(ex.report_dir.lexically_normal() == (s.dir.path() / "out" / "here").lexically_normal());
    CHECK(ex.initial_state == tvid::InitialStateKind::rest);
    CHECK(ex.warmup == 0.002);
    CHECK(ex.estimation[0].start == 8);
}

TEST_CASE("bad override paths and values are errors from --set", "[experiment][overrides]") {
    SECTION("list index past the end") {
        expect_set_error(kPreset, overrides({"windows.estimation.3.time=[0.01, 0.02]"}), "windows.estimation.3.time",
                         "only 1 entr");
    }
    SECTION("through a value that is not a section") {
        expect_set_error(kPreset, overrides({"name.first=x"}), "name.first", "not a section");
    }
    SECTION("a value that is not valid YAML") {
        expect_set_error(kPreset, overrides({"parameters.rho1.range=[1, 2"}), "parameters.rho1.range", "YAML");
    }
    SECTION("a value checked like one in the file") {
        expect_set_error(kPreset, overrides({"parameters.rho1.min=20"}), "parameters.rho1.min",
                         "min (20) is greater than max (10)");
        expect_set_error(kPreset, overrides({"estimation.pso.iterations=many"}), "estimation.pso.iterations",
                         "'many'");
        expect_set_error(kPreset, overrides({"windows.estimation.0.time=[5, 6]"}), "windows.estimation[0].time",
                         "outside the data");
        expect_set_error(kPreset, overrides({"parameters.sigma={ fixed: true }"}), "parameters.sigma.value",
                         "missing");
        expect_set_error(kPreset, overrides({"simulation={ method: euler }"}), "simulation.method", "'euler'");
    }
    SECTION("an unknown key added by --set") {
        expect_set_error(kPreset, overrides({"estimation.pso.itrations=5"}), "estimation.pso.itrations",
                         "did you mean 'iterations'");
    }
    SECTION("errors elsewhere still name the file line") {
        // The override is fine; the file's own mistake is reported at its line.
        expect_error(with(kPreset, 11, "  c_minus: { init: 4, min: 50, max: 10 }"), 11, "parameters.c_minus.min",
                     "greater than max", overrides({"estimation.pso.iterations=2"}));
    }
}

TEST_CASE("a grid start too large for the free parameters names the grid setting", "[experiment][overrides]") {
    SECTION("grid from --set") {
        // 5^9 = 1953125 particles > 1e6
        const auto file = source_dir() / "configs" / "cvt_tipin.yaml";
        check_error(load_error(file, overrides({"estimation.pso.grid=5"})), "--set", 0, "estimation.pso.grid",
                    "latin_hypercube");
    }
    SECTION("grid in the file") {
        expect_error(with(kPreset, 21, "  pso: { start: grid, grid: 6, iterations: 1 }"), 21, "estimation.pso.grid",
                     "latin_hypercube");  // 6^8 = 1679616
    }
    SECTION("the default grid of 2 on 20 free parameters, with no estimation section") {
        // 2^20 = 1048576 > 1e6: the message must explain, not claim a key is missing.
        std::vector<std::string> lines = {"tvid: 1", "data: { file: rec.csv, time: t }", "model:", "  nodes: [ { name: n, J: 1 } ]",
                                          "  elements:", "    - { type: torque, node: n, input: u_in }"};
        std::vector<std::string> params = {"parameters:"};
        for (int i = 0; i < 20; ++i) {
            lines.push_back("    - { type: spring_damper, between: [n], k: k" + std::to_string(i) + " }");
            params.push_back("  k" + std::to_string(i) + ": { min: 1, max: 2 }");
        }
        lines.push_back("inputs: { u_in: u }");
        lines.push_back("outputs: { w: { column: w, speed: n } }");
        lines.insert(lines.end(), params.begin(), params.end());
        lines.push_back("windows: { estimation: [ { samples: [1, 5] } ] }");
        Scratch s;
        const auto file = s.write(lines);
        const auto e = load_error(file);
        REQUIRE(e.has_value());
        INFO(e->what());
        CHECK(e->file() == file.string());
        CHECK(e->line() > 0);
        CHECK(e->key().rfind("estimation.pso", 0) == 0);
        CHECK(contains(e->what(), "latin_hypercube"));
        CHECK_FALSE(contains(e->what(), "missing"));
        // With a latin-hypercube start the same network loads.
        lines.push_back("estimation: { pso: { start: latin_hypercube, particles: 10 } }");
        CHECK(s.load(lines).parameters.size() == 20);
    }
}

// =======================================================================================
// Parameters

TEST_CASE("parameter settings: fixed values, defaults for init", "[experiment][parameters]") {
    Scratch s;
    std::vector<std::string> lines = kPreset;
    lines = with(lines, 9, "  k_minus: { min: 1, max: 1001 }");               // init = middle of the bounds
    lines = with(lines, 10, "  k_plus:  { min: 0, max: 1.0e6, range: [10, 30] }");  // init = middle of the range
    lines = with(lines, 11, "  c_minus: 4");                                   // shorthand: fixed
    lines = with(lines, 12, "  c_plus:  { value: 19, fixed: true }");
    lines = with(lines, 13, "  mu:      { init: 0.004, fixed: true }");        // fixed at its init
    lines = with(lines, 15, "  d_ds:\n    init: -7\n    min: -100\n    max: 100");  // block style
    const Experiment ex = s.load(lines);
    CHECK(parameter(ex, "k_minus").init == 501);
    CHECK_FALSE(parameter(ex, "k_minus").fixed);
    CHECK(parameter(ex, "k_plus").init == 20);
    CHECK(parameter(ex, "c_minus").fixed);
    CHECK(parameter(ex, "c_minus").init == 4);
    CHECK(parameter(ex, "c_plus").fixed);
    CHECK(parameter(ex, "c_plus").init == 19);
    CHECK(parameter(ex, "mu").fixed);
    CHECK(parameter(ex, "mu").init == 0.004);
    CHECK(parameter(ex, "sigma").fixed);  // `value:` alone fixes
    CHECK(parameter(ex, "sigma").init == 1132.81);
    CHECK(parameter(ex, "d_ds").init == -7);
    CHECK_FALSE(parameter(ex, "d_ds").fixed);
    CHECK(parameter(ex, "rho1").init == 1.5);
    // Parameters stay in the network's order whatever the file's order.
    CHECK(ex.parameters[0].name == "rho1");
    CHECK(ex.parameters[8].name == "d_tm");
    // A fixed parameter needs no search box, even under the particle swarm.
    CHECK_FALSE(parameter(ex, "c_minus").has_min);
}

TEST_CASE("parameter errors name the line and the key", "[experiment][parameters]") {
    SECTION("fixed without a value") {
        expect_error(with(kPreset, 14, "  sigma:   { fixed: true }"), 14, "parameters.sigma.value", "needs its value");
    }
    SECTION("value on a parameter marked free") {
        expect_error(with(kPreset, 14, "  sigma:   { value: 1132.81, fixed: false }"), 14, "parameters.sigma.value",
                     "free parameter");
    }
    SECTION("value and init together") {
        expect_error(with(kPreset, 15, "  d_ds:    { init: -7, value: -7 }"), 15, "parameters.d_ds.value", "not both");
    }
    SECTION("min > max") {
        expect_error(with(kPreset, 11, "  c_minus: { init: 4, min: 50, max: 10 }"), 11, "parameters.c_minus.min",
                     "min (50) is greater than max (10)");
    }
    SECTION("min > max in block style names the line of min") {
        expect_error(with(kPreset, 11, "  c_minus:\n    init: 4\n    min: 50\n    max: 10"), 13, "parameters.c_minus.min",
                     "greater than max");
    }
    SECTION("init outside the bounds") {
        expect_error(with(kPreset, 12, "  c_plus:  { init: 190, min: 0, max: 100 }"), 12, "parameters.c_plus.init",
                     "outside the bounds [0, 100]");
    }
    SECTION("init below min only") {
        expect_error(with(kPreset, 12, "  c_plus:  { init: -1, min: 0, range: [1, 2] }"), 12, "parameters.c_plus.init",
                     "outside the bounds [0, inf]");
    }
    SECTION("fixed value outside the bounds") {
        expect_error(with(kPreset, 14, "  sigma:   { value: 5, min: 10, max: 100 }"), 14, "parameters.sigma.value",
                     "outside the bounds");
    }
    SECTION("range outside the bounds") {
        expect_error(with(kPreset, 8, "  rho1:    { init: 1.5, min: 0.1, max: 10, range: [1, 20] }"), 8,
                     "parameters.rho1.range", "outside the bounds");
    }
    SECTION("range the wrong way round") {
        expect_error(with(kPreset, 8, "  rho1:    { init: 1.5, min: 0.1, max: 10, range: [2, 1] }"), 8,
                     "parameters.rho1.range", "below the upper end");
    }
    SECTION("an inverse inertia must be positive") {
        expect_error(with(kPreset, 8, "  rho1:    { init: 1, min: -5, max: 10 }"), 8, "parameters.rho1.min",
                     "must be positive");
        // A lower bound of exactly 0 would let the swarm place a particle on 1/J = 0.
        expect_error(with(kPreset, 8, "  rho1:    { init: 1, min: 0, max: 10 }"), 8, "parameters.rho1.min",
                     "must be positive");
        expect_error(with(kPreset, 8, "  rho1:    { init: 0, min: 0, max: 10 }"), 8, "parameters.rho1.init",
                     "must be positive");
        expect_error(with(kPreset, 8, "  rho1:    0"), 8, "parameters.rho1", "must be positive");
        expect_error(with(kPreset, 8, "  rho1:    { value: -2 }"), 8, "parameters.rho1.value", "must be positive");
        expect_error(with(kPreset, 8, "  rho1:    { range: [0, 2] }"), 8, "parameters.rho1.range", "positive");
    }
    SECTION("sigma must be positive") {
        expect_error(with(kPreset, 14, "  sigma:   { value: -1132.81 }"), 14, "parameters.sigma.value", "positive");
    }
    SECTION("a free parameter without a search box under the particle swarm") {
        expect_error(with(kPreset, 9, "  k_minus: { init: 3000 }"), 9, "parameters.k_minus", "search box");
        expect_error(with(kPreset, 9, "  k_minus: { init: 3000, min: 1 }"), 9, "parameters.k_minus", "search box");
    }
    SECTION("a model parameter not declared") {
        std::vector<std::string> lines = kPreset;
        lines.erase(lines.begin() + 15);  // d_tm
        Scratch s;
        const auto file = s.write(lines);
        const auto e = load_error(file);
        REQUIRE(e.has_value());
        INFO(e->what());
        CHECK(e->key() == "parameters.d_tm");
        CHECK((e->line() == 7 || e->line() == 8));  // the parameters section
        CHECK(contains(e->what(), "missing"));
    }
    SECTION("an unknown parameter") {
        expect_error(inserted(kPreset, 16, "  d_tn:    { init: 1, min: 0, max: 2 }"), 17, "parameters.d_tn",
                     "did you mean 'd_tm'");
    }
    SECTION("an unknown key in a parameter") {
        expect_error(with(kPreset, 11, "  c_minus: { init: 4, min: 0, maximum: 100 }"), 11, "parameters.c_minus.maximum",
                     "unknown key");
    }
    SECTION("a number that is not one") {
        expect_error(with(kPreset, 11, "  c_minus: { init: 4, min: 0, max: 1oo }"), 11, "parameters.c_minus.max",
                     "expected a number");
        expect_error(with(kPreset, 11, "  c_minus: { init: .nan, min: 0, max: 100 }"), 11, "parameters.c_minus.init",
                     "number");
    }
}

TEST_CASE("scale: log or linear per parameter, log only on a positive box", "[experiment][parameters][scale]") {
    Scratch s;
    std::vector<std::string> lines = kPreset;
    lines = with(lines, 9, "  k_minus: { init: 3000, min: 1, max: 1.0e6, scale: log }");
    lines = with(lines, 10, "  k_plus:  { init: 8000, min: 1, max: 1.0e6, scale: linear }");
    const Experiment ex = s.load(lines);
    CHECK(parameter(ex, "k_minus").scale == tvid::ParameterScale::log);
    CHECK(parameter(ex, "k_plus").scale == tvid::ParameterScale::linear);
    CHECK(parameter(ex, "rho1").scale == tvid::ParameterScale::linear);  // the default
    // --set reaches it as any other key.
    CHECK(parameter(s.load(kPreset, overrides({"parameters.k_plus.scale=log"})), "k_plus").scale ==
          tvid::ParameterScale::log);

    SECTION("a box reaching 0 or below has no logarithm") {
        expect_error(with(kPreset, 11, "  c_minus: { init: 4, min: 0, max: 100, scale: log }"), 11,
                     "parameters.c_minus.scale", "give min > 0 (min is 0)");
        expect_error(with(kPreset, 15, "  d_ds:    { init: -7, min: -100, max: 100, scale: log }"), 15,
                     "parameters.d_ds.scale", "min is -100");
        expect_error(with(kPreset, 11, "  c_minus: { init: 4, range: [1, 10], scale: log }"), 11,
                     "parameters.c_minus.scale", "no min is given");
        const auto e = load_error(s.write(kPreset), overrides({"parameters.c_plus.scale=log"}));
        REQUIRE(e.has_value());
        CHECK(e->key() == "parameters.c_plus.scale");
    }
    SECTION("an unknown scale") {
        expect_error(with(kPreset, 9, "  k_minus: { init: 3000, min: 1, max: 1.0e6, scale: logarithmic }"), 9,
                     "parameters.k_minus.scale", "expected log or linear");
    }
}

TEST_CASE("a linear search box of more than two decades is found", "[experiment][parameters][scale]") {
    Scratch s;
    std::vector<std::string> lines = kPreset;
    lines = with(lines, 9, "  k_minus: { init: 3000, min: 1, max: 1.0e6 }");                    // bounds: 6 decades
    lines = with(lines, 10, "  k_plus:  { init: 8000, min: 1, max: 1.0e6, range: [5000, 20000] }");  // range: 0.6
    lines = with(lines, 11, "  c_minus: { init: 4, min: 0, max: 100 }");                        // from 0: no decades
    lines = with(lines, 12, "  c_plus:  { init: 19, min: 1, max: 1.0e6, scale: log }");         // already log
    lines = with(lines, 13, "  mu:      { init: 0.004, min: 1.0e-4, max: 0.1, fixed: true }");  // fixed
    const Experiment ex = s.load(lines);
    CHECK(tvid::spans_decades(parameter(ex, "k_minus"), 2));
    CHECK_FALSE(tvid::spans_decades(parameter(ex, "k_minus"), 6));
    CHECK_FALSE(tvid::spans_decades(parameter(ex, "k_plus"), 2));
    CHECK_FALSE(tvid::spans_decades(parameter(ex, "c_minus"), 2));
    CHECK_FALSE(tvid::spans_decades(parameter(ex, "c_plus"), 2));
    CHECK_FALSE(tvid::spans_decades(parameter(ex, "mu"), 2));
    CHECK(tvid::search_interval(parameter(ex, "k_plus")) == std::make_pair(5000.0, 20000.0));
    CHECK(tvid::search_interval(parameter(ex, "k_minus")) == std::make_pair(1.0, 1.0e6));
}

// =======================================================================================
// Windows

TEST_CASE("windows by time and by samples, with a warm-up", "[experiment][windows]") {
    Scratch s;
    SECTION("samples") {
        const Experiment ex = s.load(with(kPreset, 18, "  estimation: [ { samples: [0, 100] }, { samples: [3, 4] } ]"));
        REQUIRE(ex.estimation.size() == 2);
        CHECK(ex.estimation[0].first == 0);
        CHECK(ex.estimation[0].last == 100);
        CHECK(ex.estimation[1].first == 3);
        CHECK(ex.estimation[1].last == 4);
        CHECK(scored_samples(ex.estimation[1]) == 1);
    }
    SECTION("time between samples takes the samples inside") {
        const Experiment ex = s.load(with(kPreset, 18, "  estimation: [ { time: [0.0105, 0.0205] } ]"));
        CHECK(ex.estimation[0].first == 11);
        CHECK(ex.estimation[0].last == 20);
    }
    SECTION("the whole recording") {
        const Experiment ex = s.load(with(kPreset, 18, "  estimation: [ { time: [0, 0.1] } ]"));
        CHECK(ex.estimation[0].first == 0);
        CHECK(ex.estimation[0].last == 100);
    }
    SECTION("a warm-up starts the simulation earlier") {
        const Experiment ex = s.load(inserted(kPreset, 17, "  warmup: 0.005"));
        CHECK(ex.warmup == 0.005);
        CHECK(ex.estimation[0].start == 5);
        CHECK(ex.estimation[0].first == 10);
        CHECK(ex.estimation[0].last == 50);
        CHECK(ex.validation[0].start == 55);
        CHECK(ex.validation[0].first == 60);
    }
    SECTION("a warm-up reaching exactly the first sample") {
        std::vector<std::string> lines = inserted(kPreset, 17, "  warmup: 0.005");
        lines = with(lines, 19, "  estimation: [ { time: [0.005, 0.050] } ]");
        const Experiment ex = s.load(lines);
        CHECK(ex.estimation[0].start == 0);
        CHECK(ex.estimation[0].first == 5);
    }
}

TEST_CASE("window errors name the line and the key", "[experiment][windows]") {
    SECTION("time outside the data") {
        expect_error(with(kPreset, 18, "  estimation: [ { time: [0.010, 0.2] } ]"), 18, "windows.estimation[0].time",
                     "outside the data");
        expect_error(with(kPreset, 18, "  estimation: [ { time: [-1, 0.05] } ]"), 18, "windows.estimation[0].time",
                     "outside the data");
    }
    SECTION("samples outside the data") {
        expect_error(with(kPreset, 19, "  validation: [ { samples: [60, 101] } ]"), 19, "windows.validation[0].samples",
                     "outside the data");
        expect_error(with(kPreset, 19, "  validation: [ { samples: [-1, 10] } ]"), 19, "windows.validation[0].samples",
                     "outside the data");
    }
    SECTION("the second window of a list") {
        expect_error(with(kPreset, 19, "  validation: [ { samples: [60, 90] }, { time: [0.09, 0.5] } ]"), 19,
                     "windows.validation[1].time", "outside the data");
    }
    SECTION("fewer than two samples") {
        expect_error(with(kPreset, 18, "  estimation: [ { time: [0.0101, 0.0109] } ]"), 18, "windows.estimation[0].time",
                     "fewer than two samples");
        expect_error(with(kPreset, 18, "  estimation: [ { time: [0.0101, 0.0111] } ]"), 18, "windows.estimation[0].time",
                     "fewer than two samples");
        expect_error(with(kPreset, 18, "  estimation: [ { samples: [5, 5] } ]"), 18, "windows.estimation[0].samples",
                     "before the last");
        expect_error(with(kPreset, 18, "  estimation: [ { time: [0.02, 0.02] } ]"), 18, "windows.estimation[0].time",
                     "below the upper end");
    }
    SECTION("no estimation window") {
        expect_error(with(kPreset, 18, "  estimation: []"), 18, "windows.estimation", "at least one window");
    }
    SECTION("both time and samples") {
        Scratch s;
        const auto file = s.write(with(kPreset, 18, "  estimation: [ { time: [0.01, 0.05], samples: [10, 50] } ]"));
        const auto e = load_error(file);
        REQUIRE(e.has_value());
        INFO(e->what());
        CHECK(e->line() == 18);
        CHECK(e->key().rfind("windows.estimation[0]", 0) == 0);
        CHECK(contains(e->what(), "not both"));
        CHECK_FALSE(contains(e->what(), "missing"));  // both are there
    }
    SECTION("neither time nor samples") {
        expect_error(with(kPreset, 18, "  estimation: [ { } ]"), 18, "windows.estimation[0].time", "missing");
    }
    SECTION("an unknown window kind") {
        expect_error(with(kPreset, 18, "  estimation: [ { tim: [0.01, 0.05] } ]"), 18, "windows.estimation[0].tim",
                     "did you mean 'time'");
    }
    SECTION("a warm-up reaching before the recording") {
        std::vector<std::string> lines = inserted(kPreset, 17, "  warmup: 0.015");
        expect_error(lines, 19, "windows.estimation[0]", "warm-up");
        lines = inserted(kPreset, 17, "  warmup: 0.005");
        lines = with(lines, 19, "  estimation: [ { time: [0.004, 0.050] } ]");
        expect_error(lines, 19, "windows.estimation[0]", "before the recording");
    }
    SECTION("a negative warm-up") {
        expect_error(inserted(kPreset, 17, "  warmup: -0.001"), 18, "windows.warmup", "negative");
    }
}

// =======================================================================================
// Channels and units

TEST_CASE("channels carry a unit or a scale", "[experiment][channels]") {
    Scratch s;
    SECTION("a unit of the channel's quantity") {
        const Experiment ex = s.load(with(kPreset, 5, "inputs: { Ttm: { column: Ttm, unit: kN m } }"));
        CHECK(ex.inputs[0].column == "Ttm");
        CHECK(ex.inputs[0].scale == 1e3);
        CHECK(s.load(with(kPreset, 6, "outputs: { Tds: { column: Tds, unit: kN m } }")).outputs[0].scale == 1e3);
        CHECK(s.load(with(kPreset, 6, "outputs: { Tds: { column: Tds, unit: N m } }")).outputs[0].scale == 1.0);
    }
    SECTION("the factors") {
        CHECK(tvid::unit_to_si("rpm") == Approx(2 * std::numbers::pi / 60).epsilon(1e-15));
        CHECK(tvid::unit_to_si("bar") == 1e5);
        CHECK(tvid::unit_to_si("deg") == Approx(std::numbers::pi / 180).epsilon(1e-15));
        CHECK(tvid::unit_to_si("mm/s") == 1e-3);
        CHECK(tvid::unit_to_si("furlong") == 0.0);
    }
    SECTION("a unit of another quantity is refused, naming both") {
        expect_error(with(kPreset, 5, "inputs: { Ttm: { column: Ttm, unit: rpm } }"), 5, "inputs.Ttm.unit",
                     "'rpm' is a unit of angular speed, and Ttm is a torque [N m] (read on a rotational node): give "
                     "N m, Nm, kN m or kNm, or scale: for another factor");
        expect_error(with(kPreset, 5, "inputs: { Ttm: { column: Ttm, unit: bar } }"), 5, "inputs.Ttm.unit",
                     "'bar' is a unit of pressure");
        expect_error(with(kPreset, 6, "outputs: { Tds: { column: Tds, unit: N } }"), 6, "outputs.Tds.unit",
                     "'N' is a unit of force, and Tds is a torque [N m]");
    }
    SECTION("a scale") {
        const Experiment ex = s.load(with(kPreset, 5, "inputs: { Ttm: { column: Ttm, scale: -2.5 } }"));
        CHECK(ex.inputs[0].scale == -2.5);
    }
    SECTION("block style") {
        const Experiment ex = s.load(with(kPreset, 5, "inputs:\n  Ttm:\n    column: Ttm\n    unit: kN m"));
        CHECK(ex.inputs[0].scale == 1e3);
    }
}

TEST_CASE("channel errors name the line and the key", "[experiment][channels]") {
    SECTION("unknown unit") {
        expect_error(with(kPreset, 5, "inputs: { Ttm: { column: Ttm, unit: furlong } }"), 5, "inputs.Ttm.unit",
                     "unknown unit 'furlong'");
        expect_error(with(kPreset, 5, "inputs:\n  Ttm:\n    column: Ttm\n    unit: RPM"), 8, "inputs.Ttm.unit",
                     "unknown unit");
    }
    SECTION("unit and scale together") {
        expect_error(with(kPreset, 5, "inputs: { Ttm: { column: Ttm, unit: rpm, scale: 2 } }"), 5, "inputs.Ttm.scale",
                     "not both");
    }
    SECTION("a scale of zero") {
        expect_error(with(kPreset, 6, "outputs: { Tds: { column: Tds, scale: 0 } }"), 6, "outputs.Tds.scale", "0");
    }
    SECTION("a column not in the CSV") {
        expect_error(with(kPreset, 5, "inputs: { Ttm: { column: Tq, unit: rpm } }"), 5, "inputs.Ttm.column",
                     "no column 'Tq'");
        expect_error(with(kPreset, 6, "outputs:\n  Tds: Tq"), 7, "outputs.Tds", "no column 'Tq'");
    }
    SECTION("no column given") {
        expect_error(with(kPreset, 5, "inputs: { Ttm: { unit: rpm } }"), 5, "inputs.Ttm.column", "missing");
    }
    SECTION("an input the model does not have") {
        expect_error(with(kPreset, 5, "inputs: { Ttm: Ttm, Tin: Tds }"), 5, "inputs.Tin", "unknown key");
    }
    SECTION("an unbound model input") {
        expect_error(with(kPreset, 5, "inputs: { }"), 5, "inputs.Ttm", "missing");
    }
    SECTION("the time column") {
        expect_error(with(kPreset, 3, "data: { file: rec.csv, time: time }"), 3, "data.time", "no column 'time'");
    }
    SECTION("a data file that does not exist") {
        expect_error(with(kPreset, 3, "data:\n  time: t\n  file: nothere.csv"), 5, "data.file", "nothere.csv");
    }
}

// =======================================================================================
// File-level problems

TEST_CASE("duplicate keys are errors at the second occurrence", "[experiment][yaml]") {
    expect_error(inserted(kPreset, 2, "name: again"), 3, "name", "duplicate key");
    expect_error(with(kPreset, 8, "  rho1:    { init: 1.5, min: 0.1, max: 10, init: 2 }"), 8, "parameters.rho1.init",
                 "duplicate key");
    expect_error(inserted(kPreset, 16, "  rho1:    { init: 1.5, min: 0.1, max: 10 }"), 17, "parameters.rho1",
                 "duplicate key");
    expect_error(with(kPreset, 3, "data:\n  file: rec.csv\n  time: t\n  file: rec.csv"), 6, "data.file",
                 "duplicate key");
    expect_error(with(kPreset, 18, "  estimation: [ { time: [0.01, 0.05], time: [0.01, 0.02] } ]"), 18,
                 "windows.estimation[0].time", "duplicate key");
}

TEST_CASE("YAML syntax errors, empty and non-text files", "[experiment][yaml]") {
    SECTION("syntax error with its line") {
        expect_error(with(kPreset, 2, "name: unit: x"), 2, "", "YAML syntax error");
        expect_error(with(kPreset, 3, "data:\n  file: rec.csv\n  time: t: x"), 5, "", "YAML syntax error");
    }
    SECTION("empty file") {
        expect_error({}, 1, "", "empty");
        Scratch s;
        const auto file = s.dir.write("blank.yaml", "");
        check_error(load_error(file), file.string(), 1, "", "empty");
        const auto comments = s.dir.write("comments.yaml", "# nothing here\n\n");
        check_error(load_error(comments), comments.string(), 1, "", "empty");
    }
    SECTION("not a mapping") {
        expect_error({"- tvid", "- 1"}, 1, "", "expected an experiment");
    }
    SECTION("binary data") {
        Scratch s;
        const auto file = s.dir.write("bin.yaml", std::string("tvid: 1\nname: x\x01y\n", 18));
        check_error(load_error(file), file.string(), 2, "", "not a text file");
    }
    SECTION("the format version") {
        expect_error(with(kPreset, 1, "tvid: 2"), 1, "tvid", "format version");
        expect_error(with(kPreset, 1, "# no version"), 2, "tvid", "missing");
    }
    SECTION("an empty value is reported at its key's line") {
        // yaml-cpp places the null of `key:` at the next token: the line must still be the key's.
        expect_error(with(kPreset, 4, "model:"), 4, "model", "got nothing");
        expect_error(with(kPreset, 3, "data:\n  file:\n  time: t"), 4, "data.file", "got nothing");
        expect_error(with(kPreset, 1, "tvid:"), 1, "tvid", "got nothing");
        expect_error(with(kPreset, 8, "  rho1:"), 8, "parameters.rho1", "got nothing");
        std::vector<std::string> lines = kPreset;
        lines.push_back("report:");  // the last line: its null lies past the end of the file
        expect_error(lines, 22, "report", "got nothing");
        lines = with(kPreset, 18, "  estimation:");
        expect_error(lines, 18, "windows.estimation", "list of windows");
    }
    SECTION("an unknown top-level key") {
        expect_error(inserted(kPreset, 21, "reprot: { dir: x }"), 22, "reprot", "did you mean 'report'");
    }
    SECTION("no such experiment file") {
        Scratch s;
        const auto file = s.dir.path() / "none.yaml";
        const auto e = load_error(file);
        REQUIRE(e.has_value());
        CHECK(e->file() == file.string());
        CHECK(contains(e->what(), "no such experiment file"));
    }
}

TEST_CASE("other settings are checked", "[experiment]") {
    Scratch s;
    SECTION("simulation") {
        const Experiment ex = s.load(inserted(kPreset, 19, "simulation: { method: rk4, step: 0.0005 }"));
        CHECK(ex.simulation.max_step == 0.0005);
        expect_error(inserted(kPreset, 19, "simulation: { method: rk4, step: -1 }"), 20, "simulation.step", "positive");
        expect_error(inserted(kPreset, 19, "simulation: { method: dopri5, rtol: 0 }"), 20, "simulation.rtol", "positive");
    }
    SECTION("estimation") {
        expect_error(with(kPreset, 21, "  pso: { start: lhs }"), 21, "estimation.pso.start", "not one of");
        expect_error(with(kPreset, 21, "  pso: { iterations: -1 }"), 21, "estimation.pso.iterations", "between");
        expect_error(with(kPreset, 21, "  pso: { w: -1, start: uniform }"), 21, "estimation.pso.w", "negative");
        expect_error(with(kPreset, 21, "  cost: l3"), 21, "estimation.cost", "'l3'");
    }
    SECTION("initial state") {
        expect_error(inserted(kPreset, 21, "initial_state: moving"), 22, "initial_state", "not one of");
    }
}

// =======================================================================================
// A custom network

TEST_CASE("a custom network loads into the right NetworkSpec", "[experiment][network]") {
    using tvid::Field;
    using tvid::kGround;
    Scratch s;
    const Experiment ex = s.load(kCustom);
    const tvid::NetworkSpec& n = ex.network;
    auto param = [&](const Field& f, const std::string& name) {
        return f.is_parameter() && f.parameter == n.parameter_index(name);
    };
    auto constant = [](const Field& f, double v) { return !f.is_parameter() && f.constant == v; };

    CHECK(n.preset == "custom");
    CHECK(n.parameter_names == std::vector<std::string>{"J_m", "d_in", "k_s", "mu_c", "c_f", "sig", "d_T"});
    CHECK(n.input_names == std::vector<std::string>{"T_in"});

    REQUIRE(n.nodes.size() == 2);
    CHECK(n.nodes[0].name == "motor");
    CHECK_FALSE(n.nodes[0].inverse);
    CHECK(param(n.nodes[0].inertia, "J_m"));
    CHECK(n.nodes[1].name == "load");
    CHECK(n.nodes[1].inverse);
    CHECK(constant(n.nodes[1].inertia, 20));

    REQUIRE(n.torques.size() == 1);
    CHECK(n.torques[0].name == "drive");
    CHECK(n.torques[0].node == 0);
    CHECK(n.torques[0].input == 0);
    CHECK(param(n.torques[0].offset, "d_in"));
    CHECK(constant(n.torques[0].scale, 2));

    REQUIRE(n.spring_dampers.size() == 2);
    CHECK(n.spring_dampers[0].name == "shaft");
    CHECK(n.spring_dampers[0].a == 0);
    CHECK(n.spring_dampers[0].b == 1);
    CHECK(param(n.spring_dampers[0].k, "k_s"));
    CHECK(constant(n.spring_dampers[0].c, 0.5));
    CHECK(n.spring_dampers[1].name == "mount");
    CHECK(n.spring_dampers[1].a == 0);
    CHECK(n.spring_dampers[1].b == kGround);
    CHECK(constant(n.spring_dampers[1].k, 50));
    CHECK(constant(n.spring_dampers[1].c, 0));  // c defaults to 0

    REQUIRE(n.clearances.size() == 1);
    const tvid::ClearanceSpec& cl = n.clearances[0];
    CHECK(cl.name == "stop");
    CHECK(cl.a == 1);
    CHECK(cl.b == kGround);  // `between: [load]` is to ground
    CHECK(constant(cl.k_minus, 100));
    CHECK(constant(cl.k_plus, 200));
    CHECK(constant(cl.c_minus, 1));
    CHECK(constant(cl.c_plus, 2));
    CHECK(param(cl.mu, "mu_c"));
    CHECK_FALSE(cl.smooth);  // no sigma: the non-smooth law

    REQUIRE(n.frictions.size() == 1);
    CHECK(n.frictions[0].name == "bearing");
    CHECK(n.frictions[0].a == 1);
    CHECK(param(n.frictions[0].c, "c_f"));

    REQUIRE(n.gear_meshes.size() == 1);
    const tvid::GearMeshSpec& g = n.gear_meshes[0];
    CHECK(g.name == "stage");
    CHECK(g.a == 0);
    CHECK(g.b == 1);
    CHECK(constant(g.ratio, 3));
    CHECK(constant(g.k, 5000));
    CHECK(constant(g.c, 1));
    CHECK(g.has_clearance);  // backlash via mu
    CHECK(g.smooth);         // and sigma
    CHECK(constant(g.mu, 0.01));
    CHECK(param(g.sigma, "sig"));
    CHECK(constant(g.k_minus, 5000));  // the flank stiffness and damping default to k and c
    CHECK(constant(g.k_plus, 5000));
    CHECK(constant(g.c_minus, 1));
    CHECK(constant(g.c_plus, 1));

    REQUIRE(n.outputs.size() == 3);
    CHECK(n.outputs[0].name == "w_load");
    CHECK(n.outputs[0].kind == tvid::OutputKind::speed);
    CHECK(n.outputs[0].node == 1);
    CHECK(constant(n.outputs[0].offset, 0));
    CHECK(n.outputs[1].name == "a_motor");
    CHECK(n.outputs[1].kind == tvid::OutputKind::angle);
    CHECK(n.outputs[1].node == 0);
    CHECK(n.outputs[2].name == "T_shaft");
    CHECK(n.outputs[2].kind == tvid::OutputKind::torque);
    CHECK(n.outputs[2].element.kind == tvid::ElementKind::spring_damper);
    CHECK(n.outputs[2].element.index == 0);
    CHECK(param(n.outputs[2].offset, "d_T"));

    // Channels.
    REQUIRE(ex.inputs.size() == 1);
    CHECK(ex.inputs[0].model_name == "T_in");
    CHECK(ex.inputs[0].column == "u");
    REQUIRE(ex.outputs.size() == 3);
    CHECK(ex.outputs[0].column == "w");
    CHECK(ex.outputs[1].column == "a");
    CHECK(ex.outputs[2].column == "T");
    CHECK(ex.output_indices == std::vector<int>{0, 1, 2});

    // Parameters in declaration order; fixed ones from `value:`.
    REQUIRE(ex.parameters.size() == 7);
    CHECK(ex.parameters[1].name == "d_in");
    CHECK(ex.parameters[1].fixed);
    CHECK(ex.parameters[1].init == 0.5);
    CHECK_FALSE(ex.parameters[0].fixed);
    CHECK(ex.initial_state == tvid::InitialStateKind::rest);
}

TEST_CASE("a gear mesh with explicit flank fields, and an element named by default", "[experiment][network]") {
    Scratch s;
    std::vector<std::string> lines = with(kCustom, 13,
                                          "    - { type: gear_mesh, between: [motor, load], ratio: 3, k_minus: 10, k_plus: 20, "
                                          "c_minus: 0.1, c_plus: 0.2, mu: 0.01, sigma: sig }");
    lines = with(lines, 19, "  T_shaft: { column: T, torque: gear_mesh5, offset: d_T }");
    const Experiment ex = s.load(lines);
    const tvid::GearMeshSpec& g = ex.network.gear_meshes.at(0);
    CHECK(g.name == "gear_mesh5");
    CHECK(g.k_minus.constant == 10);
    CHECK(g.k_plus.constant == 20);
    CHECK(g.c_minus.constant == 0.1);
    CHECK(g.c_plus.constant == 0.2);
    CHECK(ex.network.outputs[2].element.kind == tvid::ElementKind::gear_mesh);
    CHECK(ex.network.outputs[2].element.index == 0);
}

TEST_CASE("a gear mesh's torque output reads the input shaft, or the output shaft with side: output",
          "[experiment][network]") {
    Scratch s;
    std::vector<std::string> lines =
        with(kCustom, 13, "    - { type: gear_mesh, name: stage, between: [motor, load], ratio: 3, k: 100, c: 0 }");
    lines = with(lines, 19, "  T_shaft: { column: T, torque: stage, side: output, offset: d_T }");
    lines = with(lines, 26, "  # no smoothing: the mesh has no backlash");
    lines = inserted(lines, 19, "  T_in: { column: w, torque: stage, side: input }");
    const Experiment ex = s.load(lines);
    const int out = ex.network.output_index("T_shaft"), in = ex.network.output_index("T_in");
    REQUIRE(out >= 0);
    REQUIRE(in >= 0);
    CHECK(ex.network.outputs[static_cast<std::size_t>(out)].side == tvid::TorqueSide::output);
    CHECK(ex.network.outputs[static_cast<std::size_t>(in)].side == tvid::TorqueSide::input);

    // Twist θm − 3·θl = 0.3 − 3·0.05 = 0.15 rad: mesh torque 100 · 0.15 = 15 N m on the
    // motor's shaft, 3 · 15 = 45 N m on the load's.
    tvid::NetworkModel<double> model(ex.network);
    std::vector<double> p(ex.network.parameter_names.size(), 1.0);
    p.at(static_cast<std::size_t>(ex.network.parameter_index("d_T"))) = 0.0;
    model.set_parameters(p.data());
    const double x[4] = {0.3, 0.05, 0.0, 0.0};
    const double u[1] = {0.0};
    CHECK(model.output(static_cast<std::size_t>(in), x, u) == Approx(15.0));
    CHECK(model.output(static_cast<std::size_t>(out), x, u) == Approx(45.0));
}

TEST_CASE("a channel's delay shifts it onto the model's time, interpolated, held at the ends", "[experiment][channels]") {
    Scratch s;
    // u = 500 t (the ramp of the recording, 1 ms samples) read 2.5 ms late: 2.5 samples;
    // T = 1 + 1000 t read 2 ms early.
    std::vector<std::string> lines = with(kCustom, 15, "inputs: { T_in: { column: u, delay: 0.0025 } }");
    lines = with(lines, 19, "  T_shaft: { column: T, torque: shaft, offset: d_T, delay: -0.002 }");
    const Experiment ex = s.load(lines);
    CHECK(ex.inputs[0].delay.constant == 0.0025);
    CHECK(ex.outputs[2].delay.constant == -0.002);
    const tvid::ProblemDefinition d = tvid::problem_definition(ex);
    const std::vector<double>& t = ex.data.column("t");
    std::vector<double> u(1);
    for (std::size_t i = 0; i < t.size(); ++i) {
        std::size_t hint = 0;
        d.inputs.at(t[i], hint, u.data());
        INFO("sample " << i);
        CHECK(u[0] == Approx(std::min(0.5 * static_cast<double>(i) + 1.25, 50.0)).margin(1e-9));  // held at the end
        CHECK(d.measured[2][i] == Approx(std::max(1.0 + static_cast<double>(i) - 2.0, 1.0)).margin(1e-9));
    }
}

TEST_CASE("a delay of whole samples shifts a sine exactly, one past the recording is refused", "[experiment][channels]") {
    Scratch s;
    std::ostringstream csv;
    csv << "t,u,w,a,T\n";
    const auto sine = [](int i) { return std::sin(2 * std::numbers::pi * 7.0 * i / 1000.0); };
    for (int i = 0; i <= 400; ++i) csv << i << "e-3," << sine(i) << ",0,0," << sine(i) << '\n';
    s.dir.write("sine.csv", csv.str());
    std::vector<std::string> lines = with(kCustom, 3, "data: { file: sine.csv, time: t }");
    lines = with(lines, 15, "inputs: { T_in: { column: u, delay: 0.005 } }");
    const Experiment ex = s.load(lines);
    const tvid::ProblemDefinition d = tvid::problem_definition(ex);
    const std::vector<double>& recorded = ex.data.column("u");
    std::vector<double> u(1);
    for (std::size_t i = 0; i + 5 <= 400; ++i) {
        std::size_t hint = 0;
        d.inputs.at(ex.data.column("t")[i], hint, u.data());
        INFO("sample " << i);
        CHECK(u[0] == Approx(recorded[i + 5]).margin(1e-12));  // five samples on
        CHECK(recorded[i + 5] == Approx(sine(static_cast<int>(i) + 5)).margin(1e-5));  // the sine, as written
    }
    expect_error(with(kCustom, 15, "inputs: { T_in: { column: u, delay: 0.2 } }"), 15, "inputs.T_in.delay",
                 "past the recording");
}

TEST_CASE("an output's gain scales the quantity before its offset, and can be a parameter", "[experiment][channels]") {
    Scratch s;
    std::vector<std::string> lines = with(kCustom, 17, "  w_load:  { column: w, speed: load, gain: g_w, offset: 0.25 }");
    lines = inserted(lines, 27, "  g_w:  { init: 1.5, min: 0.5, max: 2 }");
    const Experiment ex = s.load(lines);
    const tvid::OutputSpec& o = ex.network.outputs.at(0);
    REQUIRE(o.gain.is_parameter());
    CHECK(ex.network.parameter_names.at(static_cast<std::size_t>(o.gain.parameter)) == "g_w");

    // Speed 2 rad/s at the load: y = 1.5 · 2 + 0.25 = 3.25, dy/dg = 2.
    tvid::NetworkModel<tvid::Dual> model(ex.network);
    const std::size_t m = ex.network.parameter_names.size();
    std::vector<tvid::Dual> p;
    for (std::size_t j = 0; j < m; ++j)
        p.push_back(tvid::Dual::variable(j == static_cast<std::size_t>(o.gain.parameter) ? 1.5 : 1.0,
                                         static_cast<int>(j), static_cast<int>(m)));
    model.set_parameters(p.data());
    const tvid::Dual x[4] = {0.0, 0.0, 0.0, 2.0};
    const double u[1] = {0.0};
    const tvid::Dual y = model.output(0, x, u);
    CHECK(y.value() == Approx(3.25));
    CHECK(y.derivative(o.gain.parameter) == Approx(2.0));

    expect_error(with(kCustom, 17, "  w_load:  { column: w, speed: load, gain: 0 }"), 17, "outputs.w_load.gain",
                 "removes the output");
}

TEST_CASE("an order torque is read with its order, amplitude and phase", "[experiment][network]") {
    Scratch s;
    const Experiment ex = s.load(inserted(
        kCustom, 14, "    - { type: order_torque, name: ripple, node: load, order: 0.5, amplitude: 2, phase: 0.3 }"));
    REQUIRE(ex.network.order_torques.size() == 1);
    const tvid::OrderTorqueSpec& e = ex.network.order_torques[0];
    CHECK(e.name == "ripple");
    CHECK(e.node == 1);
    CHECK(e.order == 0.5);
    CHECK(e.amplitude.constant == 2);
    CHECK(e.phase.constant == 0.3);
    tvid::ElementRef ref{};
    CHECK(ex.network.find_element("ripple", ref));
    CHECK(ref.kind == tvid::ElementKind::order_torque);
}

TEST_CASE("custom network errors name the line and the key", "[experiment][network]") {
    SECTION("an order that is not positive") {
        expect_error(inserted(kCustom, 14, "    - { type: order_torque, node: load, order: 0, amplitude: 2 }"), 15,
                     "model.elements[6].order", "positive");
    }
    SECTION("an order torque without its amplitude") {
        expect_error(inserted(kCustom, 14, "    - { type: order_torque, node: load, order: 1 }"), 15,
                     "model.elements[6].amplitude", "missing");
    }
    SECTION("side: on an element with one torque") {
        expect_error(with(kCustom, 19, "  T_shaft: { column: T, torque: shaft, side: output }"), 19,
                     "outputs.T_shaft.side", "same torque on both sides");
    }
    SECTION("side: on a speed output") {
        expect_error(with(kCustom, 17, "  w_load:  { column: w, speed: load, side: output }"), 17,
                     "outputs.w_load.side", "applies to a torque output");
    }
    SECTION("side: neither input nor output") {
        expect_error(with(kCustom, 19, "  T_shaft: { column: T, torque: stage, side: both }"), 19,
                     "outputs.T_shaft.side", "input");
    }
    SECTION("unknown node in between") {
        expect_error(with(kCustom, 10, "    - { type: spring_damper, name: shaft, between: [motor, lod], k: k_s }"), 10,
                     "model.elements[1].between", "no node named 'lod'");
    }
    SECTION("unknown node in node:") {
        expect_error(with(kCustom, 12, "    - { type: friction, name: bearing, node: lod, c: c_f }"), 12,
                     "model.elements[3].node", "no node named 'lod'");
    }
    SECTION("a gear mesh to ground") {
        expect_error(with(kCustom, 13, "    - { type: gear_mesh, name: stage, between: [motor, ground], ratio: 3, k: 5000, mu: 0.01, sigma: sig }"),
                     13, "model.elements[4].between", "ground");
    }
    SECTION("clearance fields on a gear mesh without mu") {
        expect_error(with(kCustom, 13, "    - { type: gear_mesh, name: stage, between: [motor, load], ratio: 3, k: 5000, sigma: sig }"),
                     13, "model.elements[4].sigma", "mu");
    }
    SECTION("an unknown element type") {
        expect_error(with(kCustom, 12, "    - { type: frictoin, name: bearing, node: load, c: c_f }"), 12,
                     "model.elements[3].type", "not one of");
    }
    SECTION("an unknown field of an element") {
        expect_error(with(kCustom, 12, "    - { type: friction, name: bearing, node: load, c: c_f, k: 1 }"), 12,
                     "model.elements[3].k", "unknown key");
    }
    SECTION("two elements with one name") {
        expect_error(with(kCustom, 12, "    - { type: friction, name: shaft, node: load, c: c_f }"), 12,
                     "model.elements[3].name", "already exists");
    }
    SECTION("two nodes with one name") {
        expect_error(with(kCustom, 7, "    - { name: motor, inverse_J: 20 }"), 7, "model.nodes[1].name", "already exists");
    }
    SECTION("a node with both J and inverse_J") {
        Scratch s;
        const auto file = s.write(with(kCustom, 7, "    - { name: load, J: 0.05, inverse_J: 20 }"));
        const auto e = load_error(file);
        REQUIRE(e.has_value());
        INFO(e->what());
        CHECK(e->line() == 7);
        CHECK(e->key().rfind("model.nodes[1].", 0) == 0);
        CHECK(contains(e->what(), "not both"));
        CHECK_FALSE(contains(e->what(), "missing"));
    }
    SECTION("a node with neither J nor inverse_J") {
        expect_error(with(kCustom, 7, "    - { name: load }"), 7, "model.nodes[1].J", "missing");
    }
    SECTION("a constant inertia that is not positive") {
        expect_error(with(kCustom, 7, "    - { name: load, J: 0 }"), 7, "model.nodes[1].J", "positive");
    }
    SECTION("an inertia parameter that may become negative") {
        expect_error(with(kCustom, 21, "  J_m:  { init: 0.1, min: -1, max: 1 }"), 21, "parameters.J_m.min",
                     "must be positive");
        expect_error(with(kCustom, 21, "  J_m:  { value: 0 }"), 21, "parameters.J_m.value", "must be positive");
    }
    SECTION("stiffness, damping and backlash cannot be negative") {
        expect_error(with(kCustom, 23, "  k_s:  { init: 1000, min: -10, max: 1.0e5 }"), 23, "parameters.k_s.min",
                     "cannot be negative: k_s is a stiffness");
        expect_error(with(kCustom, 25, "  c_f:  { init: 0.1, range: [-1, 1] }"), 25,
                     "parameters.c_f.range", "must not reach below 0");
        expect_error(with(kCustom, 24, "  mu_c: -0.002"), 24, "parameters.mu_c", "mu_c is a half backlash");
        expect_error(with(kCustom, 10, "    - { type: spring_damper, name: shaft, between: [motor, load], k: k_s, c: -0.5 }"),
                     10, "model.elements[1].c", "cannot be negative");
        expect_error(with(kCustom, 13, "    - { type: gear_mesh, name: stage, between: [motor, load], ratio: 3, k: -5000, c: 1, mu: 0.01, sigma: sig }"),
                     13, "model.elements[4].k", "cannot be negative");
        expect_error(with(kCustom, 13, "    - { type: gear_mesh, name: stage, between: [motor, load], ratio: 3, k: 5000, c: 1, mu: 0.01, sigma: 0 }"),
                     13, "model.elements[4].sigma", "must be positive");
    }
    SECTION("a gear ratio and an offset may be negative") {
        Scratch s;
        const Experiment ex = s.load(with(with(kCustom, 13, "    - { type: gear_mesh, name: stage, between: [motor, load], ratio: -3, k: 5000, c: 1, mu: 0.01, sigma: sig }"),
                                          22, "  d_in: { value: -0.5 }"));
        CHECK(ex.network.gear_meshes[0].ratio.constant == -3.0);
    }
    SECTION("the gear mesh's sigma parameter must be positive") {
        expect_error(with(kCustom, 26, "  sig:  { value: -2000 }"), 26, "parameters.sig.value", "positive");
    }
    SECTION("an output naming an unknown element") {
        expect_error(with(kCustom, 19, "  T_shaft: { column: T, torque: shaftt, offset: d_T }"), 19,
                     "outputs.T_shaft.torque", "no element named 'shaftt'");
    }
    SECTION("an output naming an unknown node") {
        expect_error(with(kCustom, 17, "  w_load:  { column: w, speed: lod }"), 17, "outputs.w_load.speed",
                     "no node named 'lod'");
    }
    SECTION("an output with two quantities") {
        Scratch s;
        const auto file = s.write(with(kCustom, 17, "  w_load:  { column: w, speed: load, angle: load }"));
        const auto e = load_error(file);
        REQUIRE(e.has_value());
        INFO(e->what());
        CHECK(e->line() == 17);
        CHECK(e->key().rfind("outputs.w_load.", 0) == 0);
        CHECK(contains(e->what(), "exactly one"));
        CHECK_FALSE(contains(e->what(), "missing"));
    }
    SECTION("an output with no quantity") {
        expect_error(with(kCustom, 17, "  w_load:  { column: w }"), 17, "outputs.w_load.speed", "missing");
    }
    SECTION("an output's column not in the CSV") {
        expect_error(with(kCustom, 17, "  w_load:  { column: omega, speed: load }"), 17, "outputs.w_load.column",
                     "no column 'omega'");
    }
    SECTION("a parameter declared but not used") {
        expect_error(inserted(kCustom, 27, "  extra: { value: 1 }"), 28, "parameters.extra", "not used");
    }
    SECTION("a field naming an undeclared parameter") {
        expect_error(with(kCustom, 10, "    - { type: spring_damper, name: shaft, between: [motor, load], k: k_shaft }"),
                     10, "model.elements[1].k", "'k_shaft'");
        expect_error(with(kCustom, 6, "    - { name: motor, J: J_motor }"), 6, "model.nodes[0].J", "'J_motor'");
        expect_error(with(kCustom, 19, "  T_shaft: { column: T, torque: shaft, offset: d_X }"), 19,
                     "outputs.T_shaft.offset", "'d_X'");
    }
    SECTION("a model input not bound to a column") {
        expect_error(with(kCustom, 15, "inputs: { T_inn: u }"), 15, "inputs.T_inn", "did you mean 'T_in'");
    }
    SECTION("a network with no torque input") {
        std::vector<std::string> lines = kCustom;
        lines.erase(lines.begin() + 8);  // the torque element (line 9)
        Scratch s;
        const auto file = s.write(lines);
        const auto e = load_error(file);
        REQUIRE(e.has_value());
        INFO(e->what());
        CHECK(e->key() == "model.elements");
        CHECK(contains(e->what(), "torque"));
    }
}

TEST_CASE("a speed source, a speed controller and a steady start are read with their keys", "[experiment][network]") {
    Scratch s;
    SECTION("a speed source on a channel reads the channel's slope too") {
        const Experiment ex = s.load(with(inserted(kCustom, 14, "    - { type: speed_source, name: spin, node: motor, input: w_in, scale: 2 }"),
                                          16, "inputs: { T_in: u, w_in: w }"));
        REQUIRE(ex.network.speed_sources.size() == 1);
        const tvid::SpeedSourceSpec& e = ex.network.speed_sources[0];
        CHECK(e.node == 0);
        CHECK(e.input == ex.network.input_index("w_in"));
        CHECK(e.scale.constant == 2);
        CHECK(ex.network.input_rates == std::vector<int>{e.input});
        CHECK(e.rate == static_cast<int>(ex.network.input_names.size()));  // after every input
        const tvid::ProblemDefinition d = tvid::problem_definition(ex);
        CHECK(d.inputs.count() == ex.network.input_names.size() + 1);
    }
    SECTION("a PI controller is a reference node, its speed source and a spring-damper") {
        // Without the stop and the mount to ground: a line held to ground has no steady motion.
        const Experiment ex = s.load(with(with(with(
            inserted(kCustom, 14, "    - { type: speed_controller, name: pi, node: load, setpoint: 40, kp: 0.2, ki: 3 }"), 31,
            "initial_state: { kind: steady, node: motor, speed: w, samples: 5 }"), 14, ""), 11, kStopBetweenNodes));
        REQUIRE(ex.network.nodes.size() == 3);
        CHECK(ex.network.nodes[2].name == "pi.reference");
        REQUIRE(ex.network.speed_sources.size() == 1);
        CHECK(ex.network.speed_sources[0].name == "pi.setpoint");
        CHECK(ex.network.speed_sources[0].node == 2);
        CHECK(ex.network.speed_sources[0].input == -1);
        CHECK(ex.network.speed_sources[0].speed.constant == 40);
        const tvid::SpringDamperSpec& pi = ex.network.spring_dampers.back();
        CHECK(pi.name == "pi");
        CHECK(pi.a == 2);
        CHECK(pi.b == 1);
        CHECK(pi.k.constant == 3);    // ki: the integral's stiffness
        CHECK(pi.c.constant == 0.2);  // kp
        CHECK(ex.initial_state == tvid::InitialStateKind::steady);
        CHECK(ex.steady.node == 0);
        CHECK(ex.steady.speed_column == "w");
        CHECK(ex.steady.samples == 5);
    }
    SECTION("a steady start at a constant speed") {
        const Experiment ex =
            s.load(with(with(with(kCustom, 30, "initial_state: { kind: steady, node: load, speed: 12.5 }"), 14, ""), 11, kStopBetweenNodes));
        CHECK(ex.steady.node == 1);
        CHECK(ex.steady.speed == 12.5);
        CHECK(ex.steady.speed_column.empty());
        CHECK(ex.steady.samples == 0);
    }
}

TEST_CASE("speed sources, controllers and steady starts refuse bad keys naming the line", "[experiment][network]") {
    const std::string spin = "    - { type: speed_source, name: spin, node: motor, input: w_in }";
    const auto with_spin = [&](const std::string& start) {
        return with(with(inserted(kCustom, 14, spin), 16, "inputs: { T_in: u, w_in: w }"), 31, start);
    };
    SECTION("both a channel and a constant speed") {
        expect_error(inserted(kCustom, 14, "    - { type: speed_source, node: motor, input: w_in, speed: 3 }"), 15,
                     "model.elements[6].speed", "either input");
    }
    SECTION("two speed sources on one node") {
        expect_error(inserted(with_spin("initial_state: rest"), 15,
                              "    - { type: speed_source, name: spin2, node: motor, speed: 3 }"),
                     16, "model.elements[7].node", "already has its speed prescribed by 'spin'");
    }
    SECTION("a negative controller gain") {
        expect_error(inserted(kCustom, 14, "    - { type: speed_controller, node: load, setpoint: 40, kp: -1, ki: 3 }"),
                     15, "model.elements[6].kp", "cannot be negative");
    }
    SECTION("a speed source cannot start from a static equilibrium") {
        expect_error(with_spin("initial_state: equilibrium"), 31, "initial_state", "a speed source turns its node");
    }
    SECTION("a steady start without its node") {
        expect_error(with(kCustom, 30, "initial_state: { kind: steady, speed: w }"), 30, "initial_state.node", "missing");
    }
    SECTION("a steady start on a column that is not there") {
        expect_error(with(kCustom, 30, "initial_state: { kind: steady, node: motor, speed: wx }"), 30,
                     "initial_state.speed", "no column named 'wx'");
    }
    SECTION("a steady start on a line held to ground") {
        expect_error(with(kCustom, 30, "initial_state: { kind: steady, node: load, speed: 0 }"), 30,
                     "initial_state.kind", "held to ground by 'mount' (node motor to ground)");
    }
    SECTION("steady written as a word") {
        expect_error(with(kCustom, 30, "initial_state: steady"), 30, "initial_state", "needs its node and speed");
    }
}

TEST_CASE("an output's weight, detrend and high-pass are read, and bad ones refused naming the key", "[experiment][network]") {
    Scratch s;
    SECTION("read") {
        const Experiment ex = s.load(with(kCustom, 17, "  w_load:  { column: w, speed: load, weight: 2.5, detrend: linear, highpass: 3 }"));
        CHECK(ex.outputs[0].weight == 2.5);
        CHECK(ex.outputs[0].scoring.detrend == tvid::Detrend::linear);
        CHECK(ex.outputs[0].scoring.highpass == 3.0);
        CHECK(ex.outputs[1].weight == 1.0);
        CHECK_FALSE(ex.outputs[1].scoring.active());
    }
    SECTION("a weight that is not positive") {
        expect_error(with(kCustom, 17, "  w_load:  { column: w, speed: load, weight: 0 }"), 17, "outputs.w_load.weight",
                     "positive");
    }
    SECTION("an unknown detrend") {
        expect_error(with(kCustom, 17, "  w_load:  { column: w, speed: load, detrend: quadratic }"), 17,
                     "outputs.w_load.detrend", "not one of");
    }
    SECTION("a cut-off past the Nyquist frequency") {
        expect_error(with(kCustom, 17, "  w_load:  { column: w, speed: load, highpass: 600 }"), 17,
                     "outputs.w_load.highpass", "Nyquist frequency, 500 Hz");
    }
    SECTION("a weight on an input") {
        expect_error(with(kCustom, 15, "inputs: { T_in: { column: u, weight: 2 } }"), 15, "inputs.T_in.weight",
                     "unknown key");
    }
}

}  // namespace TVID_UNITY_ID
