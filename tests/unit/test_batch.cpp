// Unit tests of the batch library: the job plan (cycle lists, recording ids, overrides),
// batch.csv rows (quoting, reading back, torn lines, atomic rewrites) and the summary statistics.

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

#include "support/test_files.hpp"
#include "tvid/batch/batch_plan.hpp"
#include "tvid/batch/batch_summary.hpp"
#include "tvid/batch/batch_table.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_text;
using tvid::test::TempDir;
using Catch::Matchers::Contains;

TEST_CASE("a cycle list takes ranges and single cycles in the order given", "[batch]") {
    CHECK(parse_cycle_list("3-9") == std::vector<int>{3, 4, 5, 6, 7, 8, 9});
    CHECK(parse_cycle_list("3,5,7") == std::vector<int>{3, 5, 7});
    CHECK(parse_cycle_list("7, 2-3") == std::vector<int>{7, 2, 3});
    CHECK(parse_cycle_list("4") == std::vector<int>{4});
}

TEST_CASE("a bad cycle list is an input error of --cycles", "[batch]") {
    for (const char* bad : {"", "3-", "-3", "a", "3,,4", "1.5", "3-9-10"})
        CHECK_THROWS_WITH(parse_cycle_list(bad), Contains("--cycles: ") && Contains("is not a cycle list"));
    CHECK_THROWS_WITH(parse_cycle_list("5-3"), Contains("runs backwards"));
    CHECK_THROWS_WITH(parse_cycle_list("3-5,4"), Contains("cycle 4 is given twice"));
}

TEST_CASE("jobs: every cycle of every recording, ids from file stems", "[batch]") {
    BatchRequest request;
    request.recordings = {"/data/run_a.csv", "/data/run_b.csv"};
    request.cycles = {3, 4};
    const std::vector<BatchJob> jobs = plan_batch_jobs(request);
    REQUIRE(jobs.size() == 4);
    CHECK(jobs[0].id == "run_a/cycle-3");
    CHECK(jobs[3].id == "run_b/cycle-4");
    REQUIRE(jobs[1].overrides.size() == 3);
    CHECK(jobs[1].overrides[0].key == "data.file");
    CHECK(jobs[1].overrides[0].value == "\"/data/run_a.csv\"");  // quoted: a path is YAML text
    CHECK(jobs[1].overrides[1].key == "windows.estimation");
    CHECK(jobs[1].overrides[1].value == "[ { cycle: 4 } ]");
    CHECK(jobs[1].overrides[2].value == "[ { cycle: 5 } ]");  // validated on the next cycle
}

TEST_CASE("jobs: recordings alone keep the windows, cycles alone keep the recording", "[batch]") {
    BatchRequest recordings;
    recordings.recordings = {"/d/x.csv"};
    const auto r = plan_batch_jobs(recordings);
    REQUIRE(r.size() == 1);
    CHECK(r[0].id == "x");
    CHECK(r[0].overrides.size() == 1);

    BatchRequest cycles;
    cycles.cycles = {2};
    cycles.validation = false;
    const auto c = plan_batch_jobs(cycles);
    REQUIRE(c.size() == 1);
    CHECK(c[0].id == "cycle-2");
    REQUIRE(c[0].overrides.size() == 2);
    CHECK(c[0].overrides[1].key == "windows.validation");
    CHECK(c[0].overrides[1].value == "[]");

    CHECK_THROWS_WITH(plan_batch_jobs(BatchRequest{}), Contains("nothing to batch"));
}

TEST_CASE("jobs: recordings sharing a stem are told apart by their folders", "[batch]") {
    BatchRequest request;
    request.recordings = {"/bench/day1/run.csv", "/bench/day2/run.csv", "/bench/day2/other.csv"};
    const auto jobs = plan_batch_jobs(request);
    CHECK(jobs[0].id == "day1/run");
    CHECK(jobs[1].id == "day2/run");
    CHECK(jobs[2].id == "day2/other");
    request.recordings.push_back("/bench/day1/../day1/run.csv");
    CHECK_THROWS_WITH(plan_batch_jobs(request), Contains("listed twice"));
}

TEST_CASE("a recording list is read relative to its own folder", "[batch]") {
    TempDir tmp;
    const auto list = tmp.write("lists/runs.txt", "# recordings\nrun1.csv\n\n  ../other/run2.csv  \n/abs/run3.csv\n");
    const auto files = read_recording_list(list);
    REQUIRE(files.size() == 3);
    CHECK(files[0] == tmp.path() / "lists" / "run1.csv");
    CHECK(files[1] == tmp.path() / "lists" / "../other/run2.csv");
    CHECK(files[2] == "/abs/run3.csv");
    const auto empty = tmp.write("empty.txt", "# nothing\n");
    CHECK_THROWS_AS(read_recording_list(empty), InputError);
}

TEST_CASE("a glob lists matching files sorted, and nothing matching is an error", "[batch]") {
    TempDir tmp;
    tmp.write("b.csv", "t\n1\n");
    tmp.write("a.csv", "t\n1\n");
    tmp.write("notes.txt", "");
    const auto files = expand_recording_glob((tmp.path() / "*.csv").string());
    REQUIRE(files.size() == 2);
    CHECK(files[0].filename() == "a.csv");
    CHECK_THROWS_WITH(expand_recording_glob((tmp.path() / "*.dat").string()), Contains("--data: no file matches"));
}

TEST_CASE("cycles are checked against the recording, its warm-up and the validation cycle", "[batch]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/engine_idle_clean.yaml");
    CHECK(complete_cycles(ex) == 9);  // crank angle 0 … 7199.5 deg: cycles 0 … 8
    CHECK_NOTHROW(check_cycles_in_recording(ex, {2, 3, 7}, true));
    CHECK_NOTHROW(check_cycles_in_recording(ex, {8}, false));
    CHECK_THROWS_WITH(check_cycles_in_recording(ex, {3, 9}, false), Contains("cycle 9 is outside the data"));
    CHECK_THROWS_WITH(check_cycles_in_recording(ex, {8}, true), Contains("validated on cycle 9"));
    CHECK_THROWS_WITH(check_cycles_in_recording(ex, {1}, true), Contains("warm-up of 2 cycle(s)"));
}

TEST_CASE("batch.csv columns: parameters, cost, metrics per split, counts", "[batch]") {
    const BatchColumns one({"J1", "C1"}, {"omega_dw"});
    CHECK(one.header() == std::vector<std::string>{"id", "status", "message", "J1", "C1", "cost", "q_estimation",
                                                   "fit_estimation", "max_residual_ratio_percent_estimation", "q_validation",
                                                   "fit_validation", "max_residual_ratio_percent_validation", "evaluations",
                                                   "verdict", "findings", "wall_seconds"});
    const BatchColumns two({"k"}, {"a", "b"});
    CHECK(two.index("q_estimation_a") < two.index("q_estimation_b"));
    CHECK(two.index("max_residual_ratio_percent_validation_b") + 5 == two.size());
}

TEST_CASE("rows are quoted where needed and read back unchanged, a torn last line is dropped", "[batch]") {
    TempDir tmp;
    const BatchColumns columns({"p"}, {"y"});
    BatchRow bad = columns.row("r1", kBatchBadInput, "data.csv:12: column y, \"x\": not a number");
    BatchRow ok = columns.row("r2", kBatchOk, "step below xtol");
    ok[columns.index("p")] = batch_number(0.1);
    const auto file = tmp.path() / "batch.csv";
    {
        BatchAppender out(file, batch_csv_line(columns.header()));
        out.append(bad);
        out.append(ok);
    }
    CHECK(batch_csv_line(bad).find("\"data.csv:12: column y, \"\"x\"\": not a number\"") != std::string::npos);
    std::ofstream(file, std::ios::app) << "r3,ok,iteration limit,0.5";  // interrupted mid-line
    const auto read = read_batch_file(file);
    REQUIRE(read);
    CHECK(read->header == columns.header());
    REQUIRE(read->rows.size() == 2);
    CHECK(read->rows[0] == bad);
    CHECK(read->rows[1] == ok);
    CHECK(batch_cell_value(read->rows[1][columns.index("p")]) == 0.1);  // 17 digits read back exactly
    CHECK(read->incomplete_rows == 1);
    CHECK_FALSE(read_batch_file(tmp.path() / "absent.csv"));
}

TEST_CASE("batch.csv is rewritten whole at every row, with no temporary file left", "[batch]") {
    TempDir tmp;
    const BatchColumns columns({"p"}, {"y"});
    const auto file = tmp.path() / "batch.csv";
    const std::string header = batch_csv_line(columns.header());
    BatchAppender out(file, header);
    CHECK(read_text(file) == header);
    std::string expected = header;
    for (const char* id : {"a", "b", "c"}) {
        BatchRow row = columns.row(id, kBatchOk, "converged");
        row[columns.index("p")] = batch_number(1.5);
        out.append(row);
        expected += batch_csv_line(row);
        CHECK(read_text(file) == expected);  // the file holds every row so far, each complete
    }
    // Someone else's bytes appended behind its back are not kept: the file is the appender's.
    std::ofstream(file, std::ios::app) << "torn,o";
    BatchRow last = columns.row("d", kBatchFailed, "every candidate failed");
    out.append(last);
    CHECK(read_text(file) == expected + batch_csv_line(last));
    out.rewrite(header);
    CHECK(read_text(file) == header);
    std::size_t entries = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(tmp.path())) ++entries;
    CHECK(entries == 1);  // batch.csv only: every temporary file was renamed
}

TEST_CASE("the summary spreads the successful rows only", "[batch]") {
    const BatchColumns columns({"p"}, {"y"});
    std::vector<BatchRow> rows;
    for (const auto& [status, value] : std::vector<std::pair<const char*, const char*>>{
             {kBatchOk, "1"}, {kBatchOk, "2"}, {kBatchOk, "4"}, {kBatchFailed, ""}, {kBatchBadInput, "100"}}) {
        BatchRow r = columns.row("j", status, "");
        r[columns.index("p")] = value;
        rows.push_back(r);
    }
    const BatchSummary s = summarize_batch(columns, rows, 5, 10.0, 2);
    CHECK(s.jobs == 5);
    CHECK(s.ok == 3);
    CHECK(s.failed == 1);
    CHECK(s.bad_input == 1);
    CHECK(s.jobs_per_second == Approx(0.5));
    REQUIRE(s.parameters.size() == 1);
    const ColumnSpread& p = s.parameters[0];
    CHECK(p.count == 3);
    CHECK(p.mean == Approx(7.0 / 3.0));
    CHECK(p.std_dev == Approx(std::sqrt(((1 - 7.0 / 3) * (1 - 7.0 / 3) + (2 - 7.0 / 3) * (2 - 7.0 / 3) +
                                         (4 - 7.0 / 3) * (4 - 7.0 / 3)) / 2.0)));
    CHECK(p.min == 1.0);
    CHECK(p.max == 4.0);
    const auto json = batch_summary_json(s, BatchRunContext{"1", "tvid batch", "exp.yaml", "exp", "out"});
    CHECK(json["parameters"]["p"]["mean"].get<double>() == Approx(7.0 / 3.0));
    CHECK(json["metrics"]["q_validation"]["mean"].is_null());  // no values: null, not NaN
    CHECK(json["ok"] == 3);
}

}  // namespace TVID_UNITY_ID
