// `tvid fit --optimizer nlopt | pso+lm | multistart` through the binary: the report names
// the optimizer and its settings, multistart writes starts.csv, history.csv runs on
// across phases, and bad optimizer settings exit 2 with one line naming the key.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

// history.csv: iterations 0, 1, 2, … in order, simulations cumulative, best cost never rising.
void check_history(const std::filesystem::path& file, long long evaluations, double cost) {
    const auto rows = lines_of(read_text(file));
    REQUIRE(rows.size() >= 2);
    CHECK(rows[0] == "iteration,evaluations,best_cost");
    long long last_evaluations = 0;
    double last_cost = 1e300;
    int last_iteration = -1;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        int iteration = 0;
        long long evals = 0;
        double best = 0;
        REQUIRE(std::sscanf(rows[k].c_str(), "%d,%lld,%lf", &iteration, &evals, &best) == 3);
        CHECK(iteration > last_iteration);
        CHECK(evals >= last_evaluations);
        CHECK(best <= last_cost);
        last_iteration = iteration;
        last_evaluations = evals;
        last_cost = best;
    }
    CHECK(last_evaluations == evaluations);
    CHECK(last_cost == Approx(cost).epsilon(1e-9));
}

const std::string kCvt = (source_dir() / "configs/cvt_tipin_clean.yaml").string();

}  // namespace

TEST_CASE("tvid fit --optimizer nlopt runs the named algorithm on the configured cost", "[e2e][nlopt]") {
    TempDir tmp;
    const auto out = tmp.path() / "nlopt";
    const RunResult r = run_tvid({"fit", kCvt, "-o", out.string(), "--optimizer", "nlopt", "--set",
                                  "estimation.nlopt={ algorithm: LN_SBPLX, max_evaluations: 300 }", "--threads", "2"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("nlopt (evaluation limit)") != std::string::npos);
    const json s = json::parse(read_text(out / "summary.json"));
    CHECK(s["optimizer"]["name"] == "nlopt");
    CHECK(s["optimizer"]["algorithm"] == "LN_SBPLX");
    CHECK(s["optimizer"]["objective_evaluations"] == 300);
    CHECK(s["optimizer"]["evaluations"] == 300);  // one simulation each, no gradient
    CHECK(s["optimizer"]["termination"] == "evaluation limit");
    CHECK(s["cost"]["kind"] == "l1");
    const double cost = s["cost"]["value"].get<double>();
    CHECK(cost < s["optimizer"]["initial_cost"].get<double>());
    check_history(out / "history.csv", 300, cost);
    CHECK_FALSE(std::filesystem::exists(out / "starts.csv"));
}

TEST_CASE("tvid fit --optimizer pso+lm: the swarm, then LM from its best particle", "[e2e][hybrid]") {
    TempDir tmp;
    const auto out = tmp.path() / "hybrid";
    const RunResult r = run_tvid({"fit", kCvt, "-o", out.string(), "--optimizer", "pso+lm", "--set",
                                  "estimation.cost=l2", "--set", "estimation.pso.iterations=3", "--set",
                                  "estimation.lm.max_iterations=6"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json s = json::parse(read_text(out / "summary.json"));
    const json& o = s["optimizer"];
    CHECK(o["name"] == "pso+lm");
    CHECK(o["swarm"]["iterations"] == 3);
    CHECK(o["swarm"]["particles"] == 512);
    CHECK(o["polish"]["ran"] == true);
    CHECK(o["polish"]["initial_cost"].get<double>() == Approx(o["swarm"]["cost"].get<double>()).epsilon(1e-9));
    const double cost = s["cost"]["value"].get<double>();
    CHECK(cost < 0.5 * o["swarm"]["cost"].get<double>());  // the polish improves on the swarm
    CHECK(o["iterations"].get<int>() == 3 + 1 + o["polish"]["iterations"].get<int>());
    check_history(out / "history.csv", o["evaluations"].get<long long>(), cost);
}

TEST_CASE("tvid fit --optimizer multistart reports every start in starts.csv", "[e2e][multistart]") {
    TempDir tmp;
    const auto out = tmp.path() / "multistart";
    const RunResult r = run_tvid({"fit", kCvt, "-o", out.string(), "--optimizer", "multistart", "--set",
                                  "estimation.cost=l2", "--set", "estimation.multistart={ starts: 3, max_iterations: 4 }",
                                  "--seed", "11", "--json", "--quiet"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json s = json::parse(read_text(out / "summary.json"));
    const json& o = s["optimizer"];
    CHECK(o["name"] == "multistart");
    CHECK(o["starts"] == 3);
    CHECK(o["seed"] == 11);
    REQUIRE(o["start_results"].size() == 3);
    const int best = o["best_start"].get<int>();
    const double cost = s["cost"]["value"].get<double>();
    for (const json& start : o["start_results"]) {
        CHECK(start["iterations"].get<int>() <= 4);
        CHECK(start["cost"].get<double>() >= cost * (1 - 1e-9));
    }
    CHECK(o["start_results"][best - 1]["cost"].get<double>() == Approx(cost).epsilon(1e-9));
    const auto rows = lines_of(read_text(out / "starts.csv"));
    REQUIRE(rows.size() == 4);
    CHECK(rows[0].rfind("start,initial_rho1,", 0) == 0);
    CHECK(rows[0].find(",final_d_tm,initial_cost,cost,iterations,evaluations,termination,best,draws") != std::string::npos);
    CHECK(std::count_if(rows.begin() + 1, rows.end(), [](const std::string& row) {
              return row.find(",true,") != std::string::npos;  // best, then the points drawn
          }) == 1);
    check_history(out / "history.csv", o["evaluations"].get<long long>(), cost);

    // Another optimizer's report in the same directory leaves no stale starts.csv behind.
    const RunResult again = run_tvid({"fit", kCvt, "-o", out.string(), "--force", "--quiet", "--set",
                                      "estimation.pso={ start: latin_hypercube, particles: 4, iterations: 1 }"});
    REQUIRE(again.exit_code == 0);
    CHECK_FALSE(std::filesystem::exists(out / "starts.csv"));
}

TEST_CASE("tvid fit --optimizer multistart races its starts and says where and why each stopped",
          "[e2e][multistart]") {
    TempDir tmp;
    const auto out = tmp.path() / "race";
    const RunResult r = run_tvid({"fit", kCvt, "-o", out.string(), "--optimizer", "multistart", "--set",
                                  "estimation.cost=l2", "--set",
                                  "estimation.multistart={ starts: 6, max_iterations: 12, race_iterations: 2 }", "--seed",
                                  "11"});
    INFO(r.out << r.err);
    REQUIRE(r.exit_code == 0);
    const json o = json::parse(read_text(out / "summary.json"))["optimizer"];
    CHECK(o["race"] == true);
    CHECK(o["race_iterations"] == 2);
    int raced_out = 0;
    for (const json& start : o["start_results"]) {
        if (!start["raced_out"].get<bool>()) continue;
        ++raced_out;
        const int k = start["iterations"].get<int>();
        CHECK((k == 2 || k == 4 || k == 8));  // the rungs before the iteration limit of 12
        CHECK(start["termination"].get<std::string>().rfind("raced out after " + std::to_string(k) + " iterations: cost ",
                                                            0) == 0);
        CHECK_FALSE(start["converged"].get<bool>());
    }
    CHECK(raced_out > 0);
    CHECK(o["raced_out"] == raced_out);
    CHECK(raced_out < 6);  // one start at least runs to its end
    const std::string starts = read_text(out / "starts.csv");
    CHECK(std::count(starts.begin(), starts.end(), '\n') == 7);
    CHECK(starts.find(",\"raced out after 2 iterations: cost ") != std::string::npos);
    CHECK(r.out.find("; " + std::to_string(raced_out) + " raced out), ") != std::string::npos);  // the terminal's line

    const RunResult bad = run_tvid({"fit", kCvt, "-o", (tmp.path() / "never").string(), "--optimizer", "multistart",
                                    "--set", "estimation.cost=l2", "--set", "estimation.multistart.race_iterations=0"});
    CHECK(bad.exit_code == 2);
    CHECK(bad.err == "--set: estimation.multistart.race_iterations: must be between 1 and 1e6\n");
}

TEST_CASE("bad optimizer settings exit 2 with one line naming the key", "[e2e][nlopt][errors]") {
    TempDir tmp;
    const auto out = tmp.path() / "never";
    const RunResult unknown = run_tvid({"fit", kCvt, "-o", out.string(), "--optimizer", "nlopt", "--set",
                                        "estimation.nlopt.algorithm=LN_BOBYQUA"});
    CHECK(unknown.exit_code == 2);
    CHECK(std::count(unknown.err.begin(), unknown.err.end(), '\n') == 1);
    CHECK(unknown.err.rfind("--set: estimation.nlopt.algorithm: NLopt has no algorithm 'LN_BOBYQUA'; valid: ", 0) == 0);
    CHECK(unknown.err.find("LN_BOBYQA, GN_ISRES") != std::string::npos);

    const RunResult name = run_tvid({"fit", kCvt, "-o", out.string(), "--optimizer", "simplex"});
    CHECK(name.exit_code == 2);
    CHECK(name.err.rfind("tvid: --optimizer: simplex not in", 0) == 0);  // the flag the user typed
    CHECK(name.err.find("pso+lm") != std::string::npos);

    const RunResult l1 = run_tvid({"fit", kCvt, "-o", out.string(), "--optimizer", "multistart"});
    CHECK(l1.exit_code == 2);
    CHECK(l1.err.find("estimation.cost: the multistart optimizer minimizes a sum of squares: set cost: l2") !=
          std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
}

}  // namespace TVID_UNITY_ID
