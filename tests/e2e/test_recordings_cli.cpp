// Several recordings in one experiment (data.recordings) through the tvid binary, on real
// files: the shipped constant-load recording cut in two gives the fit and the validation
// of the one file with time windows; a delayed channel at the start of the second
// recording reads that recording as it alone would; the Aalto bench's three runs in one
// experiment give the figures of the three separate configs; bad lists are one error line.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/shipped_fit.hpp"
#include "support/test_files.hpp"
#include "tvid/io/sha256.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

const std::filesystem::path kRecording = source_dir() / "data/constant_load/constant_load.csv";

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// The constant-load recording (t = 0 … 4 s at 1 ms) cut after t = 2.5 s into run1.csv and
// run2.csv; run2_from_0.csv is run2 with its clock restarted at 0.
void write_cut_recording(const TempDir& tmp) {
    const std::vector<std::string> lines = lines_of(read_text(kRecording));
    REQUIRE(lines.size() == 4002);
    std::string run1, run2, run2_from_0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (i == 0 || i <= 2501) run1 += lines[i] + "\n";
        if (i == 0 || i > 2501) run2 += lines[i] + "\n";
        if (i == 0) run2_from_0 += lines[i] + "\n";
        if (i > 2501) {
            std::ostringstream t;
            t << static_cast<double>(i - 2502) * 0.001;
            run2_from_0 += t.str() + lines[i].substr(lines[i].find(',')) + "\n";
        }
    }
    REQUIRE(lines[2501].rfind("2.5,", 0) == 0);
    tmp.write("run1.csv", run1);
    tmp.write("run2.csv", run2);
    tmp.write("run2_from_0.csv", run2_from_0);
}

// configs/constant_load.yaml with its data and windows replaced.
std::filesystem::path constant_load_variant(const TempDir& tmp, const std::string& name, const std::string& data,
                                            const std::string& windows) {
    std::string text = read_text(source_dir() / "configs/constant_load.yaml");
    const auto replace = [&](const std::string& from, const std::string& to) {
        REQUIRE(text.find(from) != std::string::npos);
        text.replace(text.find(from), from.size(), to);
    };
    replace("data:\n  file: ../data/constant_load/constant_load.csv\n  time: t\n", "data:\n" + data);
    replace("  estimation: [ { time: [0, 2.5] } ]\n  validation: [ { time: [0, 4] } ]\n", windows);
    replace("report: { dir: ../results/constant-load }\n", "");
    return tmp.write(name + ".yaml", text);
}

const std::string kTwoRecordings =
    "  recordings:\n    - { name: run1, file: run1.csv, time: t }\n    - { name: run2, file: run2.csv, time: t }\n";
const std::string kOneFile = "  file: " + kRecording.string() + "\n  time: t\n";
const std::string kRecordingWindows =
    "  estimation: [ { recording: run1 } ]\n  validation: [ { recording: run2 } ]\n";
const std::string kTimeWindows = "  estimation: [ { time: [0, 2.5] } ]\n  validation: [ { time: [2.501, 4] } ]\n";

json fit(const std::filesystem::path& experiment, const std::filesystem::path& out) {
    const RunResult r = run_tvid({"fit", experiment.string(), "-o", out.string(), "--threads", "2", "--quiet"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return json::parse(read_text(out / "summary.json"));
}

json validate(const std::filesystem::path& experiment, const std::filesystem::path& params) {
    const RunResult r = run_tvid({"validate", experiment.string(), "--params", params.string(), "--json"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return json::parse(r.out);
}

double relative_difference(double a, double b) {
    return a == b ? 0.0 : std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}

// Every free parameter of two summaries equal to `tolerance`, relatively.
void check_same_parameters(const json& a, const json& b, double tolerance) {
    REQUIRE(a["parameters"].size() == b["parameters"].size());
    for (std::size_t i = 0; i < a["parameters"].size(); ++i) {
        const json& p = a["parameters"][i];
        INFO(p["name"] << " " << p["value"] << " against " << b["parameters"][i]["value"]);
        CHECK(relative_difference(p["value"].get<double>(), b["parameters"][i]["value"].get<double>()) <= tolerance);
    }
}

// The pooled RMSE and fit % of every output of two splits equal to `tolerance`, relatively.
void check_same_split(const json& a, const json& b, double tolerance) {
    for (const auto& [output, m] : a["pooled"].items()) {
        INFO(output << ": RMSE " << m["rmse"] << " against " << b["pooled"][output]["rmse"]);
        CHECK(relative_difference(m["rmse"].get<double>(), b["pooled"][output]["rmse"].get<double>()) <= tolerance);
        CHECK(relative_difference(m["fit_percent"].get<double>(), b["pooled"][output]["fit_percent"].get<double>()) <=
              tolerance);
    }
}

}  // namespace

TEST_CASE("a recording cut in two: estimating on the first and validating on the second is the one file with time windows",
          "[e2e][recordings]") {
    const TempDir tmp;
    write_cut_recording(tmp);
    const json cut = fit(constant_load_variant(tmp, "cut", kTwoRecordings, kRecordingWindows), tmp.path() / "cut");
    const json whole = fit(constant_load_variant(tmp, "whole", kOneFile, kTimeWindows), tmp.path() / "whole");
    check_same_parameters(cut, whole, 1e-9);
    CHECK(relative_difference(cut["cost"]["value"].get<double>(), whole["cost"]["value"].get<double>()) <= 1e-9);
    check_same_split(cut["estimation"], whole["estimation"], 1e-9);
    check_same_split(cut["validation"], whole["validation"], 1e-9);

    // One row per window, labelled with its recording; one digest per recording read.
    REQUIRE(cut["validation"]["windows"].size() == 1);
    CHECK(cut["validation"]["windows"][0]["window"] == "run2: whole recording");
    CHECK(cut["validation"]["windows"][0]["recording"] == "run2");
    CHECK(cut["estimation"]["windows"][0]["recording"] == "run1");
    CHECK(whole["validation"]["windows"][0].count("recording") == 0);
    REQUIRE(cut["data_sha256"].size() == 2);
    CHECK(cut["data"][1].get<std::string>().find("run2.csv") != std::string::npos);
    CHECK(cut["recordings"][1]["name"] == "run2");
    CHECK(cut["recordings"][1]["samples"] == 1500);
    CHECK(cut["recordings"][0]["sha256"] == cut["data_sha256"][0]);
    CHECK(cut["data_sha256"][0] != cut["data_sha256"][1]);
    CHECK(whole["data_sha256"].is_string());

    // The second recording's rows carry its own time stamps and its window's label.
    const std::vector<std::string> rows = lines_of(read_text(tmp.path() / "cut" / "validation.csv"));
    REQUIRE(rows.size() == 1500);  // the header and the 1499 samples after the start sample
    CHECK(rows[1].rfind("2.502,run2: whole recording,", 0) == 0);
}

TEST_CASE("a second recording whose clock starts again at 0 validates as the one file, to rounding",
          "[e2e][recordings]") {
    const TempDir tmp;
    write_cut_recording(tmp);
    std::string recordings = kTwoRecordings;
    recordings.replace(recordings.find("run2.csv"), 8, "run2_from_0.csv");
    const json restarted = fit(constant_load_variant(tmp, "restarted", recordings, kRecordingWindows), tmp.path() / "r");
    const json whole = fit(constant_load_variant(tmp, "whole", kOneFile, kTimeWindows), tmp.path() / "whole");
    check_same_parameters(restarted, whole, 1e-9);
    check_same_split(restarted["validation"], whole["validation"], 1e-9);
    // Its rows are on its own clock: the first scored sample is its second, t = 0.001 s.
    const std::vector<std::string> rows = lines_of(read_text(tmp.path() / "r" / "validation.csv"));
    CHECK(rows[1].rfind("0.001,run2: whole recording,", 0) == 0);
}

TEST_CASE("tvid validate on a second recording gives that recording's figures", "[e2e][recordings]") {
    const TempDir tmp;
    write_cut_recording(tmp);
    fit(constant_load_variant(tmp, "whole", kOneFile, kTimeWindows), tmp.path() / "whole");
    const std::filesystem::path params = tmp.path() / "whole" / "params.json";
    const json cut = validate(constant_load_variant(tmp, "cut", kTwoRecordings, kRecordingWindows), params);
    const json whole = validate(constant_load_variant(tmp, "whole", kOneFile, kTimeWindows), params);
    const json alone = validate(
        constant_load_variant(tmp, "alone", "  file: run2.csv\n  time: t\n",
                              "  estimation: [ { samples: [0, 1499] } ]\n  validation: [ { samples: [0, 1499] } ]\n"),
        params);
    check_same_split(cut["validation"], whole["validation"], 1e-9);
    check_same_split(cut["validation"], alone["validation"], 1e-12);
    CHECK(cut["validation"]["windows"][0]["recording"] == "run2");
}

TEST_CASE("a delayed channel at the start of the second recording reads that recording, not the first",
          "[e2e][recordings]") {
    const TempDir tmp;
    write_cut_recording(tmp);
    fit(constant_load_variant(tmp, "whole", kOneFile, kTimeWindows), tmp.path() / "whole");
    const std::filesystem::path params = tmp.path() / "whole" / "params.json";
    // Recorded early by 3.5 samples: at the second recording's start the input reads 3.5 ms
    // before it, which the second file alone holds at its first sample.
    const auto delayed = [&](const std::string& name, const std::string& data, const std::string& windows) {
        const std::filesystem::path file = constant_load_variant(tmp, name, data, windows);
        std::string text = read_text(file);
        const std::string from = "inputs: { T_motor: T_motor }";
        REQUIRE(text.find(from) != std::string::npos);
        text.replace(text.find(from), from.size(), "inputs: { T_motor: { column: T_motor, delay: -0.0035 } }");
        return validate(tmp.write(name + ".yaml", text), params);
    };
    const json cut = delayed("cut", kTwoRecordings, kRecordingWindows);
    const json alone = delayed("alone", "  file: run2.csv\n  time: t\n",
                               "  estimation: [ { samples: [0, 1499] } ]\n  validation: [ { samples: [0, 1499] } ]\n");
    const json across = delayed("whole", kOneFile, kTimeWindows);  // the one file reads the first part there
    check_same_split(cut["validation"], alone["validation"], 1e-12);
    const double rmse = cut["validation"]["pooled"]["T_shaft"]["rmse"].get<double>();
    CHECK(relative_difference(rmse, across["validation"]["pooled"]["T_shaft"]["rmse"].get<double>()) > 1e-9);
}

TEST_CASE("a steady start near the end of the first recording averages that recording only", "[e2e][recordings]") {
    const TempDir tmp;
    write_cut_recording(tmp);
    fit(constant_load_variant(tmp, "whole", kOneFile, kTimeWindows), tmp.path() / "whole");
    const std::filesystem::path params = tmp.path() / "whole" / "params.json";
    // 200 samples averaged from the window's start, 50 before the first recording ends.
    const auto steady = [&](const std::string& name, const std::string& data, const std::string& windows) {
        const std::filesystem::path file = constant_load_variant(tmp, name, data, windows);
        std::string text = read_text(file);
        const std::string from = "initial_state: rest";
        REQUIRE(text.find(from) != std::string::npos);
        text.replace(text.find(from), from.size(), "initial_state: { kind: steady, node: load, speed: w2, samples: 200 }");
        return validate(tmp.write(name + ".yaml", text), params);
    };
    const json cut = steady("cut", kTwoRecordings,
                            "  estimation: [ { recording: run1 } ]\n"
                            "  validation: [ { recording: run1, time: [2.45, 2.5] } ]\n");
    const json alone = steady("alone", "  file: run1.csv\n  time: t\n",
                              "  estimation: [ { time: [0, 2.5] } ]\n  validation: [ { time: [2.45, 2.5] } ]\n");
    const json across = steady("whole", kOneFile, "  estimation: [ { time: [0, 2.5] } ]\n"
                                                  "  validation: [ { time: [2.45, 2.5] } ]\n");
    check_same_split(cut["validation"], alone["validation"], 0.0);
    const double rmse = cut["validation"]["pooled"]["w2"]["rmse"].get<double>();
    CHECK(relative_difference(rmse, across["validation"]["pooled"]["w2"]["rmse"].get<double>()) > 1e-9);
}

// data/engine/idle.csv (10 cycles at 0.5 deg, cumulative crank angle) cut at 3600 deg:
// engine_a.csv holds cycles 0-4 of the recording, engine_b.csv cycles 5-9, its crank
// angle going on from 3600 deg (less than a cycle after the first's last sample).
void write_cut_engine(const TempDir& tmp) {
    const std::vector<std::string> lines = lines_of(read_text(source_dir() / "data/engine/idle.csv"));
    std::size_t header = 0;
    while (lines[header].rfind("t,crank_deg", 0) != 0) ++header;
    std::string a = lines[header] + "\n", b = a;
    for (std::size_t i = header + 1; i < lines.size(); ++i) {
        const double angle = std::stod(lines[i].substr(lines[i].find(',') + 1));
        (angle < 3600 ? a : b) += lines[i] + "\n";
    }
    tmp.write("engine_a.csv", a);
    tmp.write("engine_b.csv", b);
}

std::filesystem::path engine_variant(const TempDir& tmp, const std::string& name, const std::string& data,
                                     const std::string& windows) {
    std::string text = read_text(source_dir() / "configs/engine_idle.yaml");
    const auto replace = [&](const std::string& from, const std::string& to) {
        REQUIRE(text.find(from) != std::string::npos);
        text.replace(text.find(from), from.size(), to);
    };
    replace("  file: ../data/engine/idle.csv      # synthetic idle recording with sensor noise\n  time: t\n", data);
    replace("  estimation: [ { cycle: 2 } ]\n"
            "  validation: [ { cycle: 3 }, { cycle: 4 }, { cycle: 5 }, { cycle: 6 }, { cycle: 7 }, { cycle: 8 } ]\n",
            windows);
    replace("report: { dir: ../results/engine-idle }\n", "");
    return tmp.write(name + ".yaml", text);
}

// orders.csv's rows of one window, without the split, window and cycle columns.
std::vector<std::vector<double>> order_rows(const std::filesystem::path& report, const std::string& window,
                                            const std::string& cycle) {
    std::vector<std::vector<double>> rows;
    for (const std::string& line : lines_of(read_text(report / "orders.csv"))) {
        std::vector<std::string> cells;
        std::istringstream in(line);
        for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
        if (cells.size() < 12 || cells[1] != window) continue;
        CHECK(cells[2] == cycle);
        std::vector<double> values;
        for (std::size_t c = 5; c < cells.size(); ++c) values.push_back(std::stod(cells[c]));
        rows.push_back(values);
    }
    return rows;
}

TEST_CASE("an engine recording cut in two: cycles count on each recording's own crank angle", "[e2e][recordings][fits]") {
    const TempDir tmp;
    write_cut_engine(tmp);
    const std::string short_fit = "estimation.lm.max_iterations=2";
    const auto engine_fit = [&](const std::filesystem::path& experiment, const std::string& out) {
        const RunResult r = run_tvid({"fit", experiment.string(), "-o", (tmp.path() / out).string(), "--threads", "2",
                                      "--quiet", "--set", short_fit});
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        return json::parse(read_text(tmp.path() / out / "summary.json"));
    };
    const json cut = engine_fit(
        engine_variant(tmp, "cut",
                       "  recordings:\n    - { name: a, file: engine_a.csv }\n    - { name: b, file: engine_b.csv }\n"
                       "  time: t\n",
                       "  estimation: [ { recording: a, cycle: 2 } ]\n  validation: [ { recording: b, cycle: 2 } ]\n"),
        "cut");
    const json whole = engine_fit(
        engine_variant(tmp, "whole", "  file: " + (source_dir() / "data/engine/idle.csv").string() + "\n  time: t\n",
                       "  estimation: [ { cycle: 2 } ]\n  validation: [ { cycle: 7 } ]\n"),
        "whole");
    // The first recording is the recording's first part, as it was: the same fit.
    check_same_parameters(cut, whole, 0.0);
    // The second one's crank angle moves by a cycle (it went on less than a cycle after the
    // first's): the cylinders repeat every cycle, so its cycle 2 is the recording's cycle 7.
    check_same_split(cut["validation"], whole["validation"], 1e-9);
    CHECK(cut["validation"]["windows"][0]["window"] == "b: cycle 2");
    // Its rows carry its own crank angle, and its order spectra its own cycle number.
    const std::vector<std::string> rows = lines_of(read_text(tmp.path() / "cut" / "validation.csv"));
    const std::vector<std::string> original = lines_of(read_text(tmp.path() / "whole" / "validation.csv"));
    REQUIRE(rows.size() == original.size());
    const auto last_cell = [](const std::string& line) { return std::stod(line.substr(line.rfind(',') + 1)); };
    CHECK(last_cell(rows[1]) == Approx(5040.0));  // 3600 + 2 cycles, the first scored sample after the warm-up
    CHECK(last_cell(rows.back()) == last_cell(original.back()));
    const auto cut_orders = order_rows(tmp.path() / "cut", "b: cycle 2", "2");
    const auto whole_orders = order_rows(tmp.path() / "whole", "cycle 7", "7");
    REQUIRE(cut_orders.size() == whole_orders.size());
    REQUIRE_FALSE(cut_orders.empty());
    for (std::size_t i = 0; i < cut_orders.size(); ++i)
        for (std::size_t c = 0; c < cut_orders[i].size(); ++c)
            CHECK(cut_orders[i][c] == Approx(whole_orders[i][c]).epsilon(1e-6).margin(1e-6));
}

TEST_CASE("the Aalto bench's three runs in one experiment give the three configs' figures", "[e2e][recordings][bench][fits]") {
    const TempDir tmp;
    const auto config = [](const std::string& name) { return source_dir() / "configs" / name; };
    const json runs = fit(config("aalto_bench_runs.yaml"), tmp.path() / "runs");
    const json one = fit(config("aalto_bench.yaml"), tmp.path() / "one");
    // Run 1 comes first, as read: the same fit, bit for bit.
    check_same_parameters(runs, one, 0.0);
    check_same_split(runs["estimation"], one["estimation"], 0.0);
    const std::filesystem::path params = tmp.path() / "one" / "params.json";
    const json run2 = validate(config("aalto_bench_run2.yaml"), params);
    const json run3 = validate(config("aalto_bench_run3.yaml"), params);
    const json& windows = runs["validation"]["windows"];
    REQUIRE(windows.size() == 3);
    const json* separate[] = {&one["validation"], &run2["validation"], &run3["validation"]};
    const char* labels[] = {"run1: samples 9000 to 13124", "run2: whole recording", "run3: whole recording"};
    const double documented[] = {72.4, 71.3, 51.3};  // torque_lower fit %, docs/real-bench.md
    for (std::size_t k = 0; k < 3; ++k) {
        INFO(labels[k]);
        CHECK(windows[k]["window"] == labels[k]);
        // Runs 2 and 3 start their clocks at 0 again: laid after run 1, their time stamps move
        // by 13.125 s and 25.875 s, and the rounding of the interpolation over some 12 000
        // samples of a stiff line moves the figures by up to 6e-10 (measured).
        const double tolerance = k == 0 ? 0.0 : 1e-8;
        for (const char* output : {"torque_upper", "torque_lower"}) {
            INFO(output);
            const json& m = windows[k]["outputs"][output];
            const json& s = (*separate[k])["pooled"][output];
            CHECK(relative_difference(m["rmse"].get<double>(), s["rmse"].get<double>()) <= tolerance);
            CHECK(relative_difference(m["fit_percent"].get<double>(), s["fit_percent"].get<double>()) <= tolerance);
        }
        CHECK(std::round(10 * windows[k]["outputs"]["torque_lower"]["fit_percent"].get<double>()) / 10 == documented[k]);
    }
    REQUIRE(runs["data_sha256"].size() == 3);
    CHECK(runs["data_sha256"][0] == one["data_sha256"]);
    CHECK(runs["data_sha256"][2] == tvid::sha256_of_file(source_dir() / "data/aalto_bench/ice_excitation3.csv"));
    CHECK(runs["recordings"][2]["name"] == "run3");
}

TEST_CASE("bad recording lists and windows are one error line, exit 2", "[e2e][recordings]") {
    const TempDir tmp;
    write_cut_recording(tmp);
    std::string text = read_text(kRecording);
    text.replace(0, text.find('\n'), "t,T_motor,w2,T_torque");  // no T_shaft column
    tmp.write("renamed.csv", text);
    const auto run = [&](const std::string& data, const std::string& windows) {
        return run_tvid({"fit", constant_load_variant(tmp, "bad", data, windows).string()});
    };
    const std::string experiment = (tmp.path() / "bad.yaml").string();
    const auto check_one_line = [&](const RunResult& r, const std::string& fragment) {
        INFO(r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.err.rfind(experiment + ":", 0) == 0);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK(r.err.find(fragment) != std::string::npos);
    };
    check_one_line(run("  recordings:\n    - { name: run1, file: run1.csv, time: t }\n"
                       "    - { name: run2, file: renamed.csv, time: t }\n",
                       kRecordingWindows),
                   "no column 'T_shaft' in " + (tmp.path() / "renamed.csv").string());
    check_one_line(run(kTwoRecordings, "  estimation: [ { recording: run1 } ]\n  validation: [ { time: [0, 1] } ]\n"),
                   "windows.validation[0].recording: missing");
    check_one_line(run(kTwoRecordings, "  estimation: [ { recording: run1 } ]\n  validation: [ { recording: run9 } ]\n"),
                   "no recording named 'run9'");
    check_one_line(run("  recordings: []\n", kRecordingWindows), "at least one recording");

    // A batch fits one recording per job: with several in the experiment it says so.
    const std::filesystem::path two = constant_load_variant(tmp, "two", kTwoRecordings, kRecordingWindows);
    const RunResult batch = run_tvid({"batch", two.string(), "--data", (tmp.path() / "run1.csv").string(), "-o",
                                      (tmp.path() / "batch").string(), "--quiet"});
    INFO(batch.err);
    CHECK(batch.exit_code == 2);
    CHECK(batch.err.find("--data: ") == 0);
    CHECK(batch.err.find("reads 2 recordings end to end (data.recordings: run1, run2)") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(tmp.path() / "batch" / "batch.csv"));
    // The same recordings from a list: the refusal names the option they came from; one
    // recording under data.recordings is not "several".
    const std::filesystem::path list = tmp.write("runs.txt", (tmp.path() / "run1.csv").string() + "\n");
    const RunResult listed = run_tvid({"batch", two.string(), "--data-list", list.string(), "-o",
                                       (tmp.path() / "batch").string(), "--quiet"});
    CHECK(listed.exit_code == 2);
    CHECK(listed.err.rfind("--data-list: ", 0) == 0);
    const std::filesystem::path one = constant_load_variant(
        tmp, "one", "  recordings:\n    - { name: run1, file: run1.csv, time: t }\n", "  estimation: [ { recording: run1 } ]\n");
    const RunResult single = run_tvid({"batch", one.string(), "--data", (tmp.path() / "run1.csv").string(), "-o",
                                       (tmp.path() / "batch").string(), "--quiet"});
    CHECK(single.exit_code == 2);
    CHECK(single.err.find("reads its recording through data.recordings (run1): ") != std::string::npos);
}

namespace {

// data/digital_drive/digital_drive_clean.csv with its time column rewritten by `clock`
// (sample index -> time), and configs/digital_drive_clean.yaml reading it.
std::filesystem::path digital_drive_on_clock(const TempDir& tmp, const std::string& name,
                                             const std::function<double(std::size_t)>& clock) {
    std::istringstream in(read_text(source_dir() / "data/digital_drive/digital_drive_clean.csv"));
    std::ostringstream out;
    out.precision(12);
    std::string line;
    std::getline(in, line);
    out << line << '\n';
    for (std::size_t i = 0; std::getline(in, line); ++i) out << clock(i) << line.substr(line.find(',')) << '\n';
    const std::filesystem::path csv = tmp.write(name + ".csv", out.str());
    std::string text = read_text(source_dir() / "configs/digital_drive_clean.yaml");
    replace_once(text, "../data/digital_drive/digital_drive_clean.csv", csv.string());
    return tmp.write(name + ".yaml", text);
}

}  // namespace

TEST_CASE("a sampled controller reads a logger's jittering clock as the clock it stands for, and refuses a drift",
          "[e2e][recordings][controller]") {
    const TempDir tmp;
    json truth = json::parse(read_text(source_dir() / "data/digital_drive/truth.json"))["parameters"];
    const std::filesystem::path params = tmp.write("truth.json", truth.dump());
    // Jitter of up to 5e-9 s on 1 ms samples (the median interval reads 0.00099999... s).
    const auto jitter = [](std::size_t i) { return static_cast<double>(i) * 1e-3 + 5e-9 * std::sin(1.7 * static_cast<double>(i)); };
    const json jittered = validate(digital_drive_on_clock(tmp, "jittered", jitter), params);
    const json exact = validate(source_dir() / "configs/digital_drive_clean.yaml", params);
    // At the true parameters on the noise-free recording both reproduce it; the jitter
    // moves the simulation by far less than the recording's noise (0.02 N m, 2e-4 rad).
    for (const char* output : {"T_drive", "theta"}) {
        INFO(output);
        CHECK(exact["estimation"]["pooled"][output]["rmse"].get<double>() < 1e-8);
        CHECK(jittered["estimation"]["pooled"][output]["rmse"].get<double>() < 1e-4 * (output == std::string("theta") ? 0.01 : 1.0));
    }
    // A clock running 1e-4 fast drifts a tenth of an interval from the controller's in a
    // second: refused at the first instant it misses, before any simulation.
    const std::filesystem::path drifting =
        digital_drive_on_clock(tmp, "drifting", [](std::size_t i) { return static_cast<double>(i) * 1e-3 * (1 + 1e-4); });
    const RunResult r = run_tvid({"validate", drifting.string(), "--params", params.string()});
    CHECK(r.exit_code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.find("model.elements[0].sample_period: the controller's instant t = ") != std::string::npos);
    CHECK(r.err.find("its clock drifts from k * 0.001 s") != std::string::npos);
}

TEST_CASE("a sampled controller samples on each recording's own clock when recordings are laid end to end",
          "[e2e][recordings][controller]") {
    const TempDir tmp;
    // The digital drive's controller at half the recording's rate (every 2 ms), read twice:
    // alone, and as the second of two recordings whose clocks both start at 0.
    std::string text = shipped_config_text("digital_drive_clean");
    const std::string csv = (source_dir() / "data/digital_drive/digital_drive_clean.csv").string();
    replace_once(text, "sample_period: 0.001, delay: 0.001", "sample_period: 0.002, delay: 0.002");
    const std::filesystem::path alone = tmp.write("alone.yaml", text);
    replace_once(text, "data:\n  file: " + csv + "\n  time: t\n",
                 "data:\n  recordings:\n    - { name: a, file: " + csv + ", time: t }\n    - { name: b, file: " + csv +
                     ", time: t }\n");
    replace_once(text, "  estimation: [ { time: [0, 2.5] } ]\n  validation: [ { time: [0, 4] } ]\n",
                 "  estimation: [ { recording: a, time: [0, 2.5] } ]\n  validation: [ { recording: b, time: [0, 4] } ]\n");
    const std::filesystem::path second = tmp.write("second.yaml", text);
    const std::filesystem::path params =
        tmp.write("truth.json", json::parse(read_text(source_dir() / "data/digital_drive/truth.json"))["parameters"].dump());
    const json a = validate(alone, params), b = validate(second, params);
    for (const char* output : {"T_drive", "theta"}) {
        INFO(output);
        const double expected = a["validation"]["pooled"][output]["rmse"].get<double>();
        CHECK(expected > 0.0);  // the controller at 2 ms is not the one that made the recording
        CHECK(relative_difference(b["validation"]["pooled"][output]["rmse"].get<double>(), expected) <= 1e-9);
    }
}

}  // namespace TVID_UNITY_ID
