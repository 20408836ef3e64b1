// Ctrl-C (SIGINT) or SIGTERM during `tvid fit`: the binary stops within about a second,
// writes a complete report with the best parameters so far marked interrupted, and exits
// with 130.
#include <catch2/catch.hpp>
#include <signal.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

using clock_type = std::chrono::steady_clock;

// How many times longer a run takes here than in an optimized build (8 under the sanitizers, whose library is compiled at -O1).
const double kTimeScale = test_time_scale();

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> cells;
        std::istringstream row(line);
        for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
        rows.push_back(cells);
    }
    return rows;
}

// Starts the fit, lets it run `run_seconds`, sends `signal` and returns the seconds from
// the signal to the exit (the process result in `fit`).
double interrupt_after(TvidProcess& fit, double run_seconds, int signal) {
    std::this_thread::sleep_for(std::chrono::duration<double>(run_seconds));
    REQUIRE_FALSE(fit.wait(0));  // still fitting
    const auto sent = clock_type::now();
    fit.send(signal);
    REQUIRE(fit.wait(60));
    return std::chrono::duration<double>(clock_type::now() - sent).count();
}

// Every file of the report is there and parses; the summary says interrupted and its
// cost is the history's last best cost, which `tvid validate` reproduces from params.json.
void check_interrupted_report(const std::filesystem::path& out, const std::string& config, int planned,
                              int min_iterations) {
    for (const char* f : {"params.json", "params.csv", "summary.json", "estimation.csv", "validation.csv", "history.csv"})
        REQUIRE(std::filesystem::is_regular_file(out / f));
    for (const auto& entry : std::filesystem::directory_iterator(out))
        CHECK(entry.path().filename().string().find(".tvid-tmp.") == std::string::npos);

    const json s = json::parse(read_text(out / "summary.json"));
    CHECK(s["interrupted"] == true);
    CHECK(s["status"] == "ok");
    CHECK(s["optimizer"]["termination"] == "interrupted");
    CHECK(s["optimizer"]["converged"] == false);
    const int iterations = s["optimizer"]["iterations"].get<int>();
    CHECK(iterations >= min_iterations);
    CHECK(iterations < planned);
    CHECK(s["identifiability"]["available"] == false);
    CHECK(s["identifiability"]["problem"] == "skipped: interrupted");
    const double cost = s["cost"]["value"].get<double>();

    const auto history = csv_rows(read_text(out / "history.csv"));
    REQUIRE(history.size() == static_cast<std::size_t>(iterations) + 2);  // header + k = 0 … iterations
    CHECK(history[0] == std::vector<std::string>{"iteration", "evaluations", "best_cost"});
    for (std::size_t k = 2; k < history.size(); ++k) CHECK(std::stod(history[k][2]) <= std::stod(history[k - 1][2]));
    CHECK(std::stod(history.back()[0]) == iterations);
    CHECK(std::stod(history.back()[2]) == Approx(cost).epsilon(1e-9));

    const json params = json::parse(read_text(out / "params.json"));
    CHECK(params["parameters"].size() >= 1);
    CHECK(csv_rows(read_text(out / "params.csv")).size() == params["parameters"].size() + 1);
    CHECK(csv_rows(read_text(out / "estimation.csv")).size() > 1);
    CHECK(csv_rows(read_text(out / "validation.csv")).size() > 1);

    // The parameters written are the point whose cost the history reports.
    const RunResult v = run_tvid({"validate", config, "--params", (out / "params.json").string(), "--json"});
    REQUIRE(v.exit_code == 0);
    CHECK(json::parse(v.out)["cost"].get<double>() == Approx(cost).epsilon(1e-9));
}

}  // namespace

TEST_CASE("Ctrl-C during the paper's swarm writes the best so far, marked interrupted, exit 130",
          "[e2e][interrupt]") {
    TempDir tmp;
    const auto out = tmp.path() / "report";
    const std::string config = (source_dir() / "configs/cvt_tipin.yaml").string();
    // 5000 iterations, twenty times the paper's: the signal finds the swarm fitting however
    // fast the machine (250 took less than the 12 s this test waits under the sanitizers).
    TvidProcess fit({"fit", config, "-o", out.string(), "--threads", "2", "--set", "estimation.pso.iterations=5000"});
    const double seconds = interrupt_after(fit, 1.5 * kTimeScale, SIGINT);
    const RunResult& r = fit.result();
    INFO(r.err);
    CHECK(r.exit_code == 130);
    CHECK(seconds < 2.0 * kTimeScale);  // stopped within a second, then the report (measured on 2 busy cores)
    CHECK(r.out.find("interrupted: the report holds the best parameters after iteration") != std::string::npos);
    CHECK(r.err.find("tvid: interrupted; the report in") != std::string::npos);
    check_interrupted_report(out, config, 5000, 1);
}

TEST_CASE("SIGTERM during a Levenberg-Marquardt fit writes the best so far, marked interrupted, exit 130",
          "[e2e][interrupt][fits]") {
    TempDir tmp;
    const auto out = tmp.path() / "report";
    const std::string config = (source_dir() / "configs/engine_idle.yaml").string();
    // The signal ends the simulations in flight at their next sample, so the optimizer,
    // whose clock started after the process did, stops within 4 s and a moment. The report
    // then simulates the estimation cycle and six validation cycles again: about 0.5 s in an
    // optimized build, several seconds under the sanitizers on a busy machine.
    // stol 0: LM crawls to its iteration limit (about 20 s), so the signal finds it fitting.
    TvidProcess fit({"fit", config, "-o", out.string(), "--threads", "2", "--set", "estimation.lm.stol=0"});
    const double seconds = interrupt_after(fit, 4.0 * kTimeScale, SIGTERM);
    const RunResult& r = fit.result();
    INFO(r.err);
    CHECK(r.exit_code == 130);
    CHECK(seconds < 30.0);
    check_interrupted_report(out, config, 100, 0);  // on a busy machine it may still be at the start
    const json s = json::parse(read_text(out / "summary.json"));
    CHECK(s["optimizer"]["name"] == "lm");
    CHECK(s["optimizer_time_s"].get<double>() < 4.5 * kTimeScale);
}

TEST_CASE("a second Ctrl-C exits at once with 130 and leaves no torn file", "[e2e][interrupt]") {
    TempDir tmp;
    const auto out = tmp.path() / "report";
    TvidProcess fit({"fit", (source_dir() / "configs/cvt_tipin.yaml").string(), "-o", out.string()});
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    REQUIRE_FALSE(fit.wait(0));
    fit.send(SIGINT);
    fit.send(SIGINT);
    REQUIRE(fit.wait(10));
    CHECK(fit.result().exit_code == 130);
    // Whatever was written is whole: each report file present parses.
    if (std::filesystem::exists(out))
        for (const auto& entry : std::filesystem::directory_iterator(out)) {
            const std::string name = entry.path().filename().string();
            INFO(name);
            if (name.size() > 5 && name.substr(name.size() - 5) == ".json")
                CHECK_NOTHROW(json::parse(read_text(entry.path())));
        }
}

}  // namespace TVID_UNITY_ID
