// More bad input through the binary: broken files, not just broken keys. Each is exit
// status 2, exactly one line on stderr "FILE:LINE: key: what is wrong" naming the file
// at fault (the experiment or the CSV), and no report directory left behind.
#include <catch2/catch.hpp>
#include <algorithm>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

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

    Run(const std::string& experiment_text, const std::string& csv_text, std::vector<std::string> extra = {}) {
        csv = tmp.write("rec.csv", csv_text);
        exp = tmp.write("exp.yaml", experiment_text);
        out = tmp.path() / "out";
        std::vector<std::string> args{"fit", exp.string(), "-o", out.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        result = run_tvid(args);
    }
};

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
    CHECK(est.rfind("t,window,", 0) == 0);
}
