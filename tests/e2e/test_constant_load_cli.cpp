// A constant torque (`torque` with `value:`) on a line not tied to ground, fitted by `tvid fit`
// on recordings made by scripts/generate_constant_load_data.py (numpy, its own RK4): the
// noise-free one gives the truth back, the noisy one reaches its noise floor.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <cmath>
#include <map>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

const std::string kConfig = (source_dir() / "configs/constant_load.yaml").string();

std::map<std::string, double> truth() {
    const json t = json::parse(read_text(source_dir() / "data/constant_load/truth.json"));
    std::map<std::string, double> out;
    for (auto it = t["parameters"].begin(); it != t["parameters"].end(); ++it) out[it.key()] = it.value().get<double>();
    return out;
}

json fit(const TempDir& tmp, std::vector<std::string> extra) {
    std::vector<std::string> args{"fit", kConfig, "-o", (tmp.path() / "fit").string(), "--threads", "2", "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return json::parse(r.out);
}

}  // namespace

TEST_CASE("a constant load torque as a parameter: the noise-free recording gives every parameter back",
          "[e2e][elements]") {
    const TempDir tmp;
    const json s = fit(tmp, {"--set", "data.file=../data/constant_load/constant_load_clean.csv"});
    CHECK(s["optimizer"]["converged"] == true);
    const auto t = truth();
    for (const json& p : s["parameters"]) {
        const std::string name = p["name"].get<std::string>();
        INFO(name << " = " << p["value"].get<double>() << ", truth " << t.at(name));
        CHECK(p["value"].get<double>() == Approx(t.at(name)).epsilon(1e-5));
    }
    CHECK(s["parameters"][5]["unit"] == "N m");  // T_load, a torque
}

TEST_CASE("a constant load torque on the noisy recording: the noise floor, the truth within its errors",
          "[e2e][elements]") {
    const TempDir tmp;
    const json s = fit(tmp, {});
    const json noise = json::parse(read_text(source_dir() / "data/constant_load/truth.json"))["noise_std"];
    // Validation over the last 1.5 s, never fitted: at the sensors' noise.
    const json& v = s["validation"]["pooled"];
    CHECK(v["w2"]["rmse"].get<double>() < 1.1 * noise["w2"].get<double>());
    CHECK(v["T_shaft"]["rmse"].get<double>() < 1.1 * noise["T_shaft"].get<double>());
    const auto t = truth();
    for (const json& p : s["parameters"]) {
        const std::string name = p["name"].get<std::string>();
        const double value = p["value"].get<double>(), se = p["std_error"].get<double>();
        INFO(name << " = " << value << " ± " << se << ", truth " << t.at(name));
        CHECK(std::abs(value - t.at(name)) < 4.0 * se);
    }
}

TEST_CASE("a torque is a measured input or a constant value, never both or neither", "[e2e][elements]") {
    const TempDir tmp;
    const std::string yaml = read_text(kConfig);
    const auto variant = [&](const std::string& from, const std::string& to) {
        std::string text = yaml;
        text.replace(text.find(from), from.size(), to);
        const auto file = tmp.write("configs/variant.yaml", text);
        return run_tvid({"simulate", file.string(), "-o", (tmp.path() / "simulated.csv").string()});
    };
    // The data path is relative to configs/: the variants go to a configs/ beside a copy of data/.
    std::filesystem::create_directories(tmp.path() / "data");
    std::filesystem::copy(source_dir() / "data/constant_load", tmp.path() / "data/constant_load");
    const std::string brake = "{ type: torque, name: brake, node: load, value: T_load }";
    const RunResult both = variant(brake, "{ type: torque, name: brake, node: load, value: T_load, input: T_motor }");
    CHECK(both.exit_code == 2);
    CHECK(both.err.find("variant.yaml:") != std::string::npos);
    CHECK(both.err.find("input") != std::string::npos);
    CHECK(both.err.find("not both") != std::string::npos);
    const RunResult neither = variant(brake, "{ type: torque, name: brake, node: load }");
    CHECK(neither.exit_code == 2);
    CHECK(neither.err.find("value:") != std::string::npos);
}

}  // namespace TVID_UNITY_ID
