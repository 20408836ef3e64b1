// What tvid writes, and only that: every report file, `-o FILE` and a written reference
// go into the place the user named, never over a FIFO or a device (replaced by a regular
// file they would be lost: /dev/null as root), never over a file the run reads (a
// recording named estimation.csv in the folder the report goes to), and never outside the
// report folder however a name is spelt. CSV cells that hold a comma are quoted, a batch
// resumes only the batch it began (its validation switch and its recordings' content), a
// JSON number beyond a double is one line naming the file, and a profile of the only free
// parameter works on any number of threads.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// t 0 … 1 s at 1 kHz; T = sin(2π·5t) + 0.3 sin(2π·40t); w solves 0.01·w' = T − 0.1·w
// (RK4, ten steps per sample), read 3 samples late, with noise 0.02; the rec.csv.
// `column` names the speed column.
std::string recording(const std::string& column = "w") {
    const double pi = 3.14159265358979323846;
    const auto torque = [&](double t) { return std::sin(2 * pi * 5 * t) + 0.3 * std::sin(2 * pi * 40 * t); };
    const auto slope = [&](double t, double w) { return (torque(t) - 0.1 * w) / 0.01; };
    std::vector<double> w(1001, 0.0);
    double y = 0.0;
    const double h = 1e-4;
    for (int i = 1; i <= 1000; ++i) {
        for (int k = 0; k < 10; ++k) {
            const double t = (i - 1) * 1e-3 + k * h;
            const double k1 = slope(t, y), k2 = slope(t + h / 2, y + h / 2 * k1), k3 = slope(t + h / 2, y + h / 2 * k2),
                         k4 = slope(t + h, y + h * k3);
            y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        }
        w[static_cast<std::size_t>(i)] = y;
    }
    std::mt19937 random(35);
    std::normal_distribution<double> noise(0.0, 0.02);
    std::ostringstream out;
    out.precision(10);
    out << "t,T," << column << "\n";
    for (int i = 0; i <= 1000; ++i) {
        const double late = i >= 3 ? w[static_cast<std::size_t>(i - 3)] : 0.0;
        out << i * 1e-3 << ',' << torque(i * 1e-3) << ',' << late + noise(random) << '\n';
    }
    return out.str();
}

// The one.yaml over `data`: one node, a torque from T, friction c; the output and
// the parameter may be renamed.
std::string one_node(const std::string& data, const std::string& output = "w", const std::string& parameter = "c") {
    return "tvid: 1\n"
           "name: one\n"
           "data: { file: '" + data + "', time: t }\n"
           "model:\n"
           "  nodes:\n"
           "    - { name: a, J: 0.01 }\n"
           "  elements:\n"
           "    - { type: torque, name: drive, node: a, input: T }\n"
           "    - { type: friction, name: loss, node: a, c: '" + parameter + "' }\n"
           "inputs: { T: T }\n"
           "outputs:\n"
           "  '" + output + "': { column: w, speed: a }\n"
           "parameters:\n"
           "  '" + parameter + "': { init: 0.1, min: 0.01, max: 1 }\n"
           "windows:\n"
           "  estimation: [ { time: [0, 0.9] } ]\n"
           "initial_state: rest\n"
           "estimation: { cost: l2, optimizer: lm }\n";
}

bool still_fifo(const fs::path& p) {
    struct stat st {};
    return ::lstat(p.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}

bool still_char_device(const fs::path& p) {
    struct stat st {};
    return ::lstat(p.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

long lines_of(const std::string& text) { return static_cast<long>(std::count(text.begin(), text.end(), '\n')); }

// The records of a CSV file read as RFC 4180 says (quoted cells may hold commas, quotes
// doubled, line breaks).
std::vector<std::vector<std::string>> rfc4180(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> row(1);
    bool quoted = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') row.back() += '"', ++i;
            else if (c == '"') quoted = false;
            else row.back() += c;
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            row.emplace_back();
        } else if (c == '\n') {
            rows.push_back(row);
            row.assign(1, "");
        } else if (c != '\r') {
            row.back() += c;
        }
    }
    return rows;
}

// Every record has as many cells as the header, and the header holds `cell`.
void check_csv(const fs::path& file, const std::string& cell) {
    INFO(file.string());
    REQUIRE(fs::exists(file));
    const auto rows = rfc4180(read_text(file));
    REQUIRE(rows.size() >= 2);
    const auto header = rows.front();
    CHECK(std::any_of(header.begin(), header.end(), [&](const std::string& c) { return c.find(cell) != std::string::npos; }));
    for (const auto& r : rows) CHECK(r.size() == header.size());
}

}  // namespace

TEST_CASE("simulate -o, validate -o and check --write-reference never replace a FIFO, a device or a folder", "[e2e][files]") {
    TempDir tmp;
    const fs::path rec = tmp.write("rec.csv", recording());
    const fs::path exp = tmp.write("one.yaml", one_node(rec.string()));
    const fs::path params = tmp.write("P.json", "{ \"c\": 0.1 }\n");
    const fs::path fifo = tmp.path() / "pipe";
    REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
    // A device of /dev/null's numbers in the scratch folder (root may make one; skipped otherwise).
    const fs::path device = tmp.path() / "null";
    const bool have_device = ::mknod(device.c_str(), S_IFCHR | 0666, ::makedev(1, 3)) == 0;
    std::vector<fs::path> targets{fifo, tmp.path()};
    if (have_device) targets.push_back(device);

    for (const fs::path& target : targets) {
        for (const char* command : {"simulate", "validate"}) {
            INFO(command << " -o " << target.string());
            const RunResult r =
                run_tvid({command, exp.string(), "--params", params.string(), "-o", target.string(), "--quiet"});
            CHECK(r.exit_code == 2);
            CHECK(lines_of(r.err) == 1);
            CHECK(r.err.rfind(target.string() + ": is ", 0) == 0);
            CHECK(r.err.find("tvid writes only regular files") != std::string::npos);
        }
    }
    CHECK(still_fifo(fifo));
    if (have_device) CHECK(still_char_device(device));
    CHECK(fs::is_directory(tmp.path()));

    // A reference written from a fit report.
    const fs::path report = tmp.path() / "report";
    REQUIRE(run_tvid({"fit", exp.string(), "-o", report.string(), "--quiet", "--threads", "1"}).exit_code == 0);
    for (const fs::path& target : targets) {
        INFO("--write-reference " << target.string());
        const RunResult r = run_tvid({"check", report.string(), "--write-reference", target.string(), "--quiet"});
        CHECK(r.exit_code == 2);
        CHECK(lines_of(r.err) == 1);
        CHECK(r.err.rfind(target.string() + ": is ", 0) == 0);
    }
    CHECK(still_fifo(fifo));
    if (have_device) CHECK(still_char_device(device));
    // No temporary file is left beside the targets.
    for (const fs::directory_entry& e : fs::directory_iterator(tmp.path()))
        CHECK(e.path().filename().string().find(".tvid-tmp.") == std::string::npos);

    // A FIFO under a report's name in the report folder: refused before the fit.
    const fs::path folder = tmp.path() / "with-fifo";
    fs::create_directories(folder);
    REQUIRE(::mkfifo((folder / "history.csv").c_str(), 0644) == 0);
    const RunResult fit = run_tvid({"fit", exp.string(), "-o", folder.string(), "--quiet", "--threads", "1"});
    CHECK(fit.exit_code == 2);
    CHECK(fit.err == (folder / "history.csv").string() +
                         ": is a named pipe (FIFO): tvid writes only regular files, and replaces nothing else; give a "
                         "file name\n");
    CHECK(still_fifo(folder / "history.csv"));
    CHECK_FALSE(fs::exists(folder / "params.json"));
}

TEST_CASE("a report never replaces a file the run reads", "[e2e][files]") {
    for (const char* name : {"estimation.csv", "history.csv", "validation.csv"}) {
        INFO(name);
        TempDir tmp;
        const std::string data = recording();
        const fs::path rec = tmp.write(name, data);
        const fs::path exp = tmp.write("exp.yaml", one_node(name));
        // `tvid fit exp.yaml -o .` in the recording's folder: refused before the fit.
        const RunResult r = run_tvid({"fit", "exp.yaml", "-o", ".", "--threads", "1"}, tmp.path().string());
        CHECK(r.exit_code == 2);
        CHECK(lines_of(r.err) == 1);
        CHECK(r.err.find(std::string(name) + ": is the data file ") != std::string::npos);
        CHECK(r.err.find("tvid never replaces a file it reads") != std::string::npos);
        CHECK(read_text(rec) == data);
        CHECK_FALSE(fs::exists(tmp.path() / "params.json"));
        CHECK_FALSE(fs::exists(tmp.path() / "summary.json"));
    }

    TempDir tmp;
    const std::string data = recording();
    const fs::path rec = tmp.write("rec.csv", data);
    const std::string experiment = one_node("rec.csv");
    const fs::path exp = tmp.write("one.yaml", experiment);
    const std::string params_text = "{ \"c\": 0.1 }\n";
    const fs::path params = tmp.write("P.json", params_text);
    // A hard link is the same file under another name.
    const fs::path link = tmp.path() / "link.csv";
    fs::create_hard_link(rec, link);
    for (const fs::path& target : {rec, exp, params, link}) {
        for (const char* command : {"simulate", "validate"}) {
            INFO(command << " -o " << target.string());
            const RunResult r =
                run_tvid({command, exp.string(), "--params", params.string(), "-o", target.string(), "--quiet"});
            CHECK(r.exit_code == 2);
            CHECK(lines_of(r.err) == 1);
            CHECK(r.err.rfind(target.string() + ": is the ", 0) == 0);
        }
    }
    CHECK(read_text(rec) == data);
    CHECK(read_text(exp) == experiment);
    CHECK(read_text(params) == params_text);

    // A reference written over the report file it is made from.
    const fs::path report = tmp.path() / "report";
    REQUIRE(run_tvid({"fit", exp.string(), "-o", report.string(), "--quiet", "--threads", "1"}).exit_code == 0);
    const std::string summary = read_text(report / "summary.json");
    const RunResult r = run_tvid({"check", report.string(), "--write-reference", (report / "summary.json").string()});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find(": is the report file ") != std::string::npos);
    CHECK(read_text(report / "summary.json") == summary);
}

TEST_CASE("a name with a comma is one CSV cell, a name with a path separator is refused", "[e2e][files]") {
    TempDir tmp;
    const fs::path rec = tmp.write("rec.csv", recording());
    const fs::path exp = tmp.write("comma.yaml", one_node(rec.string(), "w, rad", "c,1"));
    const fs::path report = tmp.path() / "report";
    const RunResult fit = run_tvid({"fit", exp.string(), "-o", report.string(), "--quiet", "--threads", "1"});
    INFO(fit.err);
    REQUIRE(fit.exit_code == 0);
    check_csv(report / "params.csv", "ci95_low");
    check_csv(report / "estimation.csv", "w, rad_measured");
    check_csv(report / "spectra.csv", "w, rad_measured_psd");
    CHECK(rfc4180(read_text(report / "params.csv"))[1][0] == "c,1");
    const fs::path sensitivity = tmp.path() / "sensitivity";
    REQUIRE(run_tvid({"sensitivity", exp.string(), "-o", sensitivity.string(), "--quiet"}).exit_code == 0);
    check_csv(sensitivity / "sensitivity.csv", "d_c,1");
    check_csv(sensitivity / "ranking.csv", "parameter");
    CHECK(rfc4180(read_text(sensitivity / "ranking.csv"))[1][2] == "c,1");
    const fs::path profile = tmp.path() / "profile";
    REQUIRE(run_tvid({"profile", exp.string(), "--param", "c,1", "--points", "3", "-o", profile.string(), "--quiet"})
                .exit_code == 0);
    check_csv(profile / "profile.csv", "c,1");
    const fs::path batch = tmp.path() / "batch";
    REQUIRE(run_tvid({"batch", exp.string(), "--data", rec.string(), "-o", batch.string(), "--quiet"}).exit_code == 0);
    check_csv(batch / "batch.csv", "c,1");

    // Path separators, "." and "..": refused where the name is given, one line.
    for (const auto& [output, parameter, key] : std::vector<std::tuple<std::string, std::string, std::string>>{
             {"w/motor", "c", "outputs.w/motor"},
             {"w", "../../../escape", "parameters.../../../escape"},
             {"w", "..", "parameters..."},
             {"w\\x", "c", "outputs.w\\x"}}) {
        INFO(output << " " << parameter);
        const fs::path bad = tmp.write("bad.yaml", one_node(rec.string(), output, parameter));
        const RunResult r = run_tvid({"fit", bad.string(), "-o", (tmp.path() / "never").string()});
        CHECK(r.exit_code == 2);
        CHECK(lines_of(r.err) == 1);
        CHECK(r.err.rfind(bad.string() + ":", 0) == 0);
        CHECK(r.err.find(": " + key + ": '") != std::string::npos);
        CHECK(r.err.find("is not a plain name") != std::string::npos);
        CHECK_FALSE(fs::exists(tmp.path() / "never"));
    }

    // --param names no parameter: refused before a folder is named after it.
    TempDir work;
    const fs::path plain = work.write("sub/deeper/one.yaml", one_node(rec.string()));
    const RunResult escape = run_tvid({"profile", plain.string(), "--param", "../../../escape"}, (work.path() / "sub").string());
    CHECK(escape.exit_code == 2);
    CHECK(escape.err == "--param: ../../../escape: is not a parameter of the model\n");
    CHECK_FALSE(fs::exists(work.path() / "escape"));
    CHECK_FALSE(fs::exists(work.path() / "sub" / "results"));
}

TEST_CASE("a profile of the only free parameter: the points are simulations, on any number of threads",
          "[e2e][files][profile]") {
    TempDir tmp;
    const fs::path rec = tmp.write("rec.csv", recording());
    const fs::path exp = tmp.write("one.yaml", one_node(rec.string()));
    std::string first;
    for (const char* threads : {"1", "2"}) {
        INFO("--threads " << threads);
        const fs::path out = tmp.path() / (std::string("p") + threads);
        const RunResult r = run_tvid({"profile", exp.string(), "--param", "c", "-o", out.string(), "--threads", threads});
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        const auto rows = rfc4180(read_text(out / "profile.csv"));
        REQUIRE(rows.size() == 22);  // the header and 21 points
        CHECK(rows[0] == std::vector<std::string>{"c", "cost", "delta_chi2", "converged", "termination"});
        for (std::size_t k = 1; k < rows.size(); ++k) {
            CHECK(std::isfinite(std::stod(rows[k][1])));
            CHECK(std::stod(rows[k][2]) >= -1e-6);  // no point below the optimum
            CHECK(rows[k][3] == "true");
        }
        const json p = json::parse(read_text(out / "profile.json"));
        CHECK(p["better_point_found"] == false);
        CHECK(p["interval95"]["low"].is_number());
        CHECK(p["interval95"]["high"].is_number());
        const double low = p["interval95"]["low"], high = p["interval95"]["high"], best = p["optimum"]["value"];
        CHECK(low < best);
        CHECK(best < high);
        if (first.empty()) first = read_text(out / "profile.csv");
        else CHECK(read_text(out / "profile.csv") == first);  // the same for any thread count
    }
}

TEST_CASE("batch --resume continues only the same batch: its validation switch and its recordings' content",
          "[e2e][files][batch]") {
    TempDir tmp;
    const std::string data = recording();
    const fs::path rec1 = tmp.write("recs/r1.csv", data), rec2 = tmp.write("recs/r2.csv", data);
    const fs::path exp = tmp.write("one.yaml", one_node(rec1.string()));
    const fs::path out = tmp.path() / "batch";
    const auto batch = [&](const std::vector<std::string>& extra) {
        std::vector<std::string> args{"batch", exp.string(), "--data", (tmp.path() / "recs/*.csv").string(), "-o",
                                      out.string(), "--quiet", "--threads", "1"};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tvid(args);
    };
    REQUIRE(batch({}).exit_code == 0);
    const std::string table = read_text(out / "batch.csv");

    const RunResult no_validation = batch({"--resume", "--no-validation"});
    CHECK(no_validation.exit_code == 2);
    CHECK(no_validation.err == (out / "batch.csv").string() +
                                   ": is another batch's: it ran with validation (without --no-validation): use "
                                   "another -o, or --force to start over\n");
    CHECK(read_text(out / "batch.csv") == table);

    // The same batch resumes (nothing left to run).
    const RunResult same = batch({"--resume"});
    INFO(same.err);
    CHECK(same.exit_code == 0);

    // A recording edited since: its row would be stale.
    const std::string edited = data.substr(0, data.rfind(',') + 1) + "0.5\n";
    tmp.write("recs/r2.csv", edited);
    const RunResult changed = batch({"--resume"});
    CHECK(changed.exit_code == 2);
    CHECK(changed.err == (out / "batch.csv").string() + ": is another batch's: the recording " + rec2.string() +
                             " changed since the batch began: use another -o, or --force to start over\n");
    CHECK(read_text(out / "batch.csv") == table);

    // The other way round: a batch without validation, resumed with it.
    REQUIRE(batch({"--force", "--no-validation"}).exit_code == 0);
    const RunResult with_validation = batch({"--resume"});
    CHECK(with_validation.exit_code == 2);
    CHECK(with_validation.err.find("it ran with --no-validation") != std::string::npos);
}

TEST_CASE("a JSON number beyond a double is one line naming the file, the line and the key", "[e2e][files]") {
    TempDir tmp;
    const fs::path rec = tmp.write("rec.csv", recording());
    const fs::path exp = tmp.write("one.yaml", one_node(rec.string()));
    const fs::path report = tmp.path() / "report";
    REQUIRE(run_tvid({"fit", exp.string(), "-o", report.string(), "--quiet", "--threads", "1"}).exit_code == 0);
    const fs::path ref = tmp.write("ref.json", "{\n  \"tvid_reference\": 1,\n  \"experiment\": \"one\",\n"
                                               "  \"parameters\": { \"c\": 1e400 }\n}\n");
    const RunResult r = run_tvid({"check", report.string(), "--reference", ref.string()});
    CHECK(r.exit_code == 2);
    CHECK(r.err == ref.string() + ":4: c: '1e400' is too large for a number (at most about 1.8e308)\n");
    // The same in a parameter file.
    const fs::path params = tmp.write("P.json", "{ \"c\": -1e999 }");
    const RunResult p = run_tvid({"simulate", exp.string(), "--params", params.string()});
    CHECK(p.exit_code == 2);
    CHECK(p.err == params.string() + ":1: c: '-1e999' is too large for a number (at most about 1.8e308)\n");
}

TEST_CASE("a batch never replaces or removes files of a batch that tvid did not write, without --force",
          "[e2e][files][batch]") {
    TempDir tmp;
    const fs::path rec = tmp.write("rec.csv", recording());
    const fs::path exp = tmp.write("exp.yaml", one_node(rec.string()));
    const fs::path out = tmp.path() / "out";
    // The user's own files under the names a batch writes, and no batch.csv.
    const std::vector<std::string> names{"matrix.csv", "matrix_long.csv", "parameter_stability.csv", "batch_summary.json"};
    for (const std::string& name : names) tmp.write("out/" + name, "the user's " + name + "\n");
    const auto batch = [&](const std::vector<std::string>& extra) {
        std::vector<std::string> args{"batch", exp.string(), "--data", rec.string(), "-o", out.string(), "--quiet",
                                      "--threads", "1"};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tvid(args);
    };
    const RunResult refused = batch({});
    CHECK(refused.exit_code == 2);
    CHECK(refused.err == (out / "batch_summary.json").string() +
                             ": exists, and no record of a batch of tvid's (.tvid-batch.json) is beside it: tvid did "
                             "not write it; use --force to replace it, or -o for another directory\n");
    for (const std::string& name : names) {
        INFO(name);
        CHECK(read_text(out / name) == "the user's " + name + "\n");
    }
    CHECK_FALSE(fs::exists(out / "batch.csv"));

    // One of them alone is enough to refuse.
    for (const std::string& name : names) fs::remove(out / name);
    tmp.write("out/parameter_stability.csv", "mine\n");
    const RunResult one = batch({});
    CHECK(one.exit_code == 2);
    CHECK(one.err.rfind((out / "parameter_stability.csv").string() + ": exists, and no record", 0) == 0);
    CHECK(read_text(out / "parameter_stability.csv") == "mine\n");

    // --force replaces them; then the batch's own files are its to replace with --force again.
    REQUIRE(batch({"--force"}).exit_code == 0);
    CHECK(fs::exists(out / "batch.csv"));
    CHECK(fs::exists(out / ".tvid-batch.json"));
    const RunResult again = batch({"--force"});
    INFO(again.err);
    CHECK(again.exit_code == 0);
}

TEST_CASE("simulate -o and check --write-reference know their own files by structure, not by a text in them",
          "[e2e][files]") {
    TempDir tmp;
    const fs::path rec = tmp.write("rec.csv", recording());
    const fs::path exp = tmp.write("one.yaml", one_node(rec.string()));
    const fs::path params = tmp.write("P.json", "{ \"c\": 0.1 }\n");

    // Notes that quote a simulation CSV's heading and a reference's description.
    const std::string notes = "# How to simulate\n\nThe CSV begins `t [s],window,` and then the outputs.\n";
    const fs::path notes_md = tmp.write("notes.md", notes);
    const std::string howto = "This reference was \"written by tvid check --write-reference\" from the nightly fit.\n";
    const fs::path howto_txt = tmp.write("HOWTO.txt", howto);
    const std::string json_notes = "{ \"note\": \"\\\"written_by\\\": \\\"tvid validate\\\"\" }\n";
    const fs::path json_notes_file = tmp.write("notes.json", json_notes);

    const RunResult simulate = run_tvid({"simulate", exp.string(), "--params", params.string(), "-o", notes_md.string(), "--quiet"});
    CHECK(simulate.exit_code == 2);
    CHECK(simulate.err == notes_md.string() +
                              ": exists and is not a simulation CSV that tvid wrote: give --force to replace it, or "
                              "another name\n");
    CHECK(read_text(notes_md) == notes);
    const RunResult validate =
        run_tvid({"validate", exp.string(), "--params", params.string(), "-o", json_notes_file.string(), "--quiet"});
    CHECK(validate.exit_code == 2);
    CHECK(read_text(json_notes_file) == json_notes);

    const fs::path report = tmp.path() / "report";
    REQUIRE(run_tvid({"fit", exp.string(), "-o", report.string(), "--quiet", "--threads", "1"}).exit_code == 0);
    const RunResult reference = run_tvid({"check", report.string(), "--write-reference", howto_txt.string(), "--quiet"});
    CHECK(reference.exit_code == 2);
    CHECK(reference.err == howto_txt.string() +
                               ": exists and is not a reference that tvid wrote: give --force to replace it, or another "
                               "name\n");
    CHECK(read_text(howto_txt) == howto);
    const fs::path missing = tmp.path() / "missing" / "ref.json";
    const RunResult no_folder = run_tvid({"check", report.string(), "--write-reference", missing.string()});
    CHECK(no_folder.exit_code == 2);
    CHECK(no_folder.err == missing.string() + ": its folder " + (tmp.path() / "missing").string() +
                               " does not exist: create it first, or give another name\n");
    CHECK(no_folder.out.empty());

    // tvid's own files are replaced without --force.
    const fs::path sim = tmp.path() / "sim.csv", val = tmp.path() / "val.json", ref = tmp.path() / "ref.json";
    for (int round = 0; round < 2; ++round) {
        INFO("round " << round);
        CHECK(run_tvid({"simulate", exp.string(), "--params", params.string(), "-o", sim.string(), "--quiet"}).exit_code == 0);
        CHECK(run_tvid({"validate", exp.string(), "--params", params.string(), "-o", val.string(), "--quiet"}).exit_code == 0);
        const RunResult written = run_tvid({"check", report.string(), "--write-reference", ref.string(), "--quiet"});
        INFO(written.err);
        CHECK(written.exit_code == 0);
    }
    CHECK(read_text(sim).rfind("t [s],window,", 0) == 0);
}

}  // namespace TVID_UNITY_ID
