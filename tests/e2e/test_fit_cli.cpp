// `tvid fit` end to end: the binary on the shipped experiment, every report file and
// its fields, the summary it prints, and exit statuses.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

const std::vector<std::string> kSmallSwarm = {"--set", "estimation.pso.start=latin_hypercube",
                                              "--set", "estimation.pso.particles=16",
                                              "--set", "estimation.pso.iterations=4"};

std::vector<std::string> fit_args(const std::string& config, const std::string& out) {
    std::vector<std::string> a{"fit", (source_dir() / "configs" / config).string(), "-o", out, "--threads", "2"};
    a.insert(a.end(), kSmallSwarm.begin(), kSmallSwarm.end());
    return a;
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

json read_json(const std::filesystem::path& p) { return json::parse(read_text(p)); }

}  // namespace

TEST_CASE("tvid fit writes a complete report directory", "[e2e][fit]") {
    TempDir tmp;
    const auto out = tmp.path() / "report";
    const RunResult r = run_tvid(fit_args("cvt_tipin.yaml", out.string()));
    INFO(r.err);
    REQUIRE(r.exit_code == 0);

    // The terminal summary: Q-index, cost, parameters, wall time, report folder.
    CHECK(r.out.find("tvid fit cvt-tipin") != std::string::npos);
    CHECK(r.out.find("cost (l1)") != std::string::npos);
    CHECK(r.out.find("Q ") != std::string::npos);
    CHECK(r.out.find("rho1") != std::string::npos);
    CHECK(r.out.find(out.string()) != std::string::npos);
    CHECK(std::regex_search(r.out, std::regex(R"(\d+\.\d\d s on 2 threads)")));
    CHECK(r.err.empty());  // no progress line in a pipe

    for (const char* f : {"params.json", "params.csv", "summary.json", "estimation.csv", "validation.csv", "history.csv"})
        CHECK(std::filesystem::is_regular_file(out / f));
    for (const auto& entry : std::filesystem::directory_iterator(out))
        CHECK(entry.path().filename().string().find(".tvid-tmp.") == std::string::npos);

    const json params = read_json(out / "params.json");
    REQUIRE(params["parameters"].size() == 9);
    const std::vector<std::string> names{"rho1", "k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma", "d_ds", "d_tm"};
    for (std::size_t i = 0; i < 9; ++i) {
        const json& p = params["parameters"][i];
        CHECK(p["name"] == names[i]);
        CHECK(p["value"].is_number());
        CHECK(p["init"].is_number());
        CHECK(p["min"].is_number());
        CHECK(p["max"].is_number());
        CHECK(p["fixed"] == false);
        CHECK(p.contains("std_error"));
        CHECK(p.contains("ci95"));
        CHECK(p["value"].get<double>() >= p["min"].get<double>());
        CHECK(p["value"].get<double>() <= p["max"].get<double>());
    }
    CHECK(params["correlation"]["parameters"].size() == 9);

    const json s = read_json(out / "summary.json");
    CHECK(s["status"] == "ok");
    CHECK(s["interrupted"] == false);
    CHECK(s["experiment"] == "cvt-tipin");
    CHECK(s["model"] == "cvt_clearance");
    CHECK(s["threads"] == 2);
    CHECK(s["processes"] == 1);  // not under mpirun
    CHECK(s["optimizer"]["name"] == "pso");
    CHECK(s["optimizer"]["particles"] == 16);
    CHECK(s["optimizer"]["iterations"] == 4);
    CHECK(s["optimizer"]["seed"] == 1);
    CHECK(s["optimizer"]["termination"] == "iteration limit");
    CHECK(s["optimizer"]["evaluations"].get<long long>() >= 16);
    CHECK(s["wall_time_s"].get<double>() > 0);
    CHECK(s["cost"]["kind"] == "l1");
    const double cost = s["cost"]["value"].get<double>();
    CHECK(cost > 0);
    CHECK(std::regex_match(s["config_sha256"].get<std::string>(), std::regex("[0-9a-f]{64}")));
    CHECK(std::regex_match(s["data_sha256"].get<std::string>(), std::regex("[0-9a-f]{64}")));
    CHECK(s["version"].is_string());
    const json& est = s["estimation"]["pooled"]["Tds"];
    CHECK(est["samples"] == 1500);  // (1.5, 3.0] at 1 kHz
    CHECK(est["cost_l1"].get<double>() == Approx(cost).epsilon(1e-12));
    for (const char* k : {"q_index_percent", "fit_percent", "rmse", "max_abs_residual_ratio_percent", "e0"})
        CHECK(est[k].is_number());
    CHECK(s["validation"]["windows"].size() == 2);
    CHECK(s["validation"]["pooled"]["Tds"]["samples"] == 1000);
    CHECK(s["identifiability"]["free_parameters"] == 9);

    // estimation.csv: header plus one row per scored sample; residual = measured − simulated.
    const auto est_lines = lines_of(read_text(out / "estimation.csv"));
    REQUIRE(est_lines.size() == 1501);
    CHECK(est_lines[0] == "t [s],window,Tds_measured [N m],Tds_simulated [N m],Tds_residual [N m],Tds_residual_ratio [%]");
    double abs_sum = 0, largest_y = 0;
    std::vector<std::vector<std::string>> rows;
    for (std::size_t i = 1; i < est_lines.size(); ++i) {
        std::vector<std::string> cells;
        std::string cell;
        std::istringstream row(est_lines[i]);
        while (std::getline(row, cell, ',')) cells.push_back(cell);
        if (est_lines[i].back() == ',') cells.emplace_back();  // an empty last cell
        REQUIRE(cells.size() == 6);
        const double y = std::stod(cells[2]), ys = std::stod(cells[3]), e = std::stod(cells[4]);
        CHECK(e == Approx(y - ys).margin(1e-7));
        abs_sum += std::abs(e);
        largest_y = std::max(largest_y, std::abs(y));
        rows.push_back(cells);
    }
    CHECK(abs_sum / 1500 == Approx(cost).epsilon(1e-6));
    // The residual ratio: empty below 10 % of the window's largest |y|, and its largest
    // magnitude is the summary's.
    double largest_ratio = 0;
    std::size_t empty = 0;
    for (const auto& cells : rows) {
        const double y = std::stod(cells[2]);
        CHECK(cells[5].empty() == (std::abs(y) < 0.1 * largest_y));
        if (cells[5].empty()) ++empty;
        else largest_ratio = std::max(largest_ratio, std::abs(std::stod(cells[5])));
    }
    CHECK(empty > 0);  // the torque crosses zero in the window
    CHECK(largest_ratio == Approx(est["max_abs_residual_ratio_percent"].get<double>()).epsilon(1e-6));
    CHECK(lines_of(read_text(out / "validation.csv")).size() == 1001);

    // history.csv: one row per iteration k = 0..4, best cost non-increasing, ending at the cost.
    const auto hist = lines_of(read_text(out / "history.csv"));
    REQUIRE(hist.size() == 6);
    CHECK(hist[0] == "iteration,evaluations,best_cost");
    CHECK(std::stod(hist[5].substr(hist[5].rfind(',') + 1)) == Approx(cost).epsilon(1e-12));

    // params.csv: header plus 9 rows.
    const auto pcsv = lines_of(read_text(out / "params.csv"));
    REQUIRE(pcsv.size() == 10);
    CHECK(pcsv[0] == "name,value,init,min,max,fixed,std_error,ci95_low,ci95_high,unit");
    CHECK(pcsv[1].rfind("rho1,", 0) == 0);
    CHECK(pcsv[1].substr(pcsv[1].rfind(',') + 1) == "1/(kg m^2)");  // rho1 = 1/I1

    // validate with the fitted parameters reproduces the cost.
    const RunResult v = run_tvid({"validate", (source_dir() / "configs/cvt_tipin.yaml").string(), "--params",
                                  (out / "params.json").string(), "--json"});
    REQUIRE(v.exit_code == 0);
    CHECK(json::parse(v.out)["cost"].get<double>() == Approx(cost).epsilon(1e-12));

    // Without --json, validate prints the table fit prints: the cost, and Q and fit % per split and window.
    const RunResult table = run_tvid({"validate", (source_dir() / "configs/cvt_tipin.yaml").string(), "--params",
                                      (out / "params.json").string()});
    REQUIRE(table.exit_code == 0);
    CHECK(table.out.rfind("tvid validate cvt-tipin: 1 estimation and 2 validation windows\n  cost (l1) ", 0) == 0);
    CHECK(table.out.find("  validation Tds    Q ") != std::string::npos);
    CHECK(table.out.find("      window time 3 to 3.5 ") != std::string::npos);
    // simulate --json: the metrics and the samples of the CSV as JSON.
    const RunResult sj = run_tvid({"simulate", (source_dir() / "configs/cvt_tipin.yaml").string(), "--params",
                                   (out / "params.json").string(), "--json"});
    REQUIRE(sj.exit_code == 0);
    const json sim_json = json::parse(sj.out);
    CHECK(sim_json["cost"].get<double>() == Approx(cost).epsilon(1e-12));
    CHECK(sim_json["traces"]["estimation"]["t"].size() == 1500);
    CHECK(sim_json["traces"]["validation"]["outputs"]["Tds"]["simulated"].size() == 1000);

    // simulate prints measured vs simulated for every window.
    const RunResult sim = run_tvid({"simulate", (source_dir() / "configs/cvt_tipin.yaml").string(), "--params",
                                    (out / "params.json").string()});
    REQUIRE(sim.exit_code == 0);
    CHECK(lines_of(sim.out).size() == 1 + 1500 + 1000);
}

TEST_CASE("the swarm in tvid fit stops each candidate at its particle's personal best", "[e2e][fit][pso][fits]") {
    // The paper's swarm, 20 iterations: from the second iteration on, a candidate whose
    // partial cost passes its particle's best is not simulated to the end of the window.
    TempDir tmp;
    const auto out = tmp.path() / "r";
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o", out.string(),
                                  "--threads", "2", "--quiet", "--set", "estimation.pso.iterations=20"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json optimizer = read_json(out / "summary.json")["optimizer"];
    const long long simulations = optimizer["evaluations"].get<long long>();
    REQUIRE(simulations > 512 * 10);  // a particle that did not move is not simulated again
    REQUIRE(simulations <= 512 * 21);
    // A whole simulation: RK4 at one step per sample from the window's initial state, 4
    // right-hand sides per step, one step per scored sample (estimation.csv has a row per
    // scored sample: 1500 on [1.5, 3] s at 1 kHz).
    const std::size_t scored = lines_of(read_text(out / "estimation.csv")).size() - 1;
    REQUIRE(scored == 1500);
    const double whole = 4.0 * static_cast<double>(scored) * static_cast<double>(simulations);
    const double done = optimizer["right_hand_sides"].get<double>();
    INFO("right-hand sides " << done << " of " << whole << " for whole simulations");
    CHECK(done > 0.5 * whole);   // about 0.70 of it: the first iteration is never cut
    CHECK(done < 0.9 * whole);   // the stop at the personal best saved work (1.0 without it)
}

TEST_CASE("tvid fit --json prints the summary on stdout", "[e2e][fit]") {
    TempDir tmp;
    auto args = fit_args("cvt_tipin.yaml", (tmp.path() / "r").string());
    args.push_back("--json");
    const RunResult r = run_tvid(args);
    REQUIRE(r.exit_code == 0);
    const json s = json::parse(r.out);
    CHECK(s["status"] == "ok");
    // With the parameters as params.json lists them: the whole result in one document.
    const json params = read_json(tmp.path() / "r" / "params.json");
    CHECK(s["parameters"] == params["parameters"]);
    REQUIRE(s["parameters"].size() == 9);
    CHECK(s["parameters"][0]["name"] == "rho1");
    CHECK(s["parameters"][0]["value"].is_number());
    CHECK(s["verdict"]["summary"].is_string());
    // The file's content, and where the report went.
    CHECK(s["report"] == (tmp.path() / "r").string());
    json without_path = s;
    without_path.erase("report");
    CHECK(without_path == read_json(tmp.path() / "r" / "summary.json"));
}

TEST_CASE("the report directory comes from report.dir relative to the experiment file", "[e2e][fit]") {
    TempDir tmp;
    std::string yaml = read_text(source_dir() / "configs/cvt_tipin.yaml");
    yaml = std::regex_replace(yaml, std::regex(R"(\.\./data/cvt/)"), (source_dir() / "data/cvt/").string());
    yaml = std::regex_replace(yaml, std::regex(R"(report: \{ dir: [^}]*\})"), "report: { dir: out/here }");
    const auto exp = tmp.write("exp/cvt.yaml", yaml);
    std::vector<std::string> args{"fit", exp.string(), "--quiet"};
    args.insert(args.end(), kSmallSwarm.begin(), kSmallSwarm.end());
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.empty());  // --quiet
    CHECK(std::filesystem::is_regular_file(tmp.path() / "exp/out/here/summary.json"));
}

TEST_CASE("a fit whose every candidate fails exits 1 with a report that says so", "[e2e][fit]") {
    TempDir tmp;
    auto args = fit_args("cvt_tipin.yaml", (tmp.path() / "r").string());
    for (const char* s : {"simulation.method=dopri5", "simulation.max_steps=1"}) {
        args.push_back("--set");
        args.push_back(s);
    }
    const RunResult r = run_tvid(args);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("every candidate") != std::string::npos);
    CHECK(r.err.find("(at the init values, in estimation window time 1.5 to 3: step budget exceeded)") !=
          std::string::npos);  // why
    const json s = read_json(tmp.path() / "r" / "summary.json");
    CHECK(s["status"] == "failed");
    CHECK(s["optimizer"]["termination"] == "all candidates failed");
    CHECK(s["optimizer"]["failed_evaluations"] == s["optimizer"]["evaluations"]);
    // Why the swarm's candidates failed: the first one simulated again, alone.
    CHECK(s["optimizer"]["first_failure"] == "estimation window time 1.5 to 3: simulation step budget exceeded");
}

TEST_CASE("an lm fit whose start cannot be simulated exits 1 with a report that says so", "[e2e][fit]") {
    TempDir tmp;
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/cvt_tipin.yaml").string(), "-o",
                                  (tmp.path() / "r").string(), "--optimizer", "lm", "--quiet", "--set",
                                  "estimation.cost=l2", "--set", "simulation.method=rosenbrock4", "--set",
                                  "simulation.max_steps=1"});
    CHECK(r.exit_code == 1);
    CHECK(r.err == "tvid: the simulation at the start failed (every candidate failed; at the init values, in "
                   "estimation window time 1.5 to 3: step budget exceeded); the report in " +
                       (tmp.path() / "r").string() + " says so\n");
    const json s = read_json(tmp.path() / "r" / "summary.json");
    CHECK(s["status"] == "failed");
    // The solver says why its start failed.
    CHECK(s["optimizer"]["termination"] ==
          "start failed: estimation window time 1.5 to 3: simulation step budget exceeded");
    CHECK(s["optimizer"]["failed_evaluations"] == 1);
    CHECK(s["optimizer"]["initial_cost"].is_null());
}

TEST_CASE("a start whose simulation diverges names the node, the time and what to try", "[e2e][fit]") {
    // The CVT's clearance with contact stiffnesses of 1e6 N m/rad: the estimation window
    // starts out of contact, where nothing is stiff (no substeps, no implicit steps,
    // stable_step.hpp), and RK4 at the 1 ms sample step blows up once the tip-in closes the
    // gap, after 1.7 s. (A start stiff already at the window's start is simulated: in
    // substeps, or by sdirk3 beyond 64 of them.)
    TempDir tmp;
    std::vector<std::string> args{"fit", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o",
                                  (tmp.path() / "r").string(), "--optimizer", "lm", "--set", "estimation.cost=l2"};
    for (const char* init : {"rho1.init=100", "k_minus.init=1e6", "k_plus.init=1e6", "c_minus.init=15", "c_plus.init=15",
                             "mu.init=0.003", "sigma.init=3000", "d_ds.init=-7.5", "d_tm.init=12.5"}) {
        args.push_back("--set");
        args.push_back(std::string("parameters.") + init);
    }
    const RunResult r = run_tvid(args);
    CHECK(r.exit_code == 1);
    const json s = read_json(tmp.path() / "r" / "summary.json");
    const std::string why = s["optimizer"]["termination"];
    INFO(why);
    CHECK(why.rfind("start failed: estimation window time 1.5 to 3: simulation diverged: node cvt_input_shaft's speed "
                    "reached ", 0) == 0);
    CHECK(why.find("after t = 1.701 s (by t = 1.702 s)") != std::string::npos);  // the contact's interval
    CHECK(why.find("smaller simulation.step, or method: sdirk3") != std::string::npos);
    CHECK(r.err.find("node cvt_input_shaft's speed") != std::string::npos);  // the terminal says it too
}

TEST_CASE("a start too stiff for RK4's substeps is simulated by sdirk3's steps and fitted", "[e2e][fit]") {
    // A hub of 1e-6 kg m² on a 1e6 N m/rad mount: 1e6 rad/s, 350 times RK4's limit at
    // 1 ms, beyond the 64 substeps a window may take: sdirk3 at the step instead.
    TempDir tmp;
    const auto experiment = tmp.write("stiff.yaml", "tvid: 1\n"
        "name: stiff\n"
        "data: { file: " + (source_dir() / "data/cvt/tipin_a.csv").string() + ", time: t }\n"
        "model:\n"
        "  nodes: [ { name: motor, J: 0.05 }, { name: hub, J: J_h } ]\n"
        "  elements:\n"
        "    - { type: torque, name: drive, node: motor, input: T_in }\n"
        "    - { type: spring_damper, name: shaft, between: [motor, hub], k: 500, c: 1 }\n"
        "    - { type: spring_damper, name: mount, between: [hub], k: k_m }\n"
        "inputs: { T_in: Ttm }\n"
        "outputs: { T_shaft: { column: Tds, torque: shaft } }\n"
        "parameters:\n"
        "  J_h: { init: 1.0e-6, min: 1.0e-7, max: 1 }\n"
        "  k_m: { init: 1.0e6, min: 1, max: 1.0e7 }\n"
        "windows: { estimation: [ { time: [1.5, 3.0] } ] }\n"
        "initial_state: rest\n"
        "estimation: { cost: l2, optimizer: lm }\n");
    const RunResult r = run_tvid({"fit", experiment.string(), "-o", (tmp.path() / "r").string()});
    INFO(r.err);
    CHECK(r.exit_code == 0);
    const json s = read_json(tmp.path() / "r" / "summary.json");
    CHECK(s["optimizer"]["failed_evaluations"] == 0);
    CHECK(s["step_stability"]["implicit_starts"].get<long long>() > 0);
    CHECK(r.out.find("of candidates too stiff for RK4's substeps took sdirk3's implicit steps") != std::string::npos);
}

TEST_CASE("tvid models lists the presets and the element kinds with their fields", "[e2e][models]") {
    const RunResult r = run_tvid({"models"});
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("cvt_clearance") != std::string::npos);
    for (const char* p : {"rho1", "k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma", "d_ds", "d_tm", "Ttm", "Tds"})
        CHECK(r.out.find(p) != std::string::npos);
    const RunResult j = run_tvid({"models", "--json"});
    REQUIRE(j.exit_code == 0);
    const json all = json::parse(j.out);
    const json& m = all["presets"];
    CHECK(m[0]["preset"] == "cvt_clearance");
    CHECK(m[0]["parameters"].size() == 9);
    CHECK(m[0]["inputs"] == json::array({"Ttm"}));
    CHECK(m[0]["outputs"] == json::array({"Tds"}));
    // Every element kind with its fields, as its own file declares them.
    std::map<std::string, json> kinds;
    for (const json& k : all["element_kinds"]) kinds[k["type"].get<std::string>()] = k;
    for (const char* type : {"spring_damper", "clearance", "friction", "gear_mesh", "torque", "cylinder", "order_torque",
                             "speed_source", "speed_controller"}) {
        INFO(type);
        REQUIRE(kinds.count(type) == 1);
        CHECK_FALSE(kinds[type]["summary"].get<std::string>().empty());
    }
    const json& sd = kinds["spring_damper"];
    CHECK(sd["keys"] == json::array({"between", "k", "c"}));
    REQUIRE(sd["fields"].size() == 2);
    CHECK(sd["fields"][0]["key"] == "k");
    CHECK(sd["fields"][0]["unit"] == "N m/rad");
    CHECK(kinds["speed_controller"]["composite"] == true);
    // A composite lists its own numbers too.
    REQUIRE(kinds["speed_controller"]["fields"].size() == 5);  // setpoint, kp, ki and the limits of a sampled one
    CHECK(kinds["speed_controller"]["fields"][1]["key"] == "kp");
    CHECK(kinds["speed_controller"]["fields"][1]["unit"] == "N m s/rad");
    CHECK(r.out.find("element kinds of a custom network") != std::string::npos);
    CHECK(r.out.find("N m s/rad") != std::string::npos);
}

TEST_CASE("command-line misuse exits 2", "[e2e]") {
    CHECK(run_tvid({}).exit_code == 2);
    CHECK(run_tvid({"fit"}).exit_code == 2);
    CHECK(run_tvid({"frobnicate"}).exit_code == 2);
    const RunResult missing = run_tvid({"fit", "/nonexistent/exp.yaml"});
    CHECK(missing.exit_code == 2);
    CHECK(missing.err.find("/nonexistent/exp.yaml") != std::string::npos);
    const RunResult bad_set = run_tvid({"fit", (source_dir() / "configs/cvt_tipin.yaml").string(), "--set", "novalue"});
    CHECK(bad_set.exit_code == 2);
    CHECK(bad_set.err.find("--set") != std::string::npos);
    const RunResult ver = run_tvid({"--version"});
    CHECK(ver.exit_code == 0);
    CHECK(ver.out.find("tvid") != std::string::npos);
}

TEST_CASE("an engine's traces end with the crank angle: cycle k runs from k·720 deg to (k + 1)·720 deg", "[e2e][fit]") {
    // data/engine/idle.csv starts at 0 deg and is sampled every 0.5 deg; cycle k of a
    // four-stroke is [720 k, 720 (k + 1)], scored from its first sample to its last.
    TempDir tmp;
    const auto csv = tmp.path() / "trace.csv";
    const RunResult r = run_tvid({"simulate", (source_dir() / "configs" / "engine_idle.yaml").string(), "-o",
                                  csv.string(), "--threads", "2"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto lines = lines_of(read_text(csv));
    REQUIRE(lines.size() > 2);
    const std::string& header = lines[0];
    CHECK(header.substr(header.rfind(',') + 1) == "crank_deg [deg]");
    std::map<std::string, std::pair<double, double>> span;  // window: first and last angle
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::string& l = lines[i];
        const std::size_t a = l.find(','), b = l.find(',', a + 1);
        const double angle = std::stod(l.substr(l.rfind(',') + 1));
        auto [it, fresh] = span.try_emplace(l.substr(a + 1, b - a - 1), angle, angle);
        if (!fresh) {
            CHECK(angle == Approx(it->second.second + 0.5));  // one sample step on
            it->second.second = angle;
        }
    }
    REQUIRE(span.size() == 7);  // cycle 2 (estimation), cycles 3 … 8 (validation)
    for (int k = 2; k <= 8; ++k) {
        INFO("cycle " << k);
        const auto& [first, last] = span.at("cycle " + std::to_string(k));
        CHECK(first == Approx(720.0 * k));
        CHECK(last == Approx(720.0 * (k + 1)));
    }
}

}  // namespace TVID_UNITY_ID
