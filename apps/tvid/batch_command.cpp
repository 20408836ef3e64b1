// `tvid batch EXP.yaml`: the experiment fitted to many recordings and/or engine cycles,
// jobs in parallel, one row per job in batch.csv and the spread in batch_summary.json.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "terminal.hpp"
#include "tvid/report/report_directory.hpp"
#include "tvid/experiment/overrides.hpp"
#include "tvid/batch/batch_identity.hpp"
#include "tvid/batch/batch_plan.hpp"
#include "tvid/batch/batch_runner.hpp"
#include "tvid/batch/batch_stability.hpp"
#include "tvid/batch/cross_matrix.hpp"
#include "tvid/batch/batch_summary.hpp"
#include "tvid/batch/batch_table.hpp"
#include "tvid/batch/distributed_batch.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/io/output_directory.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/parallel/on_every_process.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/stop_request.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid::cli {


namespace {


// The experiment as the batch's jobs see it: as written, or else with the first job's
// overrides (an experiment whose data.file is only a placeholder for the recordings).
Experiment load_batch_experiment(const BatchSettings& settings, const std::vector<BatchJob>& jobs) {
    try {
        return load_experiment(settings.experiment, settings.overrides);
    } catch (const InputError&) {
        if (jobs.empty() || jobs.front().overrides.empty()) throw;
        std::vector<Override> first = settings.overrides;
        first.insert(first.end(), jobs.front().overrides.begin(), jobs.front().overrides.end());
        try {
            return load_experiment(settings.experiment, first);
        } catch (const InputError&) {
        }
        throw;
    }
}

// The default output directory: the report directory followed by "-batch".
std::filesystem::path batch_directory(const Experiment& ex, const std::string& output_dir) {
    if (!output_dir.empty()) return output_dir;
    std::string dir = report_directory(ex, "").string();
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    return dir + "-batch";
}

std::string header_line(const BatchColumns& columns) { return batch_csv_line(columns.header()); }

// The rows of an earlier run of this batch that --resume keeps, by job. Refuses a file
// written for other columns or other jobs.
std::map<std::size_t, BatchRow> resumed_rows(const std::filesystem::path& file, const BatchColumns& columns,
                                             const std::vector<BatchJob>& jobs, bool quiet) {
    std::map<std::size_t, BatchRow> kept;
    const std::optional<BatchFile> existing = read_batch_file(file);
    if (!existing) return kept;
    if (existing->header != columns.header())
        throw InputError(file.string(), 1, "", "the columns differ from this batch's (another experiment or --set?): "
                                               "use another -o, or --force to start over");
    std::map<std::string, std::size_t> job_of;
    for (std::size_t j = 0; j < jobs.size(); ++j) job_of[jobs[j].id] = j;
    std::size_t redo = existing->incomplete_rows;
    for (const BatchRow& row : existing->rows) {
        const auto job = job_of.find(row[0]);
        if (job == job_of.end())
            throw InputError(file.string(), 0, "", "job '" + row[0] + "' is not part of this batch (other --data or "
                                                   "--cycles?): use another -o, or --force to start over");
        if (is_batch_status(row[1]) && !kept.count(job->second))
            kept.emplace(job->second, row);
        else
            ++redo;
    }
    if (!quiet)
        std::cerr << "tvid batch: resuming " << file.string() << ": " << kept.size() << " of " << jobs.size()
                  << " jobs done" << (redo ? ", " + std::to_string(redo) + " incomplete row(s) dropped" : "") << '\n';
    return kept;
}

std::string cell_or_dash(const std::string& cell) { return cell.empty() ? "-" : cell; }

std::string short_number(const std::string& cell, const char* format) {
    const double v = batch_cell_value(cell);
    if (!std::isfinite(v)) return cell_or_dash(cell);
    char buf[32];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

// `[k/N] id status cost C Q q % wall s` (bad input and failures: the message instead).
std::string progress_line(std::size_t done, std::size_t total, const BatchColumns& columns, const BatchRow& row,
                          bool single_output) {
    std::string line = "[" + std::to_string(done) + "/" + std::to_string(total) + "] " + row[0] + "  " + row[1];
    if (row[1] == kBatchOk) {
        line += "  cost " + short_number(row[columns.index("cost")], "%.6g");
        if (single_output) {
            line += "  Q " + short_number(row[columns.index("q_estimation")], "%.2f") + " %";
            if (!row[columns.index("q_validation")].empty())
                line += " (validation " + short_number(row[columns.index("q_validation")], "%.2f") + " %)";
        }
    } else {
        line += "  " + row[2];
    }
    return line + "  " + short_number(row[columns.index("wall_seconds")], "%.1f") + " s";
}

std::string spread_line(const ColumnSpread& s) {
    char buf[160];
    if (s.count == 0) {
        std::snprintf(buf, sizeof buf, "  %-26s (no successful job)\n", s.column.c_str());
    } else if (s.count == 1) {
        std::snprintf(buf, sizeof buf, "  %-26s %-14.8g                   (1 job)\n", s.column.c_str(), s.mean);
    } else {
        std::snprintf(buf, sizeof buf, "  %-26s %-14.8g ± %-14.4g  [%.8g, %.8g]\n", s.column.c_str(), s.mean,
                      s.std_dev, s.min, s.max);
    }
    return buf;
}

std::string batch_summary_text(const BatchSummary& s, const std::string& name, const std::filesystem::path& dir) {
    char head[256];
    std::snprintf(head, sizeof head,
                  "tvid batch %s: %zu jobs (%zu ok, %zu failed, %zu bad input), %zu run in %.2f s on %d thread%s",
                  name.c_str(), s.jobs, s.ok, s.failed, s.bad_input, s.run, s.wall_seconds, s.threads,
                  s.threads == 1 ? "" : "s");
    std::string out = head;
    if (s.processes > 1) out += " × " + std::to_string(s.processes) + " processes";
    if (std::isfinite(s.jobs_per_second)) {
        char rate[64];
        std::snprintf(rate, sizeof rate, ", %.3g jobs/s", s.jobs_per_second);
        out += rate;
    }
    out += "\n  over the ok jobs:          mean             std               [min, max]\n";
    for (const ColumnSpread& p : s.parameters) out += spread_line(p);
    for (const ColumnSpread& m : s.metrics) out += spread_line(m);
    return out + "  batch: " + (dir / "batch.csv").string() + "\n";
}

// The cross-cycle matrix in two lines: own fit against the fit on the others' data.
std::string cross_summary_text(const nlohmann::json& cross, const std::filesystem::path& dir) {
    const auto percent = [](const nlohmann::json& v) {
        if (!v.is_number()) return std::string("-");
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.2f %%", v.get<double>());
        return std::string(buf);
    };
    std::string out = "  cross-validation over " + std::to_string(cross["jobs"].size()) +
                      " jobs: fit on own data " + percent(cross["diagonal_mean_fit_percent"]) +
                      " (mean), on the others' " + percent(cross["off_diagonal_median_fit_percent"]) +
                      " (median), " + percent(cross["off_diagonal_mean_fit_percent"]) + " (mean), " +
                      percent(cross["off_diagonal_min_fit_percent"]) + " (worst";
    const std::string worst = cross["off_diagonal_min_cell"];
    out += worst.empty() ? ")" : ": " + worst + ")";
    if (cross["failed_cells"].get<std::size_t>() > 0)
        out += ", " + std::to_string(cross["failed_cells"].get<std::size_t>()) + " simulation(s) failed";
    return out + "\n  matrix: " + (dir / "matrix.csv").string() + "\n";
}

std::string outliers_text(const BatchStability& stability) {
    if (stability.outliers.empty()) return "  outliers: none (robust z-score, |z| > 3.5)\n";
    std::string out;
    for (const OutlierJob& o : stability.outliers) out += "  outlier: " + o.id + ": " + o.reason + "\n";
    return out;
}

// The batch as the root sets it up: jobs, columns, the output directory with the rows
// kept by --resume, and the jobs still to run.
struct PreparedBatch {
    std::vector<BatchJob> jobs;
    std::string name;                       ///< the experiment's
    std::vector<std::string> outputs;
    std::vector<std::string> units;         ///< per free parameter
    BatchColumns columns;
    std::filesystem::path dir, table, summary_file;
    std::map<std::size_t, BatchRow> rows;   ///< kept by --resume
    std::vector<std::size_t> pending;
    std::unique_ptr<BatchAppender> appender;  ///< batch.csv, open for the rows to come
    OutputDirectoryLock lock;                 ///< this run's claim on the batch directory
};

std::unique_ptr<PreparedBatch> prepare_batch(const BatchCommand& cmd, const BatchSettings& settings) {
    // The jobs: recordings × cycles, each a set of overrides on the experiment.
    BatchRequest request;
    for (const std::string& pattern : cmd.data_globs) {
        const auto files = expand_recording_glob(pattern);
        request.recordings.insert(request.recordings.end(), files.begin(), files.end());
    }
    if (!cmd.data_list.empty()) {
        const auto files = read_recording_list(cmd.data_list);
        request.recordings.insert(request.recordings.end(), files.begin(), files.end());
    }
    request.recordings_option = cmd.data_globs.empty() ? "--data-list" : cmd.data_list.empty() ? "--data" : "--data, --data-list";
    if (!cmd.cycles.empty()) request.cycles = parse_cycle_list(cmd.cycles);
    request.validation = !cmd.no_validation;
    std::vector<BatchJob> jobs = plan_batch_jobs(request);

    const Experiment ex = load_batch_experiment(settings, jobs);
    check_batch_of_one_recording(ex, request);
    const IdentificationProblem problem(ex);
    if (problem.dimension() == 0)
        throw InputError(ex.file.string(), 0, "parameters", "every parameter is fixed: there is nothing to identify");
    if (!request.cycles.empty() && request.recordings.empty())
        check_cycles_in_recording(ex, request.cycles, request.validation);
    std::vector<std::string> outputs;
    for (const ChannelBinding& o : ex.outputs) outputs.push_back(o.model_name);
    const BatchColumns columns(problem.free_names(), outputs);
    if (const std::string name = columns.repeated_column(); !name.empty())
        throw InputError(ex.file.string(), 0, "parameters." + name,
                         "is named like a column batch.csv has already (id, status, message, cost, the metrics, "
                         "evaluations, wall_seconds): rename the parameter to fit it in a batch");

    // The output directory: a fresh batch.csv, or the rows of an interrupted one (--resume).
    const std::filesystem::path dir = batch_directory(ex, cmd.output_dir);
    const std::filesystem::path table = dir / "batch.csv", summary_file = dir / "batch_summary.json";
    if (!cmd.resume && !cmd.force && std::filesystem::exists(table))
        throw InputError(table.string(), 0, "",
                         "a batch is already here: use --resume to continue it or --force to start over");
    // The recordings' digests: what --resume compares, and (read through the input reader)
    // the files this run reads, which no batch file may replace.
    std::vector<std::string> digests = request.recordings.empty() ? std::vector<std::string>{ex.data.content_sha256()}
                                                                  : recording_digests(request.recordings);
    const std::vector<std::string> batch_files = {"batch.csv", "batch_summary.json", "matrix.csv", "matrix_long.csv",
                                                  "parameter_stability.csv"};
    std::vector<std::string> checked = batch_files;
    checked.push_back(batch_identity_file(dir).filename().string());
    OutputDirectoryLock lock = prepare_output_directory(dir, "batch directory", checked);
    // A batch's files are replaced or removed only when a batch of tvid's wrote them: its
    // record (.tvid-batch.json) is beside them. Else they are a user's (or another
    // program's), kept unless --force. prepare_output_directory has refused a FIFO first.
    if (!cmd.force && !has_written_file_mark(batch_identity_file(dir), {WrittenFileMark::Form::json_member, "tvid_batch", ""}))
        for (const std::string& name : batch_files)
            if (std::error_code ec; std::filesystem::exists(dir / name, ec))
                throw InputError((dir / name).string(), 0, "",
                                 "exists, and no record of a batch of tvid's (" + batch_identity_file(dir).filename().string() +
                                     ") is beside it: tvid did not write it; use --force to replace it, or -o for another directory");
    // --resume continues only the batch that began here (same experiment, --set, --seed,
    // --no-validation, recordings and their content).
    const BatchIdentity identity =
        batch_identity(settings, request.recordings, ex.config_sha256, std::move(digests), request.validation);
    if (cmd.resume && std::filesystem::exists(table)) require_same_batch(dir, identity);
    std::map<std::size_t, BatchRow> rows = cmd.resume ? resumed_rows(table, columns, jobs, cmd.common.quiet)
                                                      : std::map<std::size_t, BatchRow>{};
    write_batch_identity(dir, identity);
    remove_output_file(dir, summary_file.filename().string());  // its presence marks a complete batch
    for (const char* stale : {"matrix.csv", "matrix_long.csv", "parameter_stability.csv"})
        remove_output_file(dir, stale);  // written again at the end, if asked for
    std::vector<std::string> units;
    const std::vector<std::string> model_units = parameter_units(ex.network);
    for (std::size_t j : problem.free_indices()) units.push_back(j < model_units.size() ? model_units[j] : "");
    std::string kept = header_line(columns);
    for (const auto& [job, row] : rows) kept += batch_csv_line(row);

    std::vector<std::size_t> pending;
    for (std::size_t j = 0; j < jobs.size(); ++j)
        if (!rows.count(j)) pending.push_back(j);
    // Opened here, so that a file that cannot be written stops every process before any job.
    auto appender = std::make_unique<BatchAppender>(table, kept);
    return std::make_unique<PreparedBatch>(PreparedBatch{std::move(jobs), ex.name, outputs, std::move(units), columns,
                                                         dir, table, summary_file, std::move(rows), std::move(pending),
                                                         std::move(appender), std::move(lock)});
}

/// After the jobs: the cross matrix if asked for, the parameters' stability, the summary
/// (batch_summary.json last: it marks the batch complete), the terminal's report, and the
/// exit status (--strict: a verdict with an error fails the batch).
int finish_batch(const BatchCommand& cmd, const BatchSettings& settings, PreparedBatch& batch,
                 const std::vector<BatchRow>& ordered, int threads, int processes,
                 std::chrono::steady_clock::time_point start) {
    using clock = std::chrono::steady_clock;
    const std::vector<BatchJob>& jobs = batch.jobs;
    const BatchColumns& columns = batch.columns;
    const std::filesystem::path& dir = batch.dir;
    const double seconds = std::chrono::duration<double>(clock::now() - start).count();  // the fits
    // --cross: every job's parameters on every job's estimation windows (on the root alone).
    std::vector<BatchRow> by_job(jobs.size(), columns.row("", "", ""));
    for (const auto& [job, row] : batch.rows) by_job[job] = row;
    std::optional<CrossMatrix> cross;
    if (cmd.cross) {
        if (!cmd.common.quiet)
            std::cerr << "tvid batch: cross-validating the ok jobs on each other's data\n";
        cross = compute_cross_matrix(settings, jobs, by_job, columns, cmd.common.threads);
        if (!cross->complete || stop_requested()) {
            if (!cmd.common.quiet)
                std::cerr << "tvid batch: interrupted during the cross-validation; batch.csv is complete: run "
                             "again with --resume to compute the matrix\n";
            return kExitInterrupted;
        }
        write_output_file(dir, "matrix.csv", cross_matrix_csv(*cross));
        write_output_file(dir, "matrix_long.csv", cross_matrix_long_csv(*cross));
    }
    const BatchStability stability = batch_stability(columns, ordered, batch.units, cross ? &*cross : nullptr);
    write_output_file(dir, "parameter_stability.csv", parameter_stability_csv(stability));

    const double cross_seconds = std::chrono::duration<double>(clock::now() - start).count() - seconds;
    BatchSummary summary = summarize_batch(columns, ordered, batch.pending.size(), seconds, threads);
    summary.processes = processes;
    const BatchRunContext context{TVID_VERSION, cmd.common.command_line, cmd.common.experiment, batch.name,
                                  dir.string()};
    nlohmann::json json = batch_summary_json(summary, context);
    json["parameter_stability"] = parameter_stability_json(stability);
    json["outliers"] = outliers_json(stability);
    json["cross"] = cross ? cross_matrix_json(*cross) : nlohmann::json(nullptr);
    if (cross) json["cross"]["wall_time_s"] = cross_seconds;
    write_output_file(dir, batch.summary_file.filename().string(), json_text(json) + "\n");

    if (cmd.common.json) {
        std::cout << json_with_report(json, dir) << std::endl;
    } else if (!cmd.common.quiet) {
        std::cout << batch_summary_text(summary, batch.name, dir);
        if (cross) std::cout << cross_summary_text(json["cross"], dir);
        std::cout << outliers_text(stability) << std::flush;
    }
    if (summary.failed + summary.bad_input > 0) return kExitNotSucceeded;
    if (cmd.strict) {
        // A job whose verdict has an error (batch.csv's verdict column says so).
        const std::size_t verdict = columns.index("verdict");
        int poor = 0;
        for (const BatchRow& row : ordered) poor += row[verdict].find("error") != std::string::npos ? 1 : 0;
        if (poor > 0) {
            std::cerr << "tvid: --strict: " << poor << " job" << (poor == 1 ? "'s" : "s'")
                      << " verdict has an error (batch.csv, column verdict)\n";
            return kExitNotSucceeded;
        }
    }
    return kExitDone;
}

}  // namespace

int run_batch_command(const BatchCommand& cmd) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    ProcessGroup alone;
    ProcessGroup& group = cmd.processes ? *cmd.processes : alone;
    const BatchSettings settings{cmd.common.experiment, parse_overrides(cmd.common.overrides), cmd.seed};

    // Ctrl-C / SIGTERM from here on: no new job starts, running fits stop at their best
    // point and are left for --resume.
    install_stop_signal_handlers();
    // The root sets the batch up; under mpirun the others then take its plan and run jobs for it.
    const std::unique_ptr<PreparedBatch> prepared = on_every_process(group, [&] {
        return group.is_root() ? prepare_batch(cmd, settings) : std::unique_ptr<PreparedBatch>();
    });
    if (group.size() > 1) {
        std::string plan = group.is_root() ? encode_batch_plan({prepared->jobs, prepared->columns.parameters(),
                                                                prepared->outputs})
                                           : std::string();
        group.broadcast(plan);
        if (!group.is_root()) {
            const BatchPlan p = decode_batch_plan(plan);
            serve_batch_jobs(group, settings, p.jobs, BatchColumns(p.parameters, p.outputs), cmd.common.threads);
            return kExitDone;
        }
    }
    const std::vector<BatchJob>& jobs = prepared->jobs;
    const BatchColumns& columns = prepared->columns;
    const std::vector<std::string>& outputs = prepared->outputs;
    std::map<std::size_t, BatchRow>& rows = prepared->rows;
    const std::vector<std::size_t>& pending = prepared->pending;
    const int threads = group.size() > 1
                            ? resolve_thread_count(cmd.common.threads)
                            : std::max(1, std::min(resolve_thread_count(cmd.common.threads),
                                                   static_cast<int>(std::max<std::size_t>(1, pending.size()))));

    // Every finished row is on disk before the next one is reported; batch.csv is
    // rewritten atomically each time, so a kill never leaves it torn.
    std::size_t done = 0;
    const BatchJobFinished finished = [&](std::size_t job, const BatchRow& row) {
        if (row[1] == kBatchInterrupted) return;  // cut short: --resume runs it again
        prepared->appender->append(row);
        rows[job] = row;
        ++done;
        if (!cmd.common.quiet)
            std::cerr << progress_line(done, pending.size(), columns, row, outputs.size() == 1) << '\n';
    };
    if (group.size() > 1)
        run_batch_jobs_on_group(group, settings, jobs, pending, columns, threads, finished);
    else
        run_batch_jobs(settings, jobs, pending, columns, threads, finished);

    // The final table in job order, then the summary last.
    std::vector<BatchRow> ordered;
    std::string text = header_line(columns);
    for (const auto& [job, row] : rows) {
        ordered.push_back(row);
        text += batch_csv_line(row);
    }
    prepared->appender->rewrite(text);
    if (stop_requested()) {
        // Ctrl-C or SIGTERM: the finished jobs are in batch.csv; no summary marks it complete.
        if (!cmd.common.quiet)
            std::cerr << "tvid batch: interrupted after " << done << " of " << pending.size()
                      << " jobs; batch.csv holds the finished ones: run again with --resume to complete it\n";
        return kExitInterrupted;
    }
    return finish_batch(cmd, settings, *prepared, ordered, threads, group.size(), start);
}

CommandRow batch_command_row() {
    return {"batch", "fit the experiment to many recordings and/or cycles, one row per job", true,
            [](CLI::App& sub) -> CommandRunner {
                auto batch = std::make_shared<BatchCommand>();
                add_common(sub, batch->common);
                sub.add_option("-o,--output-dir,--output", batch->output_dir,
                               "output directory (default: the report directory + -batch)")
                    ->check(kNonEmptyPath);
                sub.add_option("--seed", batch->seed, "random seed of the optimizer, the same for every job")->check(kSeed);
                sub.add_option("--data", batch->data_globs, "recordings: files, or globs such as 'recordings/*.csv'");
                sub.add_option("--data-list", batch->data_list, "file with one recording per line (relative to it)");
                sub.add_option("--cycles", batch->cycles, "fit each cycle on its own: 3-9 or 3,5,7");
                sub.add_flag("--no-validation", batch->no_validation, "no validation (else the next cycle validates)");
                auto* resume =
                    sub.add_flag("--resume", batch->resume, "continue an interrupted batch: skip the jobs in batch.csv");
                sub.add_flag("--force", batch->force, "replace an existing batch.csv")->excludes(resume);
                sub.add_flag("--strict", batch->strict, "exit 1 when a job's verdict has an error (for CI)");
                sub.add_flag("--cross", batch->cross, "validate each job's parameters on every job's data (matrix.csv)");
                return [batch](const CommandContext& context) {
                    batch->common.command_line = context.command_line;
                    batch->processes = context.processes;
                    return run_batch_command(*batch);
                };
            }};
}

}  // namespace tvid::cli
