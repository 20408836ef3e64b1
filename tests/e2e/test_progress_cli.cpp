// The live progress line of `tvid fit`: drawn for a person at a terminal (stdout and
// stderr both terminals), absent in pipes, when stdout is piped (`| tee`), with --quiet
// and with --json. A long swarm's foretold time, said once after its first iteration.
#include <catch2/catch.hpp>
#include <signal.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;

namespace {

std::vector<std::string> swarm_fit(const std::filesystem::path& out) {
    return {"fit", (source_dir() / "configs/cvt_tipin.yaml").string(), "-o", out.string(), "--threads", "2",
            "--set", "estimation.pso.start=latin_hypercube", "--set", "estimation.pso.particles=16",
            "--set", "estimation.pso.iterations=6"};
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The CVT experiment on a 0.1 s window that names no optimizer: the default swarm, here 16
// particles and 1e8 iterations, whose first iteration takes milliseconds and the rest days.
std::filesystem::path endless_default_swarm(const TempDir& tmp) {
    const std::string data = (source_dir() / "data/cvt/tipin_clean.csv").string();
    return tmp.write("endless.yaml", "tvid: 1\n"
                                     "data: { file: '" + data + "', time: t }\n"
                                     "model: { preset: cvt_clearance }\n"
                                     "inputs: { Ttm: Ttm }\n"
                                     "outputs: { Tds: Tds }\n"
                                     "parameters:\n"
                                     "  rho1: { min: 0.01, max: 100, range: [1, 2] }\n"
                                     "  k_minus: { min: 1, max: 1.0e6, range: [1.0e3, 1.0e4] }\n"
                                     "  k_plus: { value: 5000 }\n"
                                     "  c_minus: { value: 15 }\n"
                                     "  c_plus: { value: 15 }\n"
                                     "  mu: { value: 2.0e-3 }\n"
                                     "  sigma: { value: 1132.81 }\n"
                                     "  d_ds: { value: -7 }\n"
                                     "  d_tm: { value: 12 }\n"
                                     "windows: { estimation: [ { time: [1.5, 1.6] } ] }\n"
                                     "estimation:\n"
                                     "  cost: l1\n"
                                     "  pso: { start: latin_hypercube, particles: 16, iterations: 100000000 }\n");
}

// Runs the fit, lets it start, stops it with Ctrl-C and returns what it printed.
RunResult fit_then_interrupt(std::vector<std::string> args) {
    TvidProcess fit(args);
    std::this_thread::sleep_for(std::chrono::duration<double>(0.7 * test_time_scale()));
    REQUIRE_FALSE(fit.wait(0));  // still fitting
    fit.send(SIGINT);
    REQUIRE(fit.wait(60));
    return fit.result();
}

}  // namespace

TEST_CASE("no progress text in pipes", "[e2e][progress]") {
    TempDir tmp;
    const RunResult r = run_tvid(swarm_fit(tmp.path() / "r"));
    REQUIRE(r.exit_code == 0);
    CHECK(r.err.empty());
    CHECK_FALSE(has(r.out, "\r"));
    CHECK_FALSE(has(r.out, "iteration 0/"));
    CHECK_FALSE(has(r.out, "eval/s"));
    CHECK(has(r.out, "tvid fit cvt-tipin"));  // the summary itself is there
}

TEST_CASE("on a terminal a live line shows iteration, best cost, simulations per second and time", "[e2e][progress]") {
    TempDir tmp;
    const RunResult r = run_tvid_on_terminal(swarm_fit(tmp.path() / "r"));
    INFO(r.out);
    REQUIRE(r.exit_code == 0);
    CHECK(has(r.out, "\r  iteration 0/6  best cost "));
    CHECK(has(r.out, " eval/s "));
    CHECK(has(r.out, " elapsed"));
    CHECK(has(r.out, "iteration 6/6"));   // the last iteration is always drawn
    CHECK(has(r.out, "\r\033[Ktvid fit cvt-tipin"));  // cleared before the summary
}

TEST_CASE("no progress line when stdout is piped, with --quiet or with --json", "[e2e][progress]") {
    TempDir tmp;
    SECTION("stdout to a pipe, stderr on the terminal (tvid fit ... | tee log)") {
        const RunResult r = run_tvid_on_terminal(swarm_fit(tmp.path() / "r"), TerminalStreams::stderr_only);
        REQUIRE(r.exit_code == 0);
        CHECK(r.err.empty());
        CHECK(has(r.out, "tvid fit cvt-tipin"));
    }
    SECTION("--quiet on a terminal prints nothing") {
        auto args = swarm_fit(tmp.path() / "r");
        args.push_back("--quiet");
        const RunResult r = run_tvid_on_terminal(args);
        REQUIRE(r.exit_code == 0);
        CHECK(r.out.empty());
    }
    SECTION("--json on a terminal prints only the summary JSON") {
        auto args = swarm_fit(tmp.path() / "r");
        args.push_back("--json");
        const RunResult r = run_tvid_on_terminal(args);
        REQUIRE(r.exit_code == 0);
        CHECK_FALSE(has(r.out, "eval/s"));
        CHECK_FALSE(has(r.out, "\033[K"));
        const auto s = nlohmann::json::parse(r.out);  // the terminal's \r\n are JSON whitespace
        CHECK(s["interrupted"] == false);
        CHECK(s["optimizer"]["iterations"] == 6);
    }
}

TEST_CASE("a long default swarm says after its first iteration how long the rest will take", "[e2e][progress][swarm]") {
    TempDir tmp;
    const RunResult r = fit_then_interrupt({"fit", endless_default_swarm(tmp).string(), "-o",
                                            (tmp.path() / "r").string(), "--threads", "2"});
    INFO(r.err);
    CHECK(r.exit_code == 130);
    // One line, before the interruption's, in a pipe too: the times aside, always the same words.
    CHECK(r.err.rfind("tvid: pso: scoring the 16 initial particles took ", 0) == 0);
    CHECK(has(r.err, "; 100000000 iterations more will take at most about "));
    CHECK(has(r.err, " h (the swarm is the default, as the experiment names no optimizer: `optimizer: lm` with "
                     "`cost: l2` fits locally from the init values, each step one simulation with its 2 sensitivities)\n"
                     "tvid: interrupted; "));
}

TEST_CASE("the swarm's foretold time is not said with --quiet", "[e2e][progress][swarm]") {
    TempDir tmp;
    const RunResult r = fit_then_interrupt({"fit", endless_default_swarm(tmp).string(), "-o",
                                            (tmp.path() / "r").string(), "--threads", "2", "--quiet"});
    CHECK(r.exit_code == 130);
    CHECK(r.err.empty());
    CHECK(r.out.empty());
}

}  // namespace TVID_UNITY_ID
