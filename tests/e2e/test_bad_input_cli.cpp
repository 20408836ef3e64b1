// More bad input through the binary: broken files, not just broken keys. Each is exit
// status 2, exactly one line on stderr "FILE:LINE: key: what is wrong" naming the file
// at fault (the experiment or the CSV), and no report directory left behind.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/shipped_fit.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;

namespace {

// A valid experiment over rec.csv; line numbers in the file are index + 1.
const std::vector<std::string> kExperiment = {
    "tvid: 1",                                                             // 1
    "name: bad-input",                                                     // 2
    "data:",                                                               // 3
    "  file: rec.csv",                                                     // 4
    "  time: t",                                                           // 5
    "model:",                                                              // 6
    "  preset: cvt_clearance",                                             // 7
    "inputs: { Ttm: Ttm }",                                                // 8
    "outputs: { Tds: Tds }",                                               // 9
    "parameters:",                                                         // 10
    "  rho1:    { init: 1.5, min: 0.1, max: 10, range: [1, 2] }",          // 11
    "  k_minus: { init: 3000, min: 1, max: 1.0e6 }",                       // 12
    "  k_plus:  { init: 8000, min: 1, max: 1.0e6 }",                       // 13
    "  c_minus: { init: 4, min: 0, max: 100 }",                            // 14
    "  c_plus:  { init: 19, min: 0, max: 100 }",                           // 15
    "  mu:      { init: 0.0035, min: 0, max: 0.1 }",                       // 16
    "  sigma:   { value: 1132.81, fixed: true }",                          // 17
    "  d_ds:    { init: -7, min: -100, max: 100 }",                        // 18
    "  d_tm:    { init: 13, min: -100, max: 100 }",                        // 19
    "windows:",                                                            // 20
    "  estimation: [ { time: [0.002, 0.008] } ]",                          // 21
    "estimation:",                                                         // 22
    "  pso: { start: latin_hypercube, particles: 4, iterations: 3 }",      // 23
};

// t = 0 … 0.010 s at 1 kHz.
std::string recording(char sep = ',') {
    std::ostringstream s;
    s << "t" << sep << "Ttm" << sep << "Tds\n";
    for (int i = 0; i <= 10; ++i) s << i * 0.001 << sep << 10 + i << sep << -5 + i << '\n';
    return s.str();
}

std::string join(const std::vector<std::string>& lines) {
    std::string s;
    for (const auto& l : lines) s += l + "\n";
    return s;
}

std::vector<std::string> with(std::vector<std::string> lines, int line, const std::string& text) {
    lines.at(static_cast<std::size_t>(line - 1)) = text;
    return lines;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

struct Run {
    TempDir tmp;
    std::filesystem::path exp, csv, out;
    RunResult result;

    Run(const std::string& experiment_text, const std::string& csv_text, std::vector<std::string> extra = {},
        const std::string& command = "fit") {
        csv = tmp.write("rec.csv", csv_text);
        exp = tmp.write("exp.yaml", experiment_text);
        out = tmp.path() / "out";
        std::vector<std::string> args{command, exp.string(), "-o", out.string()};
        if (command == "batch") args.insert(args.end(), {"--data", csv.string()});
        args.insert(args.end(), extra.begin(), extra.end());
        result = run_tvid(args);
    }
};

// A four-cylinder engine-block experiment over rec.csv: one engine cycle at 130 rad/s
// sampled every 5 deg of crank angle, pressures in bar (lines: index + 1).
const std::vector<std::string> kEngineExperiment = {
    "tvid: 1",                                                             // 1
    "name: engine-bad-input",                                              // 2
    "data: { file: rec.csv, time: t, angle: crank_deg }",                  // 3
    "model:",                                                              // 4
    "  preset: engine_block",                                              // 5
    "  bore: 0.079",                                                       // 6
    "  crank_radius: 0.0405",                                              // 7
    "  rod_length: 0.129",                                                 // 8
    "  K21: 8.0e4",                                                        // 9
    "  Kxx: 3.0e5",                                                        // 10
    "  K32: 2.0e5",                                                        // 11
    "inputs:",                                                             // 12
    "  p_cyl1: { column: p1, unit: bar }",                                 // 13
    "  p_cyl2: { column: p2, unit: bar }",                                 // 14
    "  p_cyl3: { column: p3, unit: bar }",                                 // 15
    "  p_cyl4: { column: p4, unit: bar }",                                 // 16
    "outputs: { omega_dw: omega }",                                        // 17
    "parameters:",                                                         // 18
    "  J1:  { init: 0.0054,  min: 1.0e-4, max: 0.05 }",                    // 19
    "  J2:  { init: 0.00096, min: 1.0e-4, max: 0.01 }",                    // 20
    "  J3:  { init: 0.144,   min: 0.01,   max: 1.0 }",                     // 21
    "  m:   { init: 0.36,    min: 0,      max: 2.0 }",                     // 22
    "  C1:  { init: 0.012,   min: 0,      max: 1.0 }",                     // 23
    "  C2:  { init: 0.016,   min: 0,      max: 1.0 }",                     // 24
    "  C3:  { init: 0.030,   min: 0,      max: 1.0 }",                     // 25
    "  C21: { init: 3.0,     min: 0,      max: 50 }",                      // 26
    "  C32: { init: 3.2,     min: 0,      max: 50 }",                      // 27
    "  Cxx: { init: 1.8,     min: 0,      max: 50 }",                      // 28
    "windows: { estimation: [ { cycle: 0 } ] }",                           // 29
    "simulation: { method: rk4, step: 1.0e-5 }",                           // 30
    "estimation: { cost: l2, optimizer: lm, lm: { max_iterations: 1 } }",  // 31
};

// One 720 deg cycle; each cylinder's pressure peaks near 30 bar at its firing TDC. The
// sample at `stuck_row` (data row, 0-based) repeats the previous crank angle when >= 0.
std::string engine_recording(int stuck_row = -1) {
    std::ostringstream s;
    s << "t,crank_deg,p1,p2,p3,p4,omega\n";
    const double deg_per_s = 130.0 * 180.0 / 3.14159265358979;
    for (int i = 0; i <= 144; ++i) {
        const double deg = 5.0 * i;
        s << deg / deg_per_s << ',' << (i == stuck_row ? deg - 5.0 : deg);
        for (int k : {0, 2, 3, 1}) {  // firing order 1-3-4-2: cylinder k fires at its slot × 180 deg
            const double from_tdc = std::fmod(deg - 180.0 * k + 720.0, 720.0);
            const double d = std::min(from_tdc, 720.0 - from_tdc);
            s << ',' << 1.0 + 29.0 * std::exp(-d * d / 800.0);
        }
        s << ",130\n";
    }
    return s.str();
}

// Exit 2, one line on stderr starting "FILE:LINE: ", naming `what`; no report directory.
void check_one_line_error(const Run& r, const std::filesystem::path& file, int line,
                          const std::vector<std::string>& mentions) {
    const std::string& err = r.result.err;
    INFO("stderr: " << err);
    CHECK(r.result.exit_code == 2);
    CHECK(std::count(err.begin(), err.end(), '\n') == 1);
    CHECK((!err.empty() && err.back() == '\n'));
    CHECK(err.rfind(file.string() + ":" + std::to_string(line) + ": ", 0) == 0);
    for (const std::string& m : mentions) CHECK(contains(err, m));
    CHECK(r.result.out.empty());
    CHECK_FALSE(std::filesystem::exists(r.out));
}

}  // namespace

TEST_CASE("broken experiment files exit 2 with one line naming the file and line", "[e2e][errors]") {
    SECTION("an empty file") {
        const Run r("", recording());
        check_one_line_error(r, r.exp, 1, {"empty"});
    }
    SECTION("a file of comments only") {
        const Run r("# tvid: 1\n\n# nothing else\n", recording());
        check_one_line_error(r, r.exp, 1, {"empty"});
    }
    SECTION("binary garbage") {
        const std::string garbage("abc\n\x89PNG\r\n\x1a\n\0\0\0\rIHDR\xff\xfe", 22);
        const Run r(garbage, recording());
        check_one_line_error(r, r.exp, 3, {"not a text file"});
    }
    SECTION("a YAML syntax error") {
        const Run r(join(with(kExperiment, 5, "  time: t: x")), recording());
        check_one_line_error(r, r.exp, 5, {"YAML syntax error"});
    }
    SECTION("a duplicate key") {
        std::vector<std::string> lines = kExperiment;
        lines.insert(lines.begin() + 5, "  file: other.csv");  // line 6, a second data.file
        const Run r(join(lines), recording());
        check_one_line_error(r, r.exp, 6, {"data.file", "duplicate"});
    }
    SECTION("a duplicate parameter") {
        std::vector<std::string> lines = kExperiment;
        lines.insert(lines.begin() + 19, "  rho1:    { init: 2, min: 0.1, max: 10 }");  // line 20
        const Run r(join(lines), recording());
        check_one_line_error(r, r.exp, 20, {"parameters.rho1", "duplicate"});
    }
}

TEST_CASE("bad parameter and window settings exit 2 naming the key", "[e2e][errors]") {
    SECTION("a free parameter without bounds or range under the particle swarm") {
        const Run r(join(with(kExperiment, 12, "  k_minus: { init: 3000 }")), recording());
        check_one_line_error(r, r.exp, 12, {"parameters.k_minus", "range"});
    }
    SECTION("a range outside the bounds") {
        const Run r(join(with(kExperiment, 11, "  rho1:    { init: 1.5, min: 0.1, max: 10, range: [1, 20] }")),
                    recording());
        check_one_line_error(r, r.exp, 11, {"parameters.rho1.range", "outside the bounds"});
    }
    SECTION("a window holding no sample") {
        const Run r(join(with(kExperiment, 21, "  estimation: [ { time: [0.0031, 0.0039] } ]")), recording());
        check_one_line_error(r, r.exp, 21, {"windows.estimation[0].time", "fewer than two samples"});
    }
    SECTION("an empty list of windows") {
        const Run r(join(with(kExperiment, 21, "  estimation: []")), recording());
        check_one_line_error(r, r.exp, 21, {"windows.estimation", "at least one window"});
    }
    SECTION("a bad value from --set is reported as --set") {
        const Run r(join(kExperiment), recording(), {"--set", "parameters.rho1.range=[1, 20]"});
        const std::string& err = r.result.err;
        INFO(err);
        CHECK(r.result.exit_code == 2);
        CHECK(std::count(err.begin(), err.end(), '\n') == 1);
        CHECK(err.rfind("--set: parameters.rho1.range: ", 0) == 0);
        CHECK_FALSE(std::filesystem::exists(r.out));
    }
}

TEST_CASE("bad CSV data exit 2 naming the data file, line and column", "[e2e][errors]") {
    SECTION("semicolon-separated") {
        const Run r(join(kExperiment), "# exported by a spreadsheet\n" + recording(';'));
        check_one_line_error(r, r.csv, 2, {"';'", "','"});
    }
    SECTION("tab-separated") {
        const Run r(join(kExperiment), recording('\t'));
        check_one_line_error(r, r.csv, 1, {"tab", "','"});
    }
    SECTION("NaN in a channel") {
        const Run r(join(kExperiment), "t,Ttm,Tds\n0,10,-5\n0.001,11,-4\n0.002,12,-3\n0.003,NaN,-2\n0.004,14,-1\n");
        check_one_line_error(r, r.csv, 5, {"column Ttm", "not finite"});
    }
    SECTION("a data file that does not exist") {
        const Run r(join(with(kExperiment, 4, "  file: recording_missing.csv")), recording());
        check_one_line_error(r, r.exp, 4, {"data.file", "recording_missing.csv"});
    }
}

TEST_CASE("broken CSV files exit 2 naming the data file and the line", "[e2e][errors]") {
    SECTION("an empty data file") {
        const Run r(join(kExperiment), "");
        check_one_line_error(r, r.csv, 1, {"file is empty"});
    }
    SECTION("a data file of comments only") {
        const Run r(join(kExperiment), "# channels: t, Ttm, Tds\n\n");
        check_one_line_error(r, r.csv, 1, {"no header row"});
    }
    SECTION("binary data in the recording") {
        const Run r(join(kExperiment), recording() + std::string("0.011,\0\x01\x02,3\n", 12));
        check_one_line_error(r, r.csv, 13, {"not text"});
    }
    SECTION("inf in a channel") {
        const Run r(join(kExperiment), "t,Ttm,Tds\n0,10,-5\n0.001,11,-4\n0.002,12,inf\n0.003,13,-2\n");
        check_one_line_error(r, r.csv, 4, {"column Tds", "not finite"});
    }
    SECTION("-inf in the time column") {
        const Run r(join(kExperiment), "t,Ttm,Tds\n0,10,-5\n-inf,11,-4\n0.002,12,-3\n");
        check_one_line_error(r, r.csv, 3, {"column t", "not finite"});
    }
    SECTION("a time column the experiment names but the file lacks") {
        const Run r(join(with(kExperiment, 5, "  time: time_s")), recording());
        check_one_line_error(r, r.exp, 5, {"data.time", "no column 'time_s'"});
    }
}

TEST_CASE("bad engine recordings exit 2 naming the line and the column or key", "[e2e][errors]") {
    SECTION("the experiment and recording are good") {  // so that each case below fails for its one reason
        const Run r(join(kEngineExperiment), engine_recording(), {}, "simulate");
        INFO(r.result.err);
        CHECK(r.result.exit_code == 0);
        CHECK(r.result.err.empty());
    }
    SECTION("a crank angle that does not advance") {
        const Run r(join(kEngineExperiment), engine_recording(40));  // data row 40 is line 42
        check_one_line_error(r, r.csv, 42, {"column crank_deg", "does not advance", "195 deg after 195 deg"});
    }
    SECTION("a pressure recorded in bar read as pascal") {
        const Run r(join(with(kEngineExperiment, 14, "  p_cyl2: p2")), engine_recording());
        check_one_line_error(r, r.exp, 14, {"inputs.p_cyl2", "not an absolute cylinder pressure", "set unit: bar"});
    }
    SECTION("a pressure recorded in bar read as kPa") {
        const Run r(join(with(kEngineExperiment, 16, "  p_cyl4: { column: p4, unit: kPa }")), engine_recording());
        check_one_line_error(r, r.exp, 16, {"inputs.p_cyl4", "not an absolute cylinder pressure", "set unit: bar"});
    }
    SECTION("a negative reciprocating mass") {
        const Run r(join(with(kEngineExperiment, 22, "  m:   { init: 0.36,    min: -1,     max: 2.0 }")),
                    engine_recording());
        check_one_line_error(r, r.exp, 22, {"parameters.m.min", "cannot be negative", "reciprocating mass"});
    }
    SECTION("a zero inertia") {
        const Run r(join(with(kEngineExperiment, 21, "  J3: 0")), engine_recording());
        check_one_line_error(r, r.exp, 21, {"parameters.J3", "must be positive", "an inertia"});
    }
    SECTION("a cycle window outside the recording") {
        const Run r(join(with(kEngineExperiment, 29, "windows: { estimation: [ { cycle: 1 } ] }")), engine_recording());
        check_one_line_error(r, r.exp, 29, {"windows.estimation[0].cycle"});
    }
}

TEST_CASE("simulate, validate, sensitivity and batch refuse bad input as fit does", "[e2e][errors]") {
    const std::string min_above_max = join(with(kExperiment, 14, "  c_minus: { init: 4, min: 50, max: 10 }"));
    const std::string inf_recording = "t,Ttm,Tds\n0,10,-5\n0.001,inf,-4\n0.002,12,-3\n";
    for (const char* command : {"simulate", "sensitivity", "batch"}) {
        SECTION(std::string(command) + ": min > max") {
            const Run r(min_above_max, recording(), {}, command);
            check_one_line_error(r, r.exp, 14, {"parameters.c_minus.min", "greater than max"});
        }
        SECTION(std::string(command) + ": an unknown key") {
            const Run r(join(with(kExperiment, 5, "  tiem: t")), recording(), {}, command);
            check_one_line_error(r, r.exp, 5, {"data.tiem", "did you mean 'time'"});
        }
    }
    for (const char* command : {"simulate", "sensitivity"}) {
        SECTION(std::string(command) + ": inf in a channel") {
            const Run r(join(kExperiment), inf_recording, {}, command);
            check_one_line_error(r, r.csv, 3, {"column Ttm", "not finite"});
        }
    }
    SECTION("validate: a window outside the data") {
        TempDir tmp;
        tmp.write("rec.csv", recording());
        const auto exp = tmp.write("exp.yaml", join(with(kExperiment, 21, "  estimation: [ { time: [0.002, 0.5] } ]")));
        const auto params = tmp.write("p.json", "{ \"rho1\": 1.5 }");
        const RunResult r = run_tvid({"validate", exp.string(), "--params", params.string()});
        INFO(r.err);
        CHECK(r.exit_code == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK(r.err.rfind(exp.string() + ":21: windows.estimation[0].time: ", 0) == 0);
        CHECK(r.out.empty());
    }
    SECTION("batch: a bad recording among good ones is that job's bad input, with the file, line and column") {
        TempDir tmp;
        const auto good = tmp.write("rec.csv", recording());
        const auto bad = tmp.write("rec_inf.csv", inf_recording);
        const auto exp = tmp.write("exp.yaml", join(kExperiment));
        const auto out = tmp.path() / "out";
        const RunResult r = run_tvid({"batch", exp.string(), "--data", good.string(), "--data", bad.string(), "-o",
                                      out.string(), "--quiet", "--threads", "1"});
        INFO(r.err);
        CHECK(r.exit_code == 1);  // it ran; one job did not succeed
        const std::string table = read_text(out / "batch.csv");
        CHECK(contains(table, "rec_inf,bad_input," + bad.string() + ":3: column Ttm: value is not finite (inf)"));
        CHECK(contains(table, "\nrec,ok,"));
    }
}

TEST_CASE("a CSV file with a UTF-8 byte-order mark is read", "[e2e]") {
    const Run r(join(kExperiment), "\xEF\xBB\xBF" + recording(),
                {"--set", "estimation.pso.iterations=1", "--set", "estimation.pso.start=latin_hypercube", "--set",
                 "estimation.pso.particles=3", "--threads", "1"});
    INFO("stderr: " << r.result.err);
    REQUIRE(r.result.exit_code == 0);
    CHECK(r.result.err.empty());
    CHECK(std::filesystem::is_regular_file(r.out / "summary.json"));
    CHECK(std::filesystem::is_regular_file(r.out / "estimation.csv"));
    // The first column was found by its name "t", not "\xEF\xBB\xBFt".
    const std::string est = read_text(r.out / "estimation.csv");
    CHECK(est.rfind("t [s],window,", 0) == 0);
}

namespace {

// A shipped experiment with one line replaced, written beside its data's absolute path.
std::filesystem::path shipped_variant(const TempDir& tmp, const std::string& config, const std::string& from,
                                      const std::string& to) {
    std::string text = shipped_config_text(config);
    replace_once(text, from, to);
    return tmp.write(config + "-variant.yaml", text);
}

}  // namespace

TEST_CASE("starts a controller makes impossible are refused at load, naming the controller", "[e2e][errors]") {
    const TempDir tmp;
    // A position controller holds its node to an angle: no steady rotation, as a spring to ground.
    const auto steady = shipped_variant(tmp, "positioning_drive", "initial_state: rest",
                                        "initial_state: { kind: steady, node: motor, speed: 1.0 }");
    const RunResult held = run_tvid({"fit", steady.string(), "-o", (tmp.path() / "a").string()});
    CHECK(held.exit_code == 2);
    CHECK(std::count(held.err.begin(), held.err.end(), '\n') == 1);
    CHECK(held.err.find(steady.string() + ":") == 0);
    CHECK(held.err.find("initial_state.kind: steady on a line held to ground by the position controller 'servo' "
                        "(node motor to its setpoint angle)") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(tmp.path() / "a"));
    // An estimated start does not estimate a sampled controller's memory.
    const auto estimated = shipped_variant(tmp, "digital_drive", "initial_state: rest",
                                           "initial_state: { kind: estimated, from: rest }");
    const RunResult sampled = run_tvid({"fit", estimated.string(), "-o", (tmp.path() / "b").string()});
    CHECK(sampled.exit_code == 2);
    CHECK(std::count(sampled.err.begin(), sampled.err.end(), '\n') == 1);
    CHECK(sampled.err.find("initial_state.kind: an estimated start estimates angles and speeds, not a sampled "
                           "controller's memory") != std::string::npos);
}

}  // namespace TVID_UNITY_ID
