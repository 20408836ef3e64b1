// Loading engine experiments: crank-angle data, cycle windows, the measured initial
// state, and the checks that come with them.
#include <catch2/catch.hpp>
#include <cmath>
#include <regex>
#include <sstream>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;
using tvid::test::TempDir;

namespace {

const std::filesystem::path kEngine = source_dir() / "configs/engine_idle.yaml";

// Three 720° cycles of a 4-cylinder engine sampled every `step_deg`, angle optionally wrapped.
std::string engine_csv(double step_deg, bool wrapped, double pressure_bar = 1.0) {
    std::ostringstream s;
    s << "t,crank_deg,p_cyl1,p_cyl2,p_cyl3,p_cyl4,omega_dw,omega_fw\n";
    const double omega_deg = 130.0 * 180.0 / 3.14159265358979;
    for (int i = 0; i * step_deg <= 3 * 720.0 + 1e-9; ++i) {
        const double deg = i * step_deg;
        const double shown = wrapped ? std::fmod(deg, 720.0) : deg;
        s << deg / omega_deg << ',' << shown;
        for (int c = 0; c < 4; ++c) s << ',' << pressure_bar;
        s << ",130,130\n";
    }
    return s.str();
}

// The shipped engine experiment pointed at `csv` with 2 windows over 3 cycles.
std::filesystem::path engine_yaml(const TempDir& tmp, const std::string& csv, const std::string& extra = "") {
    tmp.write("rec.csv", csv);
    std::string yaml = tvid::test::read_text(kEngine);
    yaml = std::regex_replace(yaml, std::regex(R"(file: \.\./data/engine/idle\.csv)"), "file: rec.csv");
    yaml = std::regex_replace(yaml, std::regex(R"(estimation: \[ \{ cycle: 2 \} \])"), "estimation: [ { cycle: 1 } ]");
    yaml = std::regex_replace(yaml, std::regex(R"(validation: \[[^\]]*\])"), "validation: [ { cycle: 2 } ]");
    yaml = std::regex_replace(yaml, std::regex(R"(warmup: \{ cycles: 2 \})"), "warmup: { cycles: 1 }");
    return tmp.write("exp.yaml", yaml + extra);
}

InputError load_error(const std::filesystem::path& file, const std::vector<Override>& overrides = {}) {
    try {
        load_experiment(file, overrides);
    } catch (const InputError& e) {
        return e;
    }
    FAIL("expected an InputError");
    throw std::logic_error("unreachable");
}

}  // namespace

TEST_CASE("the shipped engine experiment resolves cycles, inputs and its initial state", "[engine][loader]") {
    const Experiment ex = load_experiment(kEngine);
    CHECK(ex.network.preset == "engine_block");
    CHECK(ex.angle_column == "crank_deg");
    CHECK(ex.network.nodes[static_cast<std::size_t>(ex.angle_node)].name == "flywheel");
    CHECK(ex.initial_state == InitialStateKind::measured);
    CHECK(ex.warmup_cycles == 2);
    REQUIRE(ex.inputs.size() == 4);
    for (const ChannelBinding& in : ex.inputs) {
        CHECK(in.by_angle);
        CHECK(in.scale == 1e5);  // bar
    }
    // 0.5° samples from crank angle 0: cycle 2 spans samples 2880 … 4320, its warm-up starts 2 cycles earlier.
    REQUIRE(ex.estimation.size() == 1);
    CHECK(ex.estimation[0].first == 2880);
    CHECK(ex.estimation[0].last == 4320);
    CHECK(ex.estimation[0].start == 0);
    CHECK(ex.estimation[0].label == "cycle 2");
    CHECK(ex.validation.size() == 6);
    CHECK(ex.crank_angle[2880] == Approx(8 * 3.14159265358979));  // 1440°
}

TEST_CASE("a wrapped crank angle is made cumulative", "[engine][loader]") {
    TempDir tmp;
    const Experiment ex = load_experiment(engine_yaml(tmp, engine_csv(1.0, true)));
    CHECK(ex.crank_angle.back() == Approx(3 * 720.0 * 3.14159265358979 / 180.0));
    CHECK(ex.estimation[0].first == 720);
    CHECK(ex.estimation[0].last == 1440);
}

TEST_CASE("engine loading errors name the line and the key", "[engine][loader]") {
    TempDir tmp;
    SECTION("a cycle outside the recording") {
        const InputError e = load_error(engine_yaml(tmp, engine_csv(1.0, false)), {{"windows.validation.0.cycle", "3"}});
        CHECK(e.key() == "windows.validation[0].cycle");
        CHECK(std::string(e.what()).find("cycles 0 … 2") != std::string::npos);
    }
    SECTION("a crank angle that does not advance") {
        std::string csv = engine_csv(1.0, false);
        csv = std::regex_replace(csv, std::regex(R"(\n([0-9.e-]+),5,)"), "\n$1,4,");  // sample at 5° reads 4°
        const InputError e = load_error(engine_yaml(tmp, csv));
        CHECK(e.key() == "column crank_deg");
        CHECK(e.line() == 7);
        CHECK(std::string(e.what()).find("does not advance") != std::string::npos);
    }
    SECTION("a pressure in bar read as pascal") {
        const auto file = engine_yaml(tmp, engine_csv(1.0, false));
        const InputError e = load_error(file, {{"inputs.p_cyl2", "p_cyl2"}});
        CHECK(e.key() == "inputs.p_cyl2");
        CHECK(std::string(e.what()).find("set unit") != std::string::npos);
    }
    SECTION("a pressure in kPa read as bar, or in bar read as MPa") {
        const auto file = engine_yaml(tmp, engine_csv(1.0, false));
        const InputError kpa = load_error(file, {{"inputs.p_cyl3.unit", "MPa"}});  // 1 bar read as 1 MPa
        CHECK(kpa.key() == "inputs.p_cyl3");
        CHECK(kpa.line() == 25);
        CHECK(std::string(kpa.what()).find("set unit: bar") != std::string::npos);
        TempDir high;
        const InputError e = load_error(engine_yaml(high, engine_csv(1.0, false, 100.0)));  // 100 kPa as bar
        CHECK(e.key() == "inputs.p_cyl1");
        CHECK(std::string(e.what()).find("10000000 … 10000000 Pa") != std::string::npos);
        CHECK(std::string(e.what()).find("the numbers fit kPa") != std::string::npos);
    }
    SECTION("a negative pressure is not absolute") {
        const InputError e = load_error(engine_yaml(tmp, engine_csv(1.0, false, -0.5)));
        CHECK(e.key() == "inputs.p_cyl1");
        CHECK(std::string(e.what()).find("not an absolute cylinder pressure") != std::string::npos);
        CHECK(std::string(e.what()).find("check the column") != std::string::npos);  // no unit makes it fit
    }
    SECTION("a negative reciprocating mass or friction") {
        const auto file = engine_yaml(tmp, engine_csv(1.0, false));
        const InputError m = load_error(file, {{"parameters.m.min", "-1"}});
        CHECK(m.key() == "parameters.m.min");
        CHECK(std::string(m.what()).find("cannot be negative: m is a reciprocating mass") != std::string::npos);
        const InputError c = load_error(file, {{"parameters.C2", "-0.01"}});
        CHECK(c.key() == "parameters.C2");
        CHECK(std::string(c.what()).find("C2 is a friction coefficient") != std::string::npos);
        // Zero is a valid mass and damping (the bounds of the shipped experiment start there).
        CHECK_NOTHROW(load_experiment(file, {{"parameters.m", "0"}, {"parameters.C21", "0"}}));
    }
    SECTION("an engine cannot start from a static equilibrium") {
        std::string yaml = tvid::test::read_text(engine_yaml(tmp, engine_csv(1.0, false)));
        yaml = std::regex_replace(yaml, std::regex("initial_state: measured"), "initial_state: equilibrium");
        const InputError e = load_error(tmp.write("equilibrium.yaml", yaml));
        CHECK(e.key() == "initial_state");
        CHECK(std::string(e.what()).find("measured") != std::string::npos);
    }
    SECTION("cylinder pressures need the crank-angle channel") {
        std::string yaml = tvid::test::read_text(engine_yaml(tmp, engine_csv(1.0, false)));
        yaml = std::regex_replace(yaml, std::regex(R"(\n  angle: crank_deg[^\n]*)"), "");
        const InputError e = load_error(tmp.write("no_angle.yaml", yaml));
        CHECK(e.key() == "data.angle");
    }
    SECTION("a free parameter whose bounds meet") {
        const InputError e = load_error(engine_yaml(tmp, engine_csv(1.0, false)), {{"parameters.J1.min", "0.0054"},
                                                                                   {"parameters.J1.max", "0.0054"}});
        CHECK(e.key() == "parameters.J1.max");
        CHECK(std::string(e.what()).find("min equals max") != std::string::npos);
    }
}

TEST_CASE("a custom cylinder is checked and its torque can be an output", "[engine][loader]") {
    TempDir tmp;
    tmp.write("rec.csv", engine_csv(1.0, false, 5.0));
    auto yaml = [](const std::string& rod) {
        return "tvid: 1\n"
               "data: { file: rec.csv, time: t, angle: crank_deg, angle_node: crank }\n"
               "model:\n"
               "  nodes: [ { name: crank, J: 0.1 } ]\n"
               "  elements:\n"
               "    - { type: cylinder, name: cyl, node: crank, pressure: p, bore: 0.08, crank_radius: 0.04, rod_length: " +
               rod +
               ", mass: 0.4 }\n"
               "    - { type: friction, name: f, node: crank, c: c }\n"
               "inputs: { p: { column: p_cyl1, unit: bar } }\n"
               "outputs:\n"
               "  w: { column: omega_fw, speed: crank }\n"
               "  T: { column: omega_dw, torque: cyl }\n"
               "parameters: { c: { init: 0.1, min: 0.01, max: 1 } }\n"
               "windows: { estimation: [ { cycle: 1 } ], warmup: { cycles: 1 } }\n"
               "estimation: { optimizer: lm, cost: l2 }\n";
    };
    const Experiment ex = load_experiment(tmp.write("ok.yaml", yaml("0.13")));
    CHECK(ex.network.cylinders.size() == 1);
    CHECK(ex.network.outputs[1].element.kind == ElementKind::cylinder);
    CHECK(ex.initial_state == InitialStateKind::measured);
    const InputError e = load_error(tmp.write("bad.yaml", yaml("0.03")));
    CHECK(e.key() == "model.elements[0].rod_length");
    CHECK(e.line() == 6);
}

}  // namespace TVID_UNITY_ID
