// The live progress line of `tvid fit`: drawn for a person at a terminal (stdout and
// stderr both terminals), absent in pipes, when stdout is piped (`| tee`), with --quiet
// and with --json.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

using namespace tvid::test;

namespace {

std::vector<std::string> swarm_fit(const std::filesystem::path& out) {
    return {"fit", (source_dir() / "configs/cvt_tipin.yaml").string(), "-o", out.string(), "--threads", "2",
            "--set", "estimation.pso.start=latin_hypercube", "--set", "estimation.pso.particles=16",
            "--set", "estimation.pso.iterations=6"};
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

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
