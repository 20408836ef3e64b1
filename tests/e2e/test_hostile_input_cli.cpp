// Hostile inputs and faults beyond the catalogue of docs/errors.md: counts that overflow,
// thread counts no machine has, bytes that are not UTF-8, two runs into one directory,
// a resumed batch of another experiment, files that are not files, and stop requests
// during slow simulations. Each gets one clear line and exit status 2 (or a whole report),
// never a crash, a hang, a mixed report or a silently wrong result.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"
#include "tvid/io/sha256.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// How many times longer a run takes here than in an optimized build (8 under the sanitizers, whose library is compiled at -O1).
const double kTimeScale = test_time_scale();

const std::string kCleanConfig = (source_dir() / "configs/cvt_tipin_clean.yaml").string();
const std::string kCleanData = (source_dir() / "data/cvt/tipin_clean.csv").string();

// A quick fit: the CVT clearance model, three LM steps, one thread.
std::vector<std::string> quick_fit(const fs::path& out) {
    return {"fit", kCleanConfig, "-o", out.string(), "--optimizer", "lm", "--set", "estimation.cost=l2",
            "--set", "estimation.lm.max_iterations=3", "--threads", "1", "--quiet"};
}

// A fit that runs for minutes unless stopped: the swarm, many iterations, one thread.
std::vector<std::string> long_fit(const fs::path& out) {
    return {"fit", kCleanConfig, "-o", out.string(), "--set", "estimation.pso.iterations=100000", "--set",
            "estimation.pso.start=latin_hypercube", "--set", "estimation.pso.particles=64", "--threads", "1",
            "--quiet"};
}

// A small batch over the given recordings glob: 16 particles, two iterations per job.
std::vector<std::string> quick_batch(const std::string& config, const std::string& data, const fs::path& out) {
    return {"batch", config, "--data", data, "-o", out.string(), "--set", "estimation.pso.start=latin_hypercube",
            "--set", "estimation.pso.particles=16", "--set", "estimation.pso.iterations=2", "--threads", "1",
            "--quiet"};
}

// The true parameters of the CVT recordings as a parameter file ({name: value}).
std::string truth_params(const TempDir& tmp) {
    const json truth = json::parse(read_text(source_dir() / "data/cvt/truth.json"));
    return tmp.write("truth-params.json", truth["parameters"].dump()).string();
}

std::size_t line_count(const std::string& text) { return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Expects exit status 2 with one line on stderr that holds every part.
void expect_refusal(const RunResult& r, std::initializer_list<std::string> parts) {
    INFO(r.err);
    CHECK(r.exit_code == 2);
    CHECK(line_count(r.err) == 1);
    for (const std::string& p : parts) CHECK(contains(r.err, p));
}

// The recording with one more sample `gap` seconds after its last one.
std::string recording_with_gap(double gap) {
    std::istringstream in(read_text(kCleanData));
    std::string text, line, last;
    while (std::getline(in, line)) {
        text += line + "\n";
        if (!line.empty() && line[0] != '#') last = line;
    }
    const auto comma = last.find(',');
    const double t = std::stod(last.substr(0, comma));
    std::ostringstream extra;
    extra.precision(17);
    extra << t + gap << last.substr(comma) << "\n";
    return text + extra.str();
}

}  // namespace

TEST_CASE("a step count past any integer is refused, not wrapped into a constant simulation", "[e2e][hostile]") {
    TempDir tmp;
    // The step asks for 1.5e13 steps per simulation.
    RunResult r = run_tvid({"fit", kCleanConfig, "--set", "simulation.step=1e-13", "-o", (tmp.path() / "a").string()});
    expect_refusal(r, {"simulation.step", "steps per simulation", "use a larger step"});
    CHECK_FALSE(fs::exists(tmp.path() / "a" / "summary.json"));
    // A gap of 1e7 s in the time column with a step of 1 ms: 1e10 steps in one interval.
    const fs::path data = tmp.write("gap.csv", recording_with_gap(1e7));
    r = run_tvid({"fit", kCleanConfig, "--set", "data.file=" + data.string(), "--set", "simulation.step=1e-3", "-o",
                  (tmp.path() / "b").string()});
    expect_refusal(r, {"simulation.step", "longest sample interval", "gap.csv"});
    // A step that keeps the count in bounds is accepted.
    r = run_tvid({"validate", kCleanConfig, "--set", "simulation.step=1e-4", "--params", truth_params(tmp)});
    CHECK(r.exit_code == 0);
}

TEST_CASE("a thread count beyond the cap is one line and exit 2, not a crash", "[e2e][hostile]") {
    TempDir tmp;
    for (const char* threads : {"100000", "50000", "1025"}) {
        std::vector<std::string> args = quick_fit(tmp.path() / "out");
        args[std::find(args.begin(), args.end(), "--threads") - args.begin() + 1] = threads;
        const RunResult r = run_tvid(args);
        INFO(threads << ": " << r.err);
        CHECK(r.exit_code == 2);
        CHECK(contains(r.err, "--threads"));
    }
}

TEST_CASE("bytes that are not UTF-8 in names and paths still give a whole report", "[e2e][hostile]") {
    TempDir tmp;
    const fs::path out = tmp.path() / "r\xff\xfe";
    std::vector<std::string> args = quick_fit(out);
    args.insert(args.end(), {"--set", "name=caf\xe9"});
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json summary = json::parse(read_text(out / "summary.json"));
    CHECK(summary["status"] == "ok");
    CHECK(contains(summary["experiment"].get<std::string>(), "caf\xef\xbf\xbd"));  // U+FFFD for the bad byte

    const fs::path batch_out = tmp.path() / "b\xff";
    const RunResult b = run_tvid(quick_batch(kCleanConfig, kCleanData, batch_out));
    INFO(b.err);
    CHECK(b.exit_code == 0);
    CHECK(fs::is_regular_file(batch_out / "batch_summary.json"));
    // --resume of the finished batch reads its own record back.
    std::vector<std::string> resume = quick_batch(kCleanConfig, kCleanData, batch_out);
    resume.push_back("--resume");
    CHECK(run_tvid(resume).exit_code == 0);
}

TEST_CASE("a second run into a directory in use is refused while the first runs", "[e2e][hostile]") {
    TempDir tmp;
    const fs::path out = tmp.path() / "shared";
    TvidProcess first(long_fit(out));
    // The first run holds the directory once its lock file is there.
    for (int i = 0; i < 200 && !fs::exists(out / ".tvid.lock"); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    REQUIRE_FALSE(first.wait(0));
    std::vector<std::string> second = quick_fit(out);
    second.push_back("--force");
    expect_refusal(run_tvid(second), {out.string(), "in use by another tvid run"});
    std::vector<std::string> batch = quick_batch(kCleanConfig, kCleanData, out);
    expect_refusal(run_tvid(batch), {"in use by another tvid run"});
    first.send(SIGKILL);
    REQUIRE(first.wait(30));
    // The lock dies with its process: the directory is free again.
    CHECK(run_tvid(second).exit_code == 0);
}

TEST_CASE("batch --resume continues only the same experiment, settings and seed", "[e2e][hostile][batch]") {
    TempDir tmp;
    const fs::path config = tmp.write("exp.yaml", read_text(kCleanConfig));
    const fs::path out = tmp.path() / "batch";
    const std::vector<std::string> base = quick_batch(config.string(), kCleanData, out);
    REQUIRE(run_tvid(base).exit_code == 0);
    auto with = [&](std::initializer_list<std::string> extra) {
        std::vector<std::string> a = base;
        a.insert(a.end(), extra);
        a.push_back("--resume");
        return a;
    };
    const std::string table = read_text(out / "batch.csv");
    expect_refusal(run_tvid(with({"--set", "estimation.cost=l1"})), {"another batch's", "--set"});
    expect_refusal(run_tvid(with({"--set", "estimation.pso.iterations=3"})), {"another batch's", "--set"});
    expect_refusal(run_tvid(with({"--seed", "7"})), {"another batch's", "seed"});
    std::ofstream(config, std::ios::app) << "# edited\n";
    expect_refusal(run_tvid(with({})), {"another batch's", "experiment file changed"});
    CHECK(read_text(out / "batch.csv") == table);  // nothing mixed in
    // With the file as it was, the same batch resumes.
    tmp.write("exp.yaml", read_text(kCleanConfig));
    CHECK(run_tvid(with({})).exit_code == 0);
    // --resume and --force contradict each other.
    std::vector<std::string> both = with({});
    both.push_back("--force");
    CHECK(run_tvid(both).exit_code == 2);
}

TEST_CASE("a parameter named like a batch column is refused before any job", "[e2e][hostile][batch]") {
    TempDir tmp;
    // The CVT preset's torque offset d_tm is a free parameter; named `cost` in a custom network.
    const std::string config = "tvid: 1\n"
                               "name: named-cost\n"
                               "data: { file: '" + kCleanData + "', time: t }\n"
                               "model:\n"
                               "  nodes:\n"
                               "    - { name: shaft, inverse_J: rho1 }\n"
                               "  elements:\n"
                               "    - { type: torque, name: drive, node: shaft, input: Ttm, offset: cost }\n"
                               "    - { type: spring_damper, name: spring, between: [shaft, ground], k: k, c: c }\n"
                               "inputs: { Ttm: Ttm }\n"
                               "outputs:\n"
                               "  Tds: { column: Tds, torque: spring }\n"
                               "parameters:\n"
                               "  rho1: { value: 40 }\n"
                               "  cost: { init: 0, min: -10, max: 10 }\n"
                               "  k: { init: 100, min: 1, max: 1000 }\n"
                               "  c: { value: 1 }\n"
                               "windows: { estimation: [{ time: [1.5, 2.0] }] }\n";
    const fs::path file = tmp.write("named.yaml", config);
    const RunResult r = run_tvid(quick_batch(file.string(), kCleanData, tmp.path() / "b"));
    expect_refusal(r, {"parameters.cost", "batch.csv"});
    CHECK_FALSE(fs::exists(tmp.path() / "b" / "batch.csv"));
}

TEST_CASE("files that are not regular files are refused at once, never read or waited on", "[e2e][hostile]") {
    TempDir tmp;
    const auto started = std::chrono::steady_clock::now();
    expect_refusal(run_tvid({"fit", "/dev/zero", "-o", (tmp.path() / "a").string()}), {"/dev/zero", "a device"});
    expect_refusal(run_tvid({"batch", kCleanConfig, "--data-list", "/dev/zero", "-o", (tmp.path() / "b").string()}),
                   {"/dev/zero", "a device"});
    const fs::path fifo = tmp.path() / "pipe.yaml";
    REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
    expect_refusal(run_tvid({"fit", fifo.string(), "-o", (tmp.path() / "c").string()}), {"pipe.yaml", "named pipe"});
    REQUIRE(run_tvid(quick_fit(tmp.path() / "report")).exit_code == 0);
    expect_refusal(run_tvid({"check", (tmp.path() / "report").string(), "--reference", fifo.string()}),
                   {"pipe.yaml", "named pipe"});
    // data.file: a directory, a device and a FIFO are named as such, not "no such data file".
    for (const std::string& bad : {tmp.path().string(), std::string("/dev/zero"), fifo.string()}) {
        const RunResult r = run_tvid({"validate", kCleanConfig, "--set", "data.file=" + bad, "--params", truth_params(tmp)});
        expect_refusal(r, {"data.file", "not a file"});
        CHECK_FALSE(contains(r.err, "no such data file"));
    }
    const fs::path loop = tmp.path() / "loop.csv";
    fs::create_symlink(loop, loop);
    expect_refusal(run_tvid({"validate", kCleanConfig, "--set", "data.file=" + loop.string(), "--params", truth_params(tmp)}),
                   {"symbolic link loop"});
    // None of these waited: a blocked read would have hung here.
    CHECK(std::chrono::steady_clock::now() - started < std::chrono::seconds(60));
}

TEST_CASE("oversized and deeply nested inputs are refused with their size or depth", "[e2e][hostile]") {
    TempDir tmp;
    // An experiment of 8 MB: a list under an unknown key.
    std::string big = read_text(kCleanConfig) + "junk: [";
    while (big.size() < (std::size_t{8} << 20)) big += "1234567, ";
    big += "0]\n";
    expect_refusal(run_tvid({"fit", tmp.write("big.yaml", big).string(), "-o", (tmp.path() / "a").string()}),
                   {"big.yaml", "more than the", "MB"});
    // A fit report to check against.
    const fs::path report = tmp.path() / "report";
    REQUIRE(run_tvid(quick_fit(report)).exit_code == 0);
    // A reference nested 100 000 deep, and a combination expression as deep.
    std::string nested = "{\"tvid_reference\": 1, \"x\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
    expect_refusal(run_tvid({"check", report.string(), "--reference", tmp.write("deep.json", nested).string()}),
                   {"deep.json", "nested more than"});
    const std::string expression = std::string(100000, '(') + "rho1" + std::string(100000, ')');
    const json reference = {{"tvid_reference", 1}, {"combinations", {{expression, 1.0}}}};
    const RunResult deep = run_tvid({"check", report.string(), "--reference", tmp.write("expr.json", reference.dump()).string()});
    INFO(deep.err);
    CHECK(deep.exit_code == 2);
    CHECK(contains(deep.err, "nested more than"));
    // A key twice in one object: the last value silently winning would hide the first.
    const std::string duplicate = R"({"tvid_reference": 1, "cost": {"max": 1}, "cost": {"max": 2}})";
    expect_refusal(run_tvid({"check", report.string(), "--reference", tmp.write("dup.json", duplicate).string()}),
                   {"dup.json", "\"cost\" appears twice"});
}

TEST_CASE("the report records the data and experiment as they were read at the start", "[e2e][hostile]") {
    TempDir tmp;
    const fs::path data = tmp.write("rec.csv", read_text(kCleanData));
    const fs::path config = tmp.write("exp.yaml", read_text(kCleanConfig));
    const std::string data_sha = tvid::sha256_of_file(data), config_sha = tvid::sha256_of_file(config);
    const fs::path out = tmp.path() / "out";
    std::vector<std::string> args = long_fit(out);
    args[1] = config.string();
    args.insert(args.end(), {"--set", "data.file=" + data.string()});
    TvidProcess fit(args);
    std::this_thread::sleep_for(std::chrono::duration<double>(2 * kTimeScale));
    REQUIRE_FALSE(fit.wait(0));
    fs::remove(data);
    std::ofstream(config, std::ios::app) << "# changed during the fit\n";
    fit.send(SIGINT);
    REQUIRE(fit.wait(60));
    CHECK(fit.result().exit_code == 130);
    const json summary = json::parse(read_text(out / "summary.json"));
    CHECK(summary["data_sha256"] == data_sha);
    CHECK(summary["config_sha256"] == config_sha);
}

TEST_CASE("a stop request reaches into a slow simulation", "[e2e][hostile][interrupt]") {
    TempDir tmp;
    // A step of 10 ns: one simulation of the 1.5 s recording takes 1.5e8 steps.
    const fs::path out = tmp.path() / "slow";
    std::vector<std::string> args = quick_fit(out);
    args.insert(args.end(), {"--set", "simulation.step=1e-8"});
    TvidProcess fit(args);
    std::this_thread::sleep_for(std::chrono::duration<double>(2 * kTimeScale));
    REQUIRE_FALSE(fit.wait(0));
    const auto sent = std::chrono::steady_clock::now();
    fit.send(SIGTERM);
    REQUIRE(fit.wait(120));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    INFO(fit.result().err);
    CHECK(fit.result().exit_code == 130);
    CHECK(seconds < 10 * kTimeScale);  // the grace period for the report is 2 s; before, one simulation took a minute
    const json summary = json::parse(read_text(out / "summary.json"));
    CHECK(summary["interrupted"] == true);

    // A batch stopped with SIGTERM says so, keeps its finished rows and exits as fit does.
    const fs::path bout = tmp.path() / "batch";
    std::vector<std::string> batch = quick_batch(kCleanConfig, kCleanData, bout);
    batch.erase(std::find(batch.begin(), batch.end(), "--quiet"));
    batch.insert(batch.end(), {"--set", "simulation.step=1e-8"});
    TvidProcess b(batch);
    std::this_thread::sleep_for(std::chrono::duration<double>(2 * kTimeScale));
    REQUIRE_FALSE(b.wait(0));
    b.send(SIGTERM);
    REQUIRE(b.wait(120));
    INFO(b.result().err);
    CHECK(b.result().exit_code == 130);
    CHECK(contains(b.result().err, "--resume"));
    CHECK(fs::is_regular_file(bout / "batch.csv"));
    CHECK_FALSE(fs::exists(bout / "batch_summary.json"));
}

TEST_CASE("a reference that would not read back is never written", "[e2e][hostile][check]") {
    TempDir tmp;
    const fs::path report = tmp.path() / "report";
    REQUIRE(run_tvid(quick_fit(report)).exit_code == 0);
    const fs::path ref = tmp.path() / "ref.json";
    for (const char* rel : {"nan", "inf", "-0.1"}) {
        const RunResult r = run_tvid({"check", report.string(), "--write-reference", ref.string(), "--rel", rel});
        INFO(rel << ": " << r.err);
        CHECK(r.exit_code == 2);
        CHECK(contains(r.err, "--rel"));
        CHECK_FALSE(fs::exists(ref));
    }
}

TEST_CASE("weak messages and silent acceptances are named for what they are", "[e2e][hostile]") {
    TempDir tmp;
    const std::string truth = truth_params(tmp);
    // A finite 1e200 in a measured output: the cost would overflow.
    std::string data = read_text(kCleanData);
    {
        std::istringstream in(data);
        std::string line, header;
        std::getline(in, header);
        while (header[0] == '#') std::getline(in, header);
        // Replace the Tds value of the first data row by 1e200.
        std::vector<std::string> names;
        std::istringstream h(header);
        for (std::string c; std::getline(h, c, ',');) names.push_back(c);
        const auto tds = static_cast<std::size_t>(std::find(names.begin(), names.end(), "Tds") - names.begin());
        REQUIRE(tds < names.size());
        const auto start = data.find(header) + header.size() + 1;
        const auto end = data.find('\n', start);
        std::vector<std::string> cells;
        std::istringstream row(data.substr(start, end - start));
        for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
        cells[tds] = "1e200";
        std::string joined;
        for (std::size_t i = 0; i < cells.size(); ++i) joined += (i ? "," : "") + cells[i];
        data.replace(start, end - start, joined);
    }
    const fs::path huge = tmp.write("huge.csv", data);
    expect_refusal(run_tvid({"validate", kCleanConfig, "--set", "data.file=" + huge.string(), "--params", truth}),
                   {"huge.csv", "column Tds", "overflows the cost"});
    // 1e-400 underflows to 0: a number, not "not finite".
    const RunResult tiny = run_tvid({"validate", kCleanConfig, "--set", "parameters.d_tm.init=1e-400", "--params", truth});
    CHECK_FALSE(contains(tiny.err, "not a finite number"));
    // CR-only line ends (classic Mac OS) in the experiment and the recording: read as lines,
    // not as one long comment line that made the experiment look empty.
    std::string cr_data = read_text(kCleanData);
    std::replace(cr_data.begin(), cr_data.end(), '\n', '\r');
    std::string cr_config = read_text(kCleanConfig);
    std::replace(cr_config.begin(), cr_config.end(), '\n', '\r');
    const RunResult cr = run_tvid({"validate", tmp.write("cr.yaml", cr_config).string(), "--set",
                                   "data.file=" + tmp.write("cr.csv", cr_data).string(), "--params", truth});
    INFO(cr.err);
    CHECK(cr.exit_code == 0);
    // A second YAML document.
    const fs::path two = tmp.write("two.yaml", read_text(kCleanConfig) + "---\ntvid: 1\n");
    expect_refusal(run_tvid({"validate", two.string(), "--params", truth}), {"two.yaml", "second YAML document"});
    // A name that climbs out of results/.
    expect_refusal(run_tvid({"validate", kCleanConfig, "--set", "name=../../x", "--params", truth}), {"name", "plain name"});
    // A UTF-8 byte-order mark at the start of a recording list.
    const fs::path list = tmp.write("list.txt", "\xEF\xBB\xBF" + kCleanData + "\n");
    const RunResult bom = run_tvid({"batch", kCleanConfig, "--data-list", list.string(), "-o", (tmp.path() / "b").string(),
                                    "--set", "estimation.pso.start=latin_hypercube", "--set", "estimation.pso.particles=8",
                                    "--set", "estimation.pso.iterations=1", "--threads", "1", "--quiet"});
    INFO(bom.err);
    CHECK(bom.exit_code == 0);
    // --seed -1 is not 2^64 - 1, and -o "" is not report.dir.
    std::vector<std::string> seed = quick_fit(tmp.path() / "s");
    seed.insert(seed.end(), {"--seed", "-1"});
    CHECK(run_tvid(seed).exit_code == 2);
    std::vector<std::string> empty_out = quick_fit("");
    CHECK(run_tvid(empty_out).exit_code == 2);
    // validate --params: a negative inverse inertia, and a value outside the bounds.
    expect_refusal(run_tvid({"validate", kCleanConfig, "--params", tmp.write("neg.json", R"({"rho1": -1})").string()}),
                   {"rho1", "must be positive"});
    expect_refusal(run_tvid({"validate", kCleanConfig, "--params", tmp.write("far.json", R"({"rho1": 1e9})").string()}),
                   {"rho1", "outside the bounds"});
    // An NLopt algorithm that overruns its budget is held to it.
    const fs::path direct = tmp.path() / "direct";
    const RunResult d = run_tvid({"fit", kCleanConfig, "-o", direct.string(), "--optimizer", "nlopt", "--set",
                                  "estimation.nlopt.algorithm=GN_ORIG_DIRECT", "--set",
                                  "estimation.nlopt.max_evaluations=20", "--threads", "1", "--quiet"});
    INFO(d.err);
    REQUIRE(d.exit_code != 2);
    const json s = json::parse(read_text(direct / "summary.json"));
    CHECK(s["optimizer"]["evaluations"].get<long long>() <= 20);
}

}  // namespace TVID_UNITY_ID
