// `tvid batch --cross`: each job's parameters validated on every job's estimation data.
// The matrix over engine cycles has one row per cycle, its diagonal repeats batch.csv's
// estimation fit, its off-diagonal cells differ, and it is the same on 1 and 2 threads;
// without --cross the stability table is written and no matrix.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>
#include <string>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"
#include "tvid/batch/batch_table.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

tvid::BatchFile read_csv(const fs::path& file) {
    const auto t = tvid::read_batch_file(file);
    REQUIRE(t);
    return *t;
}

std::size_t column_of(const std::vector<std::string>& header, const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    REQUIRE(it != header.end());
    return static_cast<std::size_t>(it - header.begin());
}

// Cycles 3, 4 and 5 of the noise-free engine recording, two LM steps each: three
// different parameter vectors, quickly.
RunResult engine_cross_batch(const fs::path& out, const std::string& threads) {
    return run_tvid({"batch", (source_dir() / "configs/engine_idle_clean.yaml").string(), "--cycles", "3-5", "--set",
                     "estimation.lm.max_iterations=2", "--cross", "--threads", threads, "-o", out.string()});
}

}  // namespace

TEST_CASE("tvid batch --cross: one row per cycle, batch.csv's fit on the diagonal, the same on any thread count",
          "[e2e][batch][cross][fits]") {
    TempDir tmp;
    const RunResult one = engine_cross_batch(tmp.path() / "t1", "1");
    INFO(one.err);
    REQUIRE(one.exit_code == 0);
    CHECK(one.out.find("cross-validation over 3 jobs: fit on own data") != std::string::npos);
    CHECK(one.out.find("matrix: ") != std::string::npos);

    const tvid::BatchFile batch = read_csv(tmp.path() / "t1" / "batch.csv");
    const tvid::BatchFile matrix = read_csv(tmp.path() / "t1" / "matrix.csv");
    REQUIRE(batch.rows.size() == 3);
    REQUIRE(matrix.rows.size() == 3);  // one row per fitted cycle
    const std::vector<std::string> ids{"cycle-3", "cycle-4", "cycle-5"};
    CHECK(matrix.header == std::vector<std::string>{"fitted", "fit_cycle-3", "rmse_cycle-3", "fit_cycle-4",
                                                    "rmse_cycle-4", "fit_cycle-5", "rmse_cycle-5"});
    const std::size_t own_fit = column_of(batch.header, "fit_estimation");
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(matrix.rows[i][0] == ids[i]);
        // The diagonal: this cycle's parameters on its own window, as batch.csv has it (the same digits).
        CHECK(matrix.rows[i][column_of(matrix.header, "fit_" + ids[i])] == batch.rows[i][own_fit]);
        for (std::size_t j = 0; j < 3; ++j) {
            const double fit = std::stod(matrix.rows[i][column_of(matrix.header, "fit_" + ids[j])]);
            const double rmse = std::stod(matrix.rows[i][column_of(matrix.header, "rmse_" + ids[j])]);
            CHECK(fit > 50.0);  // two LM steps from a prior 20 % off already explain most of the speed
            CHECK(fit < 100.0);
            CHECK(rmse > 0.0);
            // Off the diagonal, another cycle's data: not the fitted cycle's own figure.
            if (j != i) CHECK(matrix.rows[i][column_of(matrix.header, "fit_" + ids[j])] != batch.rows[i][own_fit]);
        }
    }
    // The long form holds the same cells, one per line.
    const tvid::BatchFile longform = read_csv(tmp.path() / "t1" / "matrix_long.csv");
    CHECK(longform.rows.size() == 9);
    CHECK(longform.rows[1][0] == "cycle-3");
    CHECK(longform.rows[1][1] == "cycle-4");
    CHECK(longform.rows[1][3] == matrix.rows[0][column_of(matrix.header, "fit_cycle-4")]);

    const json s = json::parse(read_text(tmp.path() / "t1" / "batch_summary.json"));
    REQUIRE(s["cross"].is_object());
    CHECK(s["cross"]["jobs"].size() == 3);
    CHECK(s["cross"]["failed_cells"] == 0);
    CHECK(s["parameter_stability"]["J1"]["count"] == 3);
    CHECK(s["parameter_stability"]["J1"]["unit"] == "kg m^2");
    const json& j1 = s["parameter_stability"]["J1"];
    CHECK(j1["cv"].get<double>() == Approx(j1["std"].get<double>() / j1["mean"].get<double>()));
    CHECK(s["outliers"].is_array());
    CHECK(fs::exists(tmp.path() / "t1" / "parameter_stability.csv"));

    const RunResult two = engine_cross_batch(tmp.path() / "t2", "2");
    INFO(two.err);
    REQUIRE(two.exit_code == 0);
    CHECK(read_text(tmp.path() / "t2" / "matrix.csv") == read_text(tmp.path() / "t1" / "matrix.csv"));
    CHECK(read_text(tmp.path() / "t2" / "matrix_long.csv") == read_text(tmp.path() / "t1" / "matrix_long.csv"));
    CHECK(read_text(tmp.path() / "t2" / "parameter_stability.csv") ==
          read_text(tmp.path() / "t1" / "parameter_stability.csv"));

    // --resume on the finished batch fits nothing and computes the matrix again from batch.csv.
    const std::string matrix_text = read_text(tmp.path() / "t1" / "matrix.csv");
    fs::remove(tmp.path() / "t1" / "matrix.csv");
    const RunResult resumed =
        run_tvid({"batch", (source_dir() / "configs/engine_idle_clean.yaml").string(), "--cycles", "3-5", "--set",
                  "estimation.lm.max_iterations=2", "--cross", "--resume", "-o", (tmp.path() / "t1").string(),
                  "--json"});
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    CHECK(json::parse(resumed.out)["run"] == 0);
    CHECK(read_text(tmp.path() / "t1" / "matrix.csv") == matrix_text);
}

TEST_CASE("tvid batch --cross over recordings, without --cross no matrix, but the stability table",
          "[e2e][batch][cross]") {
    TempDir tmp;
    const fs::path rec = tmp.path() / "recordings";
    fs::create_directories(rec);
    fs::copy_file(source_dir() / "data/cvt/tipin_a.csv", rec / "noisy.csv");
    fs::copy_file(source_dir() / "data/cvt/tipin_clean.csv", rec / "clean.csv");
    const auto cvt = [&](const fs::path& out, bool cross) {
        std::vector<std::string> args{"batch", (source_dir() / "configs/cvt_tipin_clean.yaml").string(),
                                      "--set", "estimation.pso.iterations=5", "--data", (rec / "*.csv").string(),
                                      "-o", out.string(), "--quiet"};
        if (cross) args.push_back("--cross");
        return run_tvid(args);
    };
    const RunResult r = cvt(tmp.path() / "cross", true);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const tvid::BatchFile batch = read_csv(tmp.path() / "cross" / "batch.csv");
    const tvid::BatchFile matrix = read_csv(tmp.path() / "cross" / "matrix.csv");
    REQUIRE(matrix.rows.size() == 2);
    CHECK(matrix.rows[0][0] == "clean");
    CHECK(matrix.rows[1][0] == "noisy");
    const std::size_t own_fit = column_of(batch.header, "fit_estimation");
    CHECK(matrix.rows[0][column_of(matrix.header, "fit_clean")] == batch.rows[0][own_fit]);
    CHECK(matrix.rows[1][column_of(matrix.header, "fit_noisy")] == batch.rows[1][own_fit]);
    CHECK(matrix.rows[0][column_of(matrix.header, "fit_noisy")] != batch.rows[0][own_fit]);

    const RunResult plain = cvt(tmp.path() / "plain", false);
    REQUIRE(plain.exit_code == 0);
    CHECK_FALSE(fs::exists(tmp.path() / "plain" / "matrix.csv"));
    CHECK(fs::exists(tmp.path() / "plain" / "parameter_stability.csv"));
    const json s = json::parse(read_text(tmp.path() / "plain" / "batch_summary.json"));
    CHECK(s["cross"].is_null());
    CHECK(s["parameter_stability"]["k_plus"]["count"] == 2);
    CHECK(read_csv(tmp.path() / "plain" / "parameter_stability.csv").header ==
          std::vector<std::string>{"parameter", "unit", "count", "mean", "std", "cv", "median", "mad", "min", "max",
                                   "outliers"});
}

TEST_CASE("tvid batch --cross with estimated starts estimates each validated job's start with the fitted job's model "
          "held",
          "[e2e][batch][cross][estimated_start]") {
    // The noise-free free line (an independent numpy recording, configs/free_line_clean.yaml)
    // cut in two recordings that start in different states: each job's start corrections
    // belong to its own recording, so the other job's model, exact too, must fit it as well
    // once its start is estimated again (job A's corrections on B's seed missed by far).
    TempDir tmp;
    const fs::path rec = tmp.path() / "recordings";
    fs::create_directories(rec);
    std::istringstream lines(read_text(source_dir() / "data/free_line/free_line_clean.csv"));
    std::string header, line, first, second;
    std::getline(lines, header);
    for (std::size_t k = 0; std::getline(lines, line); ++k) (k < 3000 ? first : second) += line + "\n";
    tmp.write("recordings/a_first.csv", header + "\n" + first);
    tmp.write("recordings/b_second.csv", header + "\n" + second);
    std::vector<std::string> args{"batch", (source_dir() / "configs/free_line_clean.yaml").string(), "--data",
                                  (rec / "*.csv").string(), "--set", "windows.estimation=[{samples: [0, 1000]}]",
                                  "--set", "windows.validation=[]", "--cross", "-o", (tmp.path() / "out").string(),
                                  "--quiet"};
    const json truth = json::parse(read_text(source_dir() / "data/free_line/truth.json"))["parameters"];
    for (const auto& [name, value] : truth.items()) {
        args.push_back("--set");
        args.push_back("parameters." + name + ".init=" + value.dump());
    }
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const tvid::BatchFile matrix = read_csv(tmp.path() / "out" / "matrix.csv");
    REQUIRE(matrix.rows.size() == 2);
    for (const auto& row : matrix.rows)
        for (const std::string job : {"a_first", "b_second"})
            for (const std::string output : {"w_engine", "T_shaft", "w_vehicle"}) {
                INFO(row[0] << " on " << job << ": " << output);
                CHECK(std::stod(row[column_of(matrix.header, "fit_" + job + "_" + output)]) > 99.99999);
            }
}

}  // namespace TVID_UNITY_ID
