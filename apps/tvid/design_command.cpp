// `tvid design EXP.yaml [--evaluate]`: what a record would determine before it is measured.
// A multisine designed for the criterion (unless --evaluate), a given input (a CSV column)
// and a multisine, a chirp and a PRBS of the design's band, RMS and limits, each with the
// predicted standard errors and correlations of the free parameters from the Fisher
// information with exact sensitivities (design/).

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <limits>
#include <memory>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "tvid/design/design_experiment.hpp"
#include "tvid/design/design_spec.hpp"
#include "tvid/design/excitation_signals.hpp"
#include "tvid/design/multisine_design.hpp"
#include "tvid/design/parameter_draws.hpp"
#include "tvid/design/predicted_uncertainty.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/overrides.hpp"
#include "tvid/io/csv_table.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/io/output_directory.hpp"
#include "tvid/report/design_report.hpp"
#include "tvid/report/parameter_file.hpp"
#include "tvid/report/report_directory.hpp"
#include "tvid/estimation/evaluator_options.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/parallel_region.hpp"
#include "tvid/util/text.hpp"
#include "terminal.hpp"

namespace tvid::cli {

namespace {

// The input read from a CSV: its time column (the experiment's name) and the column given.
DesignCandidate given_input(const Experiment& ex, const DesignSpec& spec, const std::string& file,
                            const std::string& column_name) {
    const CsvTable table = CsvTable::read(file);
    const std::string column = column_name.empty() ? ex.inputs[spec.input].column : column_name;
    for (const std::string& name : {ex.time_column, column})
        if (!table.has_column(name))
            throw InputError(file, table.header_line(), "column " + name,
                             "missing: the input file needs the experiment's time column (" + ex.time_column +
                                 ") and the input's (" + column + ", or name it with --column)");
    table.require_strictly_increasing(ex.time_column);
    if (table.rows() < 3) throw InputError(file, table.header_line(), "column " + column, "fewer than 3 samples");
    DesignCandidate c;
    c.name = "given";
    c.source = file + ", column " + column;
    c.time = table.column(ex.time_column);
    c.value = table.column(column);
    return c;
}

// A generated reference input on the design's grid, scaled to its RMS within its limits.
DesignCandidate reference_input(const DesignSpec& spec, const std::string& name, const std::vector<double>& shape,
                                const std::vector<double>& time, const std::string& how) {
    double reachable = 0.0;
    std::optional<std::vector<double>> v =
        scaled_excitation(shape, spec.base, spec.rms, spec.limit_low, spec.limit_high, &reachable);
    if (!v)
        throw InputError(spec.rms_where.file, spec.rms_where.line, spec.rms_where.key,
                         number_text(spec.rms) + " is more than the limits [" + number_text(spec.limit_low) + ", " +
                             number_text(spec.limit_high) + "] allow about base " + number_text(spec.base) + " for the " +
                             name + " (at most " + number_text(reachable) + ")");
    DesignCandidate c;
    c.name = name;
    c.source = how;
    c.file = name + ".csv";
    c.time = time;
    c.value = std::move(*v);
    return c;
}

std::vector<DesignCandidate> candidates_of(const Experiment& ex, const DesignSpec& spec, const DesignCommand& cmd) {
    std::vector<DesignCandidate> out;
    if (!cmd.evaluate) {
        DesignCandidate designed;
        designed.name = "designed";
        designed.file = "designed.csv";
        out.push_back(std::move(designed));
    }
    if (!cmd.input_file.empty()) out.push_back(given_input(ex, spec, cmd.input_file, cmd.column));
    const std::vector<double> time = excitation_time_grid(spec.samples(), spec.sample_rate);
    const std::string band = number_text(spec.band_low) + " to " + number_text(spec.band_high) + " Hz";
    out.push_back(reference_input(spec, "multisine", schroeder_multisine_shape(time, spec.sample_rate, spec.band_low, spec.band_high),
                                  time, "Schroeder-phased multisine, flat amplitudes on the record's grid from " + band));
    out.push_back(reference_input(spec, "chirp", chirp_shape(time, spec.band_low, spec.band_high), time,
                                  "linear chirp from " + band));
    out.push_back(reference_input(spec, "prbs", prbs_shape(time.size(), spec.sample_rate, spec.band_high), time,
                                  "maximum-length PRBS clocked for a flat spectrum to " + number_text(spec.band_high) + " Hz"));
    return out;
}

}  // namespace

int run_design_command(const DesignCommand& cmd) {
    const std::vector<Override> overrides = parse_overrides(cmd.common.overrides);
    const Experiment ex = load_experiment(cmd.common.experiment, overrides);
    const DesignSpec spec = read_design_spec(ex, overrides);
    const std::vector<double> params =
        cmd.params_file.empty() ? initial_parameters(ex) : read_parameter_file(cmd.params_file, ex);
    const std::vector<std::vector<double>> sets = design_parameter_sets(ex, spec, params);
    std::vector<DesignCandidate> candidates = candidates_of(ex, spec, cmd);
    const std::filesystem::path dir =
        cmd.output_dir.empty() ? report_directory(ex, "") / "design" : std::filesystem::path(cmd.output_dir);
    const OutputDirectoryLock lock =
        prepare_output_directory(dir, "design directory", design_report_files(candidates), "design.json", cmd.force);

    const auto start = std::chrono::steady_clock::now();
    // The design's search: one simulation at a time, each the whole record with its sensitivities.
    MultisineDesign search;
    if (!cmd.evaluate) {
        if (!cmd.common.quiet && !cmd.common.json)
            std::cout << "designing a multisine of " << spec.bands << " bands for " << to_string(spec.criterion)
                      << (spec.draws > 0 ? " over the nominal values and " + std::to_string(spec.draws) + " draws" : "")
                      << ", " << spec.evaluations << " trial inputs at most\n" << std::flush;
        search = design_multisine(ex, spec, sets);
        DesignCandidate& designed = candidates.front();
        designed.time = excitation_time_grid(spec.samples(), spec.sample_rate);
        designed.value = search.value;
        designed.search = &search;
        designed.source = "multisine of " + std::to_string(spec.bands) + " log-spaced bands from " +
                          number_text(spec.band_low) + " to " + number_text(spec.band_high) + " Hz, the bands' powers for " +
                          to_string(spec.criterion) + " (" + std::to_string(search.evaluations) + " trial inputs)";
        if (designed.value.empty()) {
            std::cerr << "tvid: no multisine of the design simulated with every parameter determined; nothing written\n";
            return kExitNotSucceeded;
        }
    }

    // One candidate per task: each its own experiment, problem and workspace.
    const int threads =
        std::max(1, std::min(resolve_thread_count(cmd.common.threads), static_cast<int>(candidates.size())));
    const auto n = static_cast<long long>(candidates.size());
    FirstException errors;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (long long i = 0; i < n; ++i) {
        errors.run([&] {
            DesignCandidate& c = candidates[static_cast<std::size_t>(i)];
            const Experiment record = design_experiment(ex, spec, c.time, c.value);
            std::vector<PredictedUncertainty> predictions;
            for (const std::vector<double>& set : sets) predictions.push_back(predict_uncertainty(record, set, spec.noise));
            c.prediction = predictions.front();
            for (std::size_t d = 1; d < predictions.size(); ++d)
                c.draw_criteria.push_back(predictions[d].simulated ? predictions[d].criterion(spec.criterion)
                                                                   : std::numeric_limits<double>::infinity());
            c.robust_criterion = averaged_criterion(predictions, spec.criterion);
        });
    }
    errors.rethrow();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const DesignRunInfo run{TVID_VERSION, cmd.common.command_line,
                            cmd.params_file.empty() ? std::string("init") : cmd.params_file, threads, seconds};
    write_design_report(dir, ex, spec, sets, candidates, run);
    if (cmd.common.json)
        std::cout << json_text(design_json(ex, spec, sets, candidates, run)) << std::endl;
    else if (!cmd.common.quiet)
        std::cout << design_summary_text(spec, candidates, dir) << std::flush;
    const bool all = std::all_of(candidates.begin(), candidates.end(),
                                 [](const DesignCandidate& c) { return c.prediction.simulated; });
    return all ? kExitDone : kExitNotSucceeded;
}

CommandRow design_command_row() {
    return {"design", "predict the standard errors that an excitation would give before it is measured (design:)", false,
            [](CLI::App& sub) -> CommandRunner {
                auto design = std::make_shared<DesignCommand>();
                add_common(sub, design->common);
                sub.add_flag("--evaluate", design->evaluate,
                             "only predict the standard errors of a given input (--input) and of a multisine, a chirp "
                             "and a PRBS of the design's band, RMS and limits; without it, a multisine is designed "
                             "for the criterion first");
                sub.add_option("--input", design->input_file,
                               "a CSV with the experiment's time column and the designed input's column to evaluate");
                sub.add_option("--column", design->column, "the input's column in --input (default: the experiment's)");
                sub.add_option("--params", design->params_file,
                               "the nominal parameters, a parameter file (default: the experiment's init values)");
                sub.add_option("-o,--output-dir,--output", design->output_dir,
                               "output directory (default: report.dir or results/NAME, then /design)")
                    ->check(kNonEmptyPath);
                sub.add_flag("--force", design->force, "replace files in the output directory that tvid did not write");
                return [design](const CommandContext& context) {
                    design->common.command_line = context.command_line;
                    return run_design_command(*design);
                };
            }};
}

}  // namespace tvid::cli
