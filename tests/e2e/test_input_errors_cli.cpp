// Bad experiment files and CSV data through the binary: exit status 2 and one line
// FILE:LINE: key: what is wrong.
#include <catch2/catch.hpp>
#include <algorithm>
#include <sstream>
#include <utility>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;

namespace {

// A valid experiment; each case replaces one line (0-based index) with a bad one.
const std::vector<std::string> kBase = {
    "tvid: 1",                                                             // 0
    "name: errors",                                                        // 1
    "data:",                                                               // 2
    "  file: rec.csv",                                                     // 3
    "  time: t",                                                           // 4
    "model:",                                                              // 5
    "  preset: cvt_clearance",                                             // 6
    "inputs: { Ttm: Ttm }",                                                // 7
    "outputs: { Tds: Tds }",                                               // 8
    "parameters:",                                                         // 9
    "  rho1:    { init: 1.5, min: 0.1, max: 10, range: [1, 2] }",          // 10
    "  k_minus: { init: 3000, min: 1, max: 1.0e6 }",                       // 11
    "  k_plus:  { init: 8000, min: 1, max: 1.0e6 }",                       // 12
    "  c_minus: { init: 4, min: 0, max: 100 }",                            // 13
    "  c_plus:  { init: 19, min: 0, max: 100 }",                           // 14
    "  mu:      { init: 0.0035, min: 0, max: 0.1 }",                       // 15
    "  sigma:   { value: 1132.81, fixed: true }",                          // 16
    "  d_ds:    { init: -7, min: -100, max: 100 }",                        // 17
    "  d_tm:    { init: 13, min: -100, max: 100 }",                        // 18
    "windows:",                                                            // 19
    "  estimation: [ { time: [0.002, 0.008] } ]",                          // 20
    "estimation:",                                                         // 21
    "  pso: { start: latin_hypercube, particles: 4, iterations: 1 }",      // 22
};

std::string csv_text() {
    std::ostringstream s;
    s << "t,Ttm,Tds\n";
    for (int i = 0; i <= 10; ++i) s << i * 0.001 << ',' << 10 + i << ',' << -5 + i << '\n';
    return s.str();
}

struct Case {
    const char* what;
    std::size_t line;      // 0-based line to replace
    const char* replacement;
    const char* key;       // expected in the message
};

std::string join(const std::vector<std::string>& lines) {
    std::string s;
    for (const auto& l : lines) s += l + "\n";
    return s;
}

}  // namespace

TEST_CASE("every experiment error exits 2 naming the file, the line and the key", "[e2e][errors]") {
    const Case cases[] = {
        {"unknown key", 22, "  pso: { start: latin_hypercube, particles: 4, itrations: 1 }", "itrations"},
        {"wrong type", 10, "  rho1:    { init: fast, min: 0.1, max: 10, range: [1, 2] }", "parameters.rho1.init"},
        {"missing key", 4, "", "data.time"},
        {"misspelt key", 4, "  tyme: t", "did you mean 'time'"},
        {"min > max", 13, "  c_minus: { init: 4, min: 50, max: 10 }", "parameters.c_minus"},
        {"init outside bounds", 14, "  c_plus:  { init: 190, min: 0, max: 100 }", "parameters.c_plus"},
        {"min = max on a free parameter", 13, "  c_minus: { init: 4, min: 4, max: 4 }", "parameters.c_minus.max"},
        {"scale log on a box reaching 0", 13, "  c_minus: { init: 4, min: 0, max: 100, scale: log }",
         "parameters.c_minus.scale"},
        {"window outside the data", 20, "  estimation: [ { time: [0.002, 5.0] } ]", "windows.estimation"},
        {"column not in the CSV", 8, "outputs: { Tds: Tq }", "outputs.Tds"},
        {"unknown preset", 6, "  preset: cvt_clearence", "model.preset"},
        {"wrong format version", 0, "tvid: 2", "tvid"},
        {"wrong type for a list", 20, "  estimation: { time: [0.002, 0.008] }", "windows.estimation"},
        {"wrong type for a number", 22, "  pso: { start: latin_hypercube, particles: [4], iterations: 1 }",
         "estimation.pso.particles"},
        {"missing parameter", 15, "", "parameters.mu"},
        {"negative inverse inertia", 10, "  rho1:    { init: -1.5, min: -10, max: 10 }", "parameters.rho1.init"},
        {"negative damping", 13, "  c_minus: { value: -4 }", "parameters.c_minus.value"},
        {"window the wrong way round", 20, "  estimation: [ { time: [0.008, 0.002] } ]", "windows.estimation[0].time"},
        {"samples outside the data", 20, "  estimation: [ { samples: [2, 50] } ]", "windows.estimation[0].samples"},
    };
    for (const Case& c : cases) {
        SECTION(c.what) {
            TempDir tmp;
            tmp.write("rec.csv", csv_text());
            std::vector<std::string> lines = kBase;
            lines[c.line] = c.replacement;
            const auto exp = tmp.write("exp.yaml", join(lines));
            const RunResult r = run_tvid({"fit", exp.string(), "-o", (tmp.path() / "out").string()});
            INFO(r.err);
            CHECK(r.exit_code == 2);
            // One line, FILE:LINE: key: ...
            CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
            const std::string prefix = exp.string() + ":";
            CHECK(r.err.rfind(prefix, 0) == 0);
            const int line = std::atoi(r.err.c_str() + prefix.size());
            if (std::string(c.what) == "missing key") {
                CHECK((line == 3 || line == 4));  // the data map
            } else if (std::string(c.what) == "missing parameter") {
                CHECK((line == 10 || line == 11));  // the parameters map
            } else {
                CHECK(line == static_cast<int>(c.line) + 1);
            }
            CHECK(r.err.find(c.key) != std::string::npos);
            CHECK_FALSE(std::filesystem::exists(tmp.path() / "out"));  // nothing written
        }
    }
}

TEST_CASE("CSV errors exit 2 naming the data file, the line and the column", "[e2e][errors]") {
    struct CsvCase {
        const char* what;
        std::string csv;
        int line;
        const char* column;
    };
    const CsvCase cases[] = {
        {"non-numeric cell", "t,Ttm,Tds\n0,1,2\n0.001,x1,2\n0.002,1,2\n", 3, "Ttm"},
        {"short row", "t,Ttm,Tds\n0,1,2\n0.001,1\n0.002,1,2\n", 3, "Tds"},
        {"time not increasing", "t,Ttm,Tds\n0,1,2\n0.002,1,2\n0.001,1,2\n", 4, "t"},
        {"time repeated", "# comment\nt,Ttm,Tds\n0,1,2\n0,1,2\n", 4, "t"},
    };
    for (const CsvCase& c : cases) {
        SECTION(c.what) {
            TempDir tmp;
            const auto csv = tmp.write("rec.csv", c.csv);
            const auto exp = tmp.write("exp.yaml", join(kBase));
            const RunResult r = run_tvid({"fit", exp.string(), "-o", (tmp.path() / "out").string()});
            INFO(r.err);
            CHECK(r.exit_code == 2);
            CHECK(r.err.rfind(csv.string() + ":" + std::to_string(c.line) + ":", 0) == 0);
            CHECK(r.err.find(std::string("column ") + c.column) != std::string::npos);
        }
    }
}

TEST_CASE("an override with a bad value is reported as coming from --set", "[e2e][errors]") {
    TempDir tmp;
    tmp.write("rec.csv", csv_text());
    const auto exp = tmp.write("exp.yaml", join(kBase));
    const RunResult r = run_tvid({"fit", exp.string(), "--set", "estimation.pso.iterations=many"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("--set") != std::string::npos);
    CHECK(r.err.find("estimation.pso.iterations") != std::string::npos);
}

TEST_CASE("command-line errors are one line naming the flag typed, exit 2", "[e2e][errors]") {
    const std::string cvt = (source_dir() / "configs/cvt_tipin.yaml").string();
    for (const auto& [args, expected] : std::vector<std::pair<std::vector<std::string>, std::string>>{
             {{"fit", cvt, "--optimizer", "foo"}, "tvid: --optimizer: foo not in {pso,lm,nlopt,pso+lm,multistart}"},
             {{"fit", cvt, "--threads", "abc"}, "tvid: --threads: "},
             {{"fit"}, "tvid: experiment is required"},
             {{"profile", cvt, "--points", "2"}, "tvid: --points: "}}) {
        const RunResult r = run_tvid(args);
        INFO(r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.err.rfind(expected, 0) == 0);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
    // The usage line names the tool, not the path it was started by.
    const RunResult help = run_tvid({"fit", "--help"});
    CHECK(help.exit_code == 0);
    CHECK(help.out.find("Usage: tvid fit [OPTIONS] experiment") != std::string::npos);
}

}  // namespace TVID_UNITY_ID
