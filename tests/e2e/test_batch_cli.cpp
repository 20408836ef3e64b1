// `tvid batch`: many recordings and cycles through the binary: bad input per job, cycle
// windows, --resume after an interruption, thread-count independence, refusing to
// overwrite a batch.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"
#include "tvid/batch/batch_table.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A quick swarm on the CVT clean experiment: 64 particles from a Latin hypercube, 5 iterations.
std::vector<std::string> cvt_batch(const std::vector<std::string>& extra) {
    std::vector<std::string> args{"batch", (source_dir() / "configs/cvt_tipin_clean.yaml").string(),
                                  "--set", "estimation.pso.start=latin_hypercube", "--set", "estimation.pso.particles=64",
                                  "--set", "estimation.pso.iterations=5", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

// Two different recordings (noisy and clean) under `folder`.
void copy_cvt_recordings(const fs::path& folder) {
    fs::create_directories(folder);
    fs::copy_file(source_dir() / "data/cvt/tipin_a.csv", folder / "noisy.csv");
    fs::copy_file(source_dir() / "data/cvt/tipin_clean.csv", folder / "clean.csv");
}

tvid::BatchFile read_table(const fs::path& file) {
    const auto t = tvid::read_batch_file(file);
    REQUIRE(t);
    return *t;
}

// Every row with its wall time blanked out: the only cell that may differ between runs.
std::vector<tvid::BatchRow> without_wall_time(const tvid::BatchFile& t) {
    const auto wall = static_cast<std::size_t>(
        std::find(t.header.begin(), t.header.end(), "wall_seconds") - t.header.begin());
    std::vector<tvid::BatchRow> rows = t.rows;
    for (auto& r : rows) r.at(wall).clear();
    return rows;
}

std::size_t column(const tvid::BatchFile& t, const std::string& name) {
    const auto it = std::find(t.header.begin(), t.header.end(), name);
    REQUIRE(it != t.header.end());
    return static_cast<std::size_t>(it - t.header.begin());
}

}  // namespace

TEST_CASE("tvid batch over recordings: a broken one is bad input, the others are fitted", "[e2e][batch]") {
    TempDir tmp;
    const fs::path rec = tmp.path() / "recordings";
    fs::create_directories(rec);
    fs::copy_file(source_dir() / "data/cvt/tipin_clean.csv", rec / "run1.csv");
    fs::copy_file(source_dir() / "data/cvt/tipin_clean.csv", rec / "run2.csv");
    std::string broken = read_text(source_dir() / "data/cvt/tipin_clean.csv");
    broken.replace(broken.find("\n1.01,") + 1, 4, "n/a");  // a time stamp that is no number
    tmp.write("recordings/broken.csv", broken);
    const fs::path out = tmp.path() / "out";

    const RunResult r = run_tvid(cvt_batch({"--data", (rec / "*.csv").string(), "-o", out.string(), "--json"}));
    INFO(r.err);
    CHECK(r.exit_code == 1);  // a job had bad input
    const tvid::BatchFile t = read_table(out / "batch.csv");
    REQUIRE(t.rows.size() == 3);
    CHECK(t.rows[0][0] == "broken");  // job order: the sorted glob
    CHECK(t.rows[0][1] == "bad_input");
    CHECK(t.rows[0][2].find("broken.csv:") != std::string::npos);
    CHECK(t.rows[0][2].find("is not a number") != std::string::npos);
    CHECK(t.rows[0][column(t, "rho1")].empty());
    for (std::size_t i : {1, 2}) {
        CHECK(t.rows[i][1] == "ok");
        CHECK_FALSE(t.rows[i][column(t, "k_plus")].empty());
        CHECK_FALSE(t.rows[i][column(t, "q_validation")].empty());  // the experiment's validation windows
        CHECK(std::stod(t.rows[i][column(t, "evaluations")]) > 64);
    }
    CHECK(t.rows[1][0] == "run1");
    const json s = json::parse(r.out);  // --json: batch_summary.json on stdout, with where it went
    CHECK(s["report"] == out.string());
    json without_path = s;
    without_path.erase("report");
    CHECK(without_path == json::parse(read_text(out / "batch_summary.json")));
    CHECK(s["jobs"] == 3);
    CHECK(s["ok"] == 2);
    CHECK(s["bad_input"] == 1);
    CHECK(s["failed"] == 0);
    CHECK(s["parameters"]["k_plus"]["count"] == 2);
    CHECK(s["parameters"]["k_plus"]["std"].get<double>() == 0.0);  // the same recording twice
}

TEST_CASE("tvid batch --cycles fits each engine cycle and validates on the next", "[e2e][batch][fits]") {
    TempDir tmp;
    const fs::path out = tmp.path() / "cycles";
    const RunResult r = run_tvid({"batch", (source_dir() / "configs/engine_idle_clean.yaml").string(), "--cycles",
                                  "3-4", "--set", "estimation.lm.max_iterations=2", "-o", out.string()});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.err.find("[2/2] cycle-") != std::string::npos);  // a progress line per job
    CHECK(r.out.find("tvid batch engine-idle-clean: 2 jobs (2 ok") != std::string::npos);
    CHECK(r.out.find("C2") != std::string::npos);
    const tvid::BatchFile t = read_table(out / "batch.csv");
    REQUIRE(t.rows.size() == 2);
    CHECK(t.rows[0][0] == "cycle-3");
    CHECK(t.rows[1][0] == "cycle-4");
    for (const auto& row : t.rows) {
        CHECK(row[1] == "ok");
        CHECK(std::stod(row[column(t, "q_estimation")]) > 90);
        CHECK(std::stod(row[column(t, "q_validation")]) > 90);
        CHECK_FALSE(row[column(t, "fit_validation")].empty());
        CHECK_FALSE(row[column(t, "max_residual_ratio_percent_validation")].empty());
    }
    const json s = json::parse(read_text(out / "batch_summary.json"));
    CHECK(s["ok"] == 2);
    CHECK(s["parameters"]["J1"]["count"] == 2);

    // Cycle 8 has no next cycle to validate on, cycle 9 is not in the recording: bad input.
    for (const std::string cycles : {"7-8", "9"}) {
        const RunResult bad = run_tvid({"batch", (source_dir() / "configs/engine_idle_clean.yaml").string(),
                                        "--cycles", cycles, "-o", (tmp.path() / "bad").string()});
        CHECK(bad.exit_code == 2);
        CHECK(bad.err.find("--cycles: ") == 0);
    }
}

TEST_CASE("tvid batch --resume after an interruption gives the uninterrupted table", "[e2e][batch][fits]") {
    TempDir tmp;
    copy_cvt_recordings(tmp.path() / "rec");
    fs::copy_file(source_dir() / "data/cvt/tipin_clean.csv", tmp.path() / "rec" / "third.csv");
    const std::string glob = (tmp.path() / "rec" / "*.csv").string();
    const fs::path out = tmp.path() / "out";
    REQUIRE(run_tvid(cvt_batch({"--data", glob, "-o", out.string()})).exit_code == 0);
    const tvid::BatchFile full = read_table(out / "batch.csv");
    REQUIRE(full.rows.size() == 3);

    // The interruption: only the header and the first finished row made it to disk,
    // and a second row was torn mid-line.
    const std::string text = read_text(out / "batch.csv");
    std::size_t end = text.find('\n');
    end = text.find('\n', end + 1);
    std::ofstream(out / "batch.csv", std::ios::trunc) << text.substr(0, end + 1) << "third,ok,iterat";
    fs::remove(out / "batch_summary.json");

    const RunResult resumed = run_tvid(cvt_batch({"--data", glob, "-o", out.string(), "--resume", "--json"}));
    INFO(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    const json s = json::parse(resumed.out);
    CHECK(s["run"] == 2);
    CHECK(s["resumed"] == 1);
    CHECK(without_wall_time(read_table(out / "batch.csv")) == without_wall_time(full));
    CHECK(read_table(out / "batch.csv").incomplete_rows == 0);

    // Nothing left to do: a second resume runs no job and keeps the table.
    const RunResult again = run_tvid(cvt_batch({"--data", glob, "-o", out.string(), "--resume", "--json"}));
    CHECK(again.exit_code == 0);
    CHECK(json::parse(again.out)["run"] == 0);
    CHECK(without_wall_time(read_table(out / "batch.csv")) == without_wall_time(full));
}

TEST_CASE("tvid batch gives the same rows on 1 and 2 threads", "[e2e][batch][fits]") {
    TempDir tmp;
    copy_cvt_recordings(tmp.path() / "rec");
    const std::string glob = (tmp.path() / "rec" / "*.csv").string();
    std::vector<std::vector<tvid::BatchRow>> tables;
    for (const std::string threads : {"1", "2"}) {
        const fs::path out = tmp.path() / ("threads" + threads);
        const RunResult r = run_tvid(cvt_batch({"--data", glob, "-o", out.string(), "--threads", threads}));
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        tables.push_back(without_wall_time(read_table(out / "batch.csv")));
    }
    REQUIRE(tables[0].size() == 2);
    CHECK(tables[0][0] != tables[0][1]);  // noisy and clean recordings: different fits
    CHECK(tables[0] == tables[1]);
}

TEST_CASE("tvid batch refuses to overwrite a batch without --resume or --force", "[e2e][batch]") {
    TempDir tmp;
    copy_cvt_recordings(tmp.path() / "rec");
    const fs::path out = tmp.path() / "out";
    tmp.write("out/batch.csv", "id,status\n");
    const std::string glob = (tmp.path() / "rec" / "clean.csv").string();
    const RunResult refused = run_tvid(cvt_batch({"--data", glob, "-o", out.string()}));
    CHECK(refused.exit_code == 2);
    CHECK(refused.err.find("--resume") != std::string::npos);
    CHECK(read_text(out / "batch.csv") == "id,status\n");  // untouched
    // --resume on a table of other columns is refused too; --force starts over.
    CHECK(run_tvid(cvt_batch({"--data", glob, "-o", out.string(), "--resume"})).exit_code == 2);
    const RunResult forced = run_tvid(cvt_batch({"--data", glob, "-o", out.string(), "--force"}));
    CHECK(forced.exit_code == 0);
    CHECK(read_table(out / "batch.csv").rows.size() == 1);

    // Bad input in the batch command itself: no file matches, a bad cycle list.
    CHECK(run_tvid(cvt_batch({"--data", (tmp.path() / "none/*.csv").string(), "-o", out.string()})).exit_code == 2);
    CHECK(run_tvid(cvt_batch({"--cycles", "3-x", "-o", out.string()})).exit_code == 2);
    CHECK(run_tvid(cvt_batch({"-o", out.string()})).exit_code == 2);  // nothing to batch
}

TEST_CASE("tvid batch: a job whose every candidate fails is a failed row, and the batch exits 1", "[e2e][batch]") {
    TempDir tmp;
    const fs::path out = tmp.path() / "out";
    const RunResult r = run_tvid(cvt_batch({"--data", (source_dir() / "data/cvt/tipin_clean.csv").string(), "-o",
                                            out.string(), "--set", "simulation.method=dopri5", "--set",
                                            "simulation.max_steps=1", "--threads", "1", "--json"}));
    INFO(r.err);
    CHECK(r.exit_code == 1);
    const tvid::BatchFile t = read_table(out / "batch.csv");
    REQUIRE(t.rows.size() == 1);
    CHECK(t.rows[0][1] == "failed");
    CHECK(t.rows[0][column(t, "rho1")].empty());  // no parameters were identified
    const json s = json::parse(read_text(out / "batch_summary.json"));
    CHECK(s["failed"] == 1);
    CHECK(s["ok"] == 0);
}

}  // namespace TVID_UNITY_ID
