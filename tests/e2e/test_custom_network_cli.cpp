// A network written in the experiment file runs through the binary: the cvt_clearance
// preset rebuilt from nodes and elements gives the preset's cost to rounding, and a
// two-node gear train simulates with its ratio.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

std::vector<std::string> cells_of(const std::string& line) {
    std::vector<std::string> cells;
    std::istringstream in(line);
    for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
    return cells;
}

std::size_t column_index(const std::vector<std::string>& header, const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    REQUIRE(it != header.end());
    return static_cast<std::size_t>(it - header.begin());
}

// The cvt_clearance preset (Yoshida & Takamatsu eqs. 15-16) as a custom network. The parameters
// are declared in another order than the preset's, all fixed at `truth`.
std::string cvt_as_custom_network(const json& truth) {
    std::ostringstream s;
    s << "tvid: 1\n"
         "name: cvt-custom\n"
         "data:\n"
         "  file: '"
      << (source_dir() / "data/cvt/tipin_clean.csv").string()
      << "'\n"
         "  time: t\n"
         "model:\n"
         "  nodes:\n"
         "    - { name: input_shaft, inverse_J: rho1 }\n"
         "  elements:\n"
         "    - { type: torque, name: cvt_torque, node: input_shaft, input: Ttm, offset: d_tm }\n"
         "    - { type: clearance, name: gear_backlash, between: [input_shaft, ground],\n"
         "        k_minus: k_minus, k_plus: k_plus, c_minus: c_minus, c_plus: c_plus, mu: mu, sigma: sigma }\n"
         "inputs: { Ttm: Ttm }\n"
         "outputs:\n"
         "  Tds: { column: Tds, torque: gear_backlash, offset: d_ds }\n"
         "parameters:\n";
    for (const char* name : {"d_tm", "d_ds", "sigma", "mu", "rho1", "c_plus", "c_minus", "k_plus", "k_minus"})
        s << "  " << name << ": { value: " << truth.at(name).dump() << " }\n";
    s << "windows:\n"
         "  estimation: [ { time: [1.5, 3.0] } ]\n"
         "  validation: [ { time: [1.0, 1.5] }, { time: [3.0, 3.5] } ]\n"
         "initial_state: equilibrium\n"
         "simulation: { method: rk4, step: sample }\n"
         "estimation: { cost: l1 }\n";
    return s.str();
}

}  // namespace

TEST_CASE("the cvt_clearance preset written as a custom network gives the preset's cost", "[e2e][network]") {
    const json truth = json::parse(read_text(source_dir() / "data/cvt/truth.json"));
    TempDir tmp;
    const auto params = tmp.write("P.json", truth.at("parameters").dump(2));
    const auto custom = tmp.write("cvt_custom.yaml", cvt_as_custom_network(truth.at("parameters")));

    const RunResult c = run_tvid({"validate", custom.string(), "--params", params.string(), "--json"});
    INFO("custom stderr: " << c.err);
    REQUIRE(c.exit_code == 0);
    const RunResult p = run_tvid(
        {"validate", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "--params", params.string(), "--json"});
    INFO("preset stderr: " << p.err);
    REQUIRE(p.exit_code == 0);

    const json cj = json::parse(c.out), pj = json::parse(p.out);
    const double custom_cost = cj.at("cost").get<double>();
    const double preset_cost = pj.at("cost").get<double>();
    CHECK(custom_cost == Approx(preset_cost).epsilon(1e-12));
    CHECK(custom_cost == Approx(truth["reference_costs"]["clean"]["E"].get<double>()).epsilon(1e-6));
    CHECK(cj["estimation"]["pooled"]["Tds"]["samples"] == 1500);
    // The validation windows agree as well.
    CHECK(cj["validation"]["pooled"]["Tds"]["cost_l1"].get<double>() ==
          Approx(pj["validation"]["pooled"]["Tds"]["cost_l1"].get<double>()).epsilon(1e-12));
    CHECK(cj["validation"]["pooled"]["Tds"]["samples"] == 1000);

    // An empty parameter file keeps the experiment's fixed values, the truth: the same cost again.
    const RunResult own = run_tvid({"validate", custom.string(), "--params", tmp.write("empty.json", "{}").string(), "--json"});
    REQUIRE(own.exit_code == 0);
    CHECK(json::parse(own.out).at("cost").get<double>() == Approx(preset_cost).epsilon(1e-12));
}

TEST_CASE("a two-node gear train driven by a torque input simulates", "[e2e][network]") {
    // Motor side a, load side b, a stiff mesh of ratio 3: the load turns a third as far.
    auto experiment = [](const std::string& mesh_extra) {
        return "tvid: 1\n"
               "name: gear-train\n"
               "data: { file: '" +
               (source_dir() / "data/cvt/tipin_clean.csv").string() +
               "', time: t }\n"
               "model:\n"
               "  nodes:\n"
               "    - { name: a, J: 0.1 }\n"
               "    - { name: b, J: J_b }\n"
               "  elements:\n"
               "    - { type: torque, name: drive, node: a, input: T_drive }\n"
               "    - { type: gear_mesh, name: stage, between: [a, b], ratio: 3, k: 1000, c: 5" +
               mesh_extra +
               " }\n"
               "    - { type: friction, name: bearing, node: b, c: c_b }\n"
               "inputs: { T_drive: Ttm }\n"
               "outputs:\n"
               "  theta_a: { column: Ttm, angle: a }\n"
               "  theta_b: { column: Tds, angle: b }\n"
               "  T_mesh:  { column: Tds, torque: stage }\n"
               "parameters:\n"
               "  J_b: { value: 0.5 }\n"
               "  c_b: { value: 0.5 }\n"
               "windows:\n"
               "  estimation: [ { samples: [0, 200] } ]\n"
               "initial_state: rest\n"
               "simulation: { method: rk4, step: sample }\n";
    };
    for (const char* extra : {"", ", mu: 0.001, sigma: 5000"}) {
        SECTION(std::string("mesh") + extra) {
            TempDir tmp;
            const auto exp = tmp.write("gear.yaml", experiment(extra));
            const auto out = tmp.path() / "sim.csv";
            const RunResult r = run_tvid({"simulate", exp.string(), "-o", out.string()});
            INFO("stderr: " << r.err);
            REQUIRE(r.exit_code == 0);
            const auto lines = lines_of(read_text(out));
            REQUIRE(lines.size() == 1 + 200);  // header + samples 1..200
            const auto header = cells_of(lines[0]);
            const std::size_t ia = column_index(header, "theta_a_simulated [rad]");
            const std::size_t ib = column_index(header, "theta_b_simulated [rad]");
            const std::size_t it = column_index(header, "T_mesh_simulated [N m]");
            for (std::size_t i = 1; i < lines.size(); ++i) {
                const auto cells = cells_of(lines[i]);
                REQUIRE(cells.size() == header.size());
                for (std::size_t k : {ia, ib, it}) CHECK(std::isfinite(std::stod(cells[k])));
            }
            // Ttm > 0 drives node a forward; after 0.2 s the load follows through the ratio.
            const auto last = cells_of(lines.back());
            const double theta_a = std::stod(last[ia]), theta_b = std::stod(last[ib]);
            CHECK(theta_a > 0.1);
            CHECK(theta_b > 0);
            CHECK(theta_a / theta_b == Approx(3.0).epsilon(0.05));
        }
    }
}

TEST_CASE("the shipped custom-network example identifies the CVT model by least squares", "[e2e][network]") {
    // configs/cvt_custom_network.yaml fits the noisy tip-in recording from the middle of the
    // paper's search domain. On noisy data the fit must cost no more than the truth does, and
    // the well-determined stiffness on the engaged side must come within 2 % of the truth.
    const json truth = json::parse(read_text(source_dir() / "data/cvt/truth.json")).at("parameters");
    TempDir tmp;
    const auto config = (source_dir() / "configs/cvt_custom_network.yaml").string();
    const RunResult fit = run_tvid({"fit", config, "-o", (tmp.path() / "report").string(), "--quiet"});
    INFO("stderr: " << fit.err);
    REQUIRE(fit.exit_code == 0);
    const json summary = json::parse(read_text(tmp.path() / "report/summary.json"));
    CHECK(summary["optimizer"]["converged"] == true);
    const double fitted_cost = summary["cost"]["value"].get<double>();

    const auto truth_file = tmp.write("truth.json", truth.dump());
    const RunResult at_truth = run_tvid({"validate", config, "--params", truth_file.string(), "--json"});
    REQUIRE(at_truth.exit_code == 0);
    const double truth_cost = json::parse(at_truth.out).at("cost").get<double>();
    CHECK(fitted_cost <= truth_cost);
    CHECK(fitted_cost > 0.9 * truth_cost);  // the noise is not fitted away

    const json params = json::parse(read_text(tmp.path() / "report/params.json"));
    for (const json& p : params["parameters"])
        if (p["name"] == "k_plus")
            CHECK(p["value"].get<double>() == Approx(truth["k_plus"].get<double>()).epsilon(0.02));
}

}  // namespace TVID_UNITY_ID
